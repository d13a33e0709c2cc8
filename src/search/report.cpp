#include "shaderfit/search/report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit {

namespace {

std::string when(double s) {
  return s < 10 ? fmt::format("{:.1f} ms", s * 1e3) : fmt::format("{:.2f} s", s);
}

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

std::string code_for(const FrontMember& m, Language lang) {
  try {
    CodegenOptions o;
    o.language = lang;
    o.name = "shaderfit_formula";
    o.bake_parameters = true;
    return generate_function(m.expression, o);
  } catch (const std::exception&) {
    return {};
  }
}

}  // namespace

std::string SearchSummary::brief_report() const {
  std::string s = fmt::format(
      "search: {} after {:.3f} s (enumeration {:.3f} s up to cost {}, {} distinct; evolution "
      "{:.3f} s, "
      "{} generations); {} candidates, {:.3g} node evaluations\n",
      termination, total_time_s, enumeration_time_s, enumeration_cost_completed,
      distinct_candidates, evolution_time_s, generations, candidates,
      static_cast<double>(node_evaluations));
  return s + front_table(*this);
}

std::string front_member_line(const FrontMember& m, Loss loss) {
  return fmt::format("[{}] {}={:.3g} cost={:g}  {}", when(m.time_s), loss_name(loss), m.loss,
                     m.cost, m.formula);
}

std::string front_table(const SearchSummary& s, Loss loss) {
  std::string out = fmt::format("{:>6} {:>5} {:>10} {:>10} {:>10} {:>10}  {}\n", "cost", "nodes",
                                loss == Loss::Mse ? "mse" : std::string(loss_name(loss)), "mse",
                                "max_abs", "found", "formula");
  bool unstable = false;
  for (const FrontMember& m : s.front) {
    // "!" before the formula: float32 evaluation departs from float64 beyond the bound.
    out += fmt::format("{:>6g} {:>5} {:>10.4g} {:>10.4g} {:>10.4g} {:>10} {}{}\n", m.cost, m.nodes,
                       m.loss, m.metrics.mse, m.metrics.max_abs, when(m.time_s),
                       m.float32_stable ? " " : "!", m.formula);
    unstable = unstable || !m.float32_stable;
  }
  if (unstable)
    out +=
        "! not stable in float32: float32 and float64 differ by more than 1e-4 of the "
        "target's scale and 1% of the formula's max_abs error (docs/reliability.md)\n";
  return out;
}

std::string search_json(const SearchSummary& s, const SearchOptions& o, const SearchDataInfo& d) {
  using nlohmann::json;
  json front = json::array();
  for (const FrontMember& m : s.front) {
    json params = json::object();
    for (std::size_t i = 0; i < m.expression.parameters.size(); ++i)
      params[m.expression.parameters[i]] = m.expression.parameter_values[i];
    front.push_back(
        {{"formula", m.formula},
         {"cost", m.cost},
         {"nodes", m.nodes},
         {"loss", number_or_null(m.loss)},
         {"mse", number_or_null(m.metrics.mse)},
         {"rmse", number_or_null(m.metrics.rmse)},
         {"max_abs", number_or_null(m.metrics.max_abs)},
         {"rel", number_or_null(m.metrics.rel)},
         {"log", number_or_null(m.metrics.log)},
         {"time_s", m.time_s},
         {"float32_max_abs_diff", number_or_null(m.float32_max_abs_diff)},
         {"float32_stable", m.float32_stable},
         {"origin", m.origin},
         {"formula_parametric", to_infix(m.expression)},
         {"fitted_parameters", params},
         {"latex", to_latex(m.expression, {.substitute_parameters = true})},
         {"code", {{"glsl", code_for(m, Language::Glsl)}, {"cuda", code_for(m, Language::Cuda)}}}});
  }
  json literals = json::array();
  for (double v : o.literals) literals.push_back(v);
  json out = {{"inputs", d.inputs},
              {"data",
               {{"source", d.source},
                {"rows", d.rows},
                {"target", d.target},
                {"load_time_s", d.load_time_s}}},
              {"options",
               {{"loss", loss_name(o.loss)},
                {"cost", cost_target_name(o.cost)},
                {"operators", operator_list_name(o.operators)},
                {"evolution_operators", operator_list_name(o.evolution_operators)},
                {"max_power", o.max_power},
                {"literals", literals},
                {"seed", o.seed},
                {"threads", o.threads},
                {"device", device_name(o.device)},
                {"time_limit_s", o.time_limit_s},
                {"max_candidates", o.max_candidates ? json(*o.max_candidates) : json()},
                {"max_nodes", o.max_nodes}}},
              {"summary",
               {{"termination", s.termination},
                {"interrupted", s.interrupted},
                {"total_time_s", s.total_time_s},
                {"enumeration_time_s", s.enumeration_time_s},
                {"evolution_time_s", s.evolution_time_s},
                {"candidates", s.candidates},
                {"node_evaluations", s.node_evaluations},
                {"distinct_candidates", s.distinct_candidates},
                {"enumeration_cost_completed", s.enumeration_cost_completed},
                {"generations", s.generations}}},
              {"front", front}};
  return out.dump(2) + "\n";
}

}  // namespace shaderfit
