#include "search/starts/start.hpp"

#include "search/evolution/constant_fit.hpp"
#include "search/evolution/rewrites.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/fit/fixed_form.hpp"

namespace shaderfit::search_detail {

std::vector<StartFormula> parse_start_formulas(const SearchOptions& options,
                                               const SearchProblem& problem) {
  std::vector<StartFormula> out;
  for (std::size_t k = 0; k < options.start.size(); ++k) {
    ParseOptions po;
    po.variables = problem.input_names;
    po.source = "SearchOptions::start";
    po.line = static_cast<int>(k + 1);
    StartFormula s;
    s.written = parse_formula(options.start[k], po);
    po.literals_as_parameters = true;
    s.free = parse_formula(options.start[k], po);
    out.push_back(std::move(s));
  }
  return out;
}

Expression refit_for_loss(Expression e, const SearchOptions& options,
                          const SearchProblem& problem) {
  if (e.parameters.empty()) return e;
  FixedFormProblem fp;
  fp.formula = e;
  FitBlock block;
  block.label = "start";
  block.columns = problem.inputs;  // e's variables are the inputs, in order
  block.target = problem.target;
  block.weights = problem.weights;
  FixedFormOptions fo;
  fo.threads = 1;
  switch (options.loss) {
    case Loss::MaxAbs:
    case Loss::MaxRel:
      fo.loss = Loss::MaxAbs;
      block.weights = minimax_weights(options.loss, problem.target, problem.weights);
      break;
    case Loss::Relative:
      fo.loss = Loss::Mse;
      block.weights.resize(block.target.size(), 1.0);
      for (std::size_t i = 0; i < block.target.size(); ++i)
        block.weights[i] /= block.target[i] * block.target[i];
      break;
    case Loss::Log: fo.loss = Loss::Log; break;
    default: fo.loss = Loss::Mse; break;
  }
  fp.blocks.push_back(std::move(block));
  FixedFormSummary s;
  try {
    solve_fixed_form(fo, fp, &s);
  } catch (const Error&) {
    return e;  // e.g. parameters the data does not determine: the written values stay
  }
  if (!s.blocks.empty() && s.blocks[0].ok) e.parameter_values = s.blocks[0].parameters;
  return e;
}

StartFormula start_over_indexed_inputs(const std::string& text,
                                       const std::vector<std::string>& names,
                                       const std::string& source, SearchPhase origin) {
  ParseOptions po;
  for (std::size_t k = 0; k < names.size(); ++k) po.variables.push_back("x" + std::to_string(k));
  po.source = source;
  StartFormula s;
  s.written = parse_formula(text, po);
  po.literals_as_parameters = true;
  s.free = parse_formula(text, po);
  s.written.variables = s.free.variables = names;
  s.origin = origin;
  return s;
}

std::vector<Expression> offer_start_formulas(SearchContext& ctx,
                                             const std::vector<StartFormula>& starts) {
  std::vector<Expression> seeds;
  for (const StartFormula& s : starts) {
    Expression fitted = s.fitted ? s.free : refit_for_loss(s.free, ctx.options, ctx.problem);
    // A fitted start with its constants free, so that the front's polish may refine them.
    std::vector<const Expression*> forms = {s.fitted ? &s.free : &s.written};
    if (!s.fitted && !fitted.parameters.empty()) forms.push_back(&fitted);
    for (const Expression* e : forms) {
      ctx.offer(*e, loss_value(ctx.options.loss, ctx.score(*e)), s.origin);
      ctx.candidates.fetch_add(1, std::memory_order_relaxed);
    }
    seeds.push_back(std::move(fitted));
  }
  return seeds;
}

std::optional<StartFormula> reference_start(const SearchProblem& problem) {
  reference::ProgramFormula f = reference_formula(problem);
  if (!f.formula) return std::nullopt;
  StartFormula s;
  s.written = std::move(*f.formula);
  s.free = with_shared_literal_parameters(s.written);
  s.origin = SearchPhase::Reference;
  return s;
}

}  // namespace shaderfit::search_detail
