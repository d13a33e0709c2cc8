#include "search/front/symmetry_front.hpp"

#include <map>
#include <string>
#include <utility>

#include "search/front/float32_check.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit::search_detail {

namespace {

SearchOptions scoring_options(SearchOptions o) {
  o.on_new_member = nullptr;
  o.on_progress = nullptr;
  o.stop_at.reset();
  o.checkpoint_path.clear();
  return o;
}

}  // namespace

SymmetricFront::SymmetricFront(const SearchOptions& options, const SearchProblem& problem,
                               const DataSymmetry& symmetry)
    : options_(scoring_options(options)),
      on_new_member_(options.on_new_member),
      symmetry_(symmetry),
      whole_(options_, problem) {}

FrontMember SymmetricFront::reflected(const FrontMember& half) {
  FrontMember m = half;
  m.expression = reflect_expression(half.expression, symmetry_, whole_.problem.input_names);
  m.formula = to_infix(m.expression, {.substitute_parameters = true});
  m.cost = formula_cost(m.expression, options_);
  m.nodes = m.expression.size();
  std::vector<double> prediction(whole_.rows);
  whole_.predict_shown(m.expression, prediction);
  m.metrics = whole_.metrics_of(prediction);
  m.loss = loss_value(options_.loss, m.metrics);
  return m;
}

std::function<void(const FrontMember&)> SymmetricFront::forward_new_members() {
  if (!on_new_member_) return {};
  return [this](const FrontMember& half) { on_new_member_(reflected(half)); };
}

void SymmetricFront::finish(const std::vector<StartFormula>& starts, SearchSummary* summary) {
  // When and by which strategy each formula was found, to keep in the whole data's front.
  std::map<std::string, std::pair<double, SearchPhase>> found;
  for (const FrontMember& half : summary->front) {
    for (Expression& e : whole_data_forms(half.expression, symmetry_, whole_.problem.input_names,
                                          /*scored=*/true)) {
      const std::string formula = to_infix(e, {.substitute_parameters = true});
      found.emplace(formula, std::make_pair(half.time_s, half.origin));
      // Loss 0 as the estimate: every form is scored on the whole data before it may enter.
      whole_.offer(std::move(e), 0.0, half.origin);
    }
  }
  offer_start_formulas(whole_, starts);
  std::vector<FrontMember> front = whole_.front.members();
  const Float32Check float32(whole_.problem);
  for (FrontMember& m : front) {
    if (m.origin == SearchPhase::Start || m.origin == SearchPhase::Reference)
      m.time_s = 0;  // known before the search began, as when it searches the data as it is
    else if (auto it = found.find(m.formula); it != found.end())
      std::tie(m.time_s, m.origin) = it->second;
    float32.apply(m);
  }
  summary->front = std::move(front);
  summary->symmetry = symmetry_;
  summary->candidates += whole_.candidates.load();
  summary->node_evaluations += whole_.node_evaluations.load();
}

}  // namespace shaderfit::search_detail
