#include "shaderfit/report/command_json.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

#include "shaderfit/expr/print.hpp"

namespace shaderfit {

namespace {

using nlohmann::json;

json metrics_json(const ErrorMetrics& m) {
  return {{"rows", m.rows},       {"mse", m.mse},         {"rmse", m.rmse},
          {"max_abs", m.max_abs}, {"max_rel", m.max_rel}, {"nonfinite_rows", m.nonfinite}};
}

json change_json(const ErrorMetrics& m, const ErrorMetrics& b) {
  return {{"mse", relative_change(m.mse, b.mse)},
          {"rmse", relative_change(m.rmse, b.rmse)},
          {"max_abs", relative_change(m.max_abs, b.max_abs)},
          {"max_rel", relative_change(m.max_rel, b.max_rel)}};
}

json form_result_json(const rational::FormResult& r, const std::string& var) {
  json j = {{"form", r.form.name(var)},
            {"numerator_degree", r.form.numerator_degree},
            {"denominator_degree", r.form.denominator_degree},
            {"variable", r.form.variable.text(var)},
            {"status", rational::form_status_name(r.status)},
            {"message", r.message},
            {"condition_number", r.condition_number}};
  if (r.usable()) {
    j["rmse"] = r.rmse;
    j["max_abs"] = r.max_abs;
    j["max_rel"] = r.max_rel;
    j["cost"] = r.cost;
    j["formula"] = r.formula;
    j["numerator"] = r.rational.p;
    j["denominator"] = r.rational.q;
  }
  if (r.minimax) {
    const rational::Equioscillation& e = *r.minimax;
    j["minimax"] = {
        {"levelled_error", e.levelled_error}, {"max_error", e.max_error}, {"spread", e.spread},
        {"iterations", e.iterations},         {"converged", e.converged}, {"relative", e.relative},
        {"symmetric", e.symmetric},           {"points", e.points},       {"errors", e.errors}};
  }
  return j;
}

}  // namespace

std::string fit_json(const PreparedFit& fit, const FixedFormSummary& sum,
                     const std::vector<BlockComparison>& comparisons) {
  json j;
  j["schema"] = "shaderfit.fit/1";
  j["formula"] = to_infix(fit.problem.formula);
  j["data"] = fit.data_description;
  j["reference"] = fit.reference_description;
  j["loss"] = loss_description(fit.options.loss);
  j["solver"] = sum.solver;
  j["linear"] = sum.linear;
  j["coupled"] = sum.coupled;
  j["seconds"] = sum.seconds;
  j["failed_blocks"] = sum.failed_blocks;
  j["parameters"] = json::array();
  for (std::size_t p = 0; p < sum.parameter_names.size(); ++p)
    j["parameters"].push_back(
        {{"name", sum.parameter_names[p]},
         {"scope", sum.scopes[p] == ParameterScope::global ? "global" : "per block"}});
  j["baselines"] = fit.baselines;
  j["blocks"] = json::array();
  for (std::size_t b = 0; b < sum.blocks.size(); ++b) {
    const BlockResult& r = sum.blocks[b];
    json params;
    for (std::size_t p = 0; p < r.parameters.size(); ++p)
      params[sum.parameter_names[p]] = r.parameters[p];
    j["blocks"].push_back({{"label", r.label},
                           {"rows", r.rows},
                           {"ok", r.ok},
                           {"failure", r.failure},
                           {"parameters", params},
                           {"initial_cost", r.initial_cost},
                           {"final_cost", r.final_cost},
                           {"rms", r.rms},
                           {"max_abs", r.max_abs},
                           {"iterations", r.iterations},
                           {"termination", r.termination},
                           {"mse", comparisons[b].mse},
                           {"baseline_mse", comparisons[b].baseline_mse}});
  }
  return j.dump(2);
}

std::string eval_json(const EvalReport& report) {
  json j;
  j["schema"] = "shaderfit.eval/1";
  j["data"] = {{"source", report.data}, {"rows", report.rows}, {"target", report.target}};
  // "float64", "float32" or "float16": the names this schema has always used.
  j["precision"] = report.precision == Precision::Half    ? "float16"
                   : report.precision == Precision::Float ? "float32"
                                                          : "float64";
  j["groups"] = report.groups;
  if (!report.uniform.empty()) j["uniform"] = report.uniform;
  const EvalFormulaResult* base = !report.results.empty() && report.results.front().baseline
                                      ? &report.results.front()
                                      : nullptr;
  j["baseline"] = base ? json(base->formula) : json(nullptr);
  j["results"] = json::array();
  for (const EvalFormulaResult& r : report.results) {
    json f;
    f["formula"] = r.formula;
    f["input"] = r.input;
    f["role"] = r.baseline ? "baseline" : "candidate";
    if (report.cost_target) {
      const SplitCost c = split_instruction_count(r.expression, report.uniform, *report.cost_target);
      f["cost"] = {{"target", instruction_target_name(*report.cost_target)}};
      if (report.uniform.empty())
        f["cost"]["instructions"] = c.per_pixel;
      else
        f["cost"].update({{"per_pixel", c.per_pixel}, {"per_material", c.per_material}});
    }
    f["all"] = metrics_json(r.all);
    if (base && !r.baseline) f["all"]["change_vs_baseline"] = change_json(r.all, base->all);
    json groups = json::object();
    for (std::size_t g = 0; g < r.groups.size(); ++g) {
      const EvalGroupResult& gm = r.groups[g];
      json m = metrics_json(gm.metrics);
      if (base && !r.baseline)
        m["change_vs_baseline"] = change_json(gm.metrics, base->groups[g].metrics);
      groups[gm.column][gm.label] = m;
    }
    f["groups"] = groups;
    if (r.checked_between_samples) {
      f["max_abs_checked"] = "between samples";
      f["worst_point"] = r.worst_point;
    }
    if (r.certified_max_abs) {
      f["certified_max_abs"] =
          std::isfinite(*r.certified_max_abs) ? json(*r.certified_max_abs) : json(nullptr);
      f["certified_converged"] = r.certified_converged;
      f["certify_time_s"] = r.certify_time_s;
      if (!r.certify_note.empty()) f["certify_note"] = r.certify_note;
    }
    j["results"].push_back(f);
  }
  return j.dump(2);
}

namespace {

json unit_counts(const InstructionCost& c) {
  return {{"instructions", c.instructions},
          {"fp32", c.fp32},
          {"minmax", c.minmax},
          {"mufu", c.mufu},
          {"weighted", c.weighted}};
}

json listing_json(const InstructionCost& c) {
  json lines = json::array();
  for (const ListingLine& l : c.listing)
    lines.push_back({{"instruction", l.instruction},
                     {"comment", l.comment},
                     {"unit", instruction_unit_name(l.unit)}});
  return {{"target", instruction_target_name(c.target)}, {"lines", lines}};
}

}  // namespace

CostTable cost_table(const Expression& e, InstructionTarget shown,
                     const std::vector<std::string>& uniform, const SourceLocation& uniform_where) {
  check_uniform_inputs(uniform, e.variables, uniform_where);
  CostTable table;
  if (!uniform.empty()) table.material = MaterialCosts{uniform, split_per_material(e, uniform), {}};
  const Expression& counted = table.material ? table.material->split.per_pixel : e;
  for (InstructionTarget t : kInstructionTargets) {
    try {
      InstructionCost c = instruction_cost(counted, t);
      if (table.material)
        table.material->material.push_back(material_instruction_cost(table.material->split, t));
      if (t == shown) table.shown = table.costs.size();
      table.costs.push_back(std::move(c));
    } catch (const Error& missing) {
      // An operator with no half form (sign, select, asin, ...) has no sass-half2 row.
      if (t != InstructionTarget::SassHalf2 || t == shown) throw;
      table.unavailable.emplace_back(t, missing.message());
    }
  }
  return table;
}

std::string cost_json(const Expression& e, const CostTable& table) {
  const MaterialCosts* material = table.material ? &*table.material : nullptr;
  const InstructionCost& shown = table.costs[table.shown];
  json j;
  j["schema"] = "shaderfit.cost/1";
  j["formula"] = to_infix(e);
  j["inputs"] = e.variables;
  j["parameters"] = e.parameters;
  for (std::size_t k = 0; k < table.costs.size(); ++k) {
    json& t = j["targets"][std::string(instruction_target_name(table.costs[k].target))];
    t = unit_counts(table.costs[k]);
    if (material != nullptr) t["per_material"] = unit_counts(material->material[k]);
  }
  for (const auto& [target, why] : table.unavailable)
    j["unavailable"][std::string(instruction_target_name(target))] = why;
  j["listing"] = listing_json(shown);
  if (material != nullptr) {
    j["uniform"] = material->uniform;
    j["per_pixel"] = to_infix(material->split.per_pixel);
    json values = json::array();
    for (const MaterialValue& v : material->split.values)
      values.push_back({{"name", v.name}, {"formula", to_infix(v.value)}});
    j["material_values"] = values;
    j["material_listing"] = listing_json(material->material[table.shown]);
  }
  return j.dump(2);
}

std::string rational_json(const rational::RationalReport& report) {
  json j;
  j["schema"] = "shaderfit.rational/1";
  j["target"] = report.target;
  j["variable"] = report.variable;
  j["domain"] = {report.domain.lo, report.domain.hi};
  j["fit"] = std::string(rational::fit_name(report.fit));
  for (const std::string& c : report.conditions) j["conditions"].push_back(c);
  for (const rational::RationalRun& r : report.runs) {
    json run;
    for (std::size_t i = 0; i < report.parameter_names.size(); ++i)
      run["parameters"][report.parameter_names[i]] = r.parameter_values[i];
    for (const rational::FormResult& f : r.summary.results)
      run["results"].push_back(form_result_json(f, report.variable));
    run["pareto"] = r.summary.pareto;
    j["runs"].push_back(run);
  }
  for (const rational::ParametricLaw& l : report.laws) {
    json lj = {{"form", l.form.name(report.variable)},
               {"usable", l.usable},
               {"all_rational", l.all_rational},
               {"formula", l.formula},
               {"note", l.note}};
    for (const rational::CoefficientLaw& c : l.coefficients)
      lj["coefficients"].push_back({{"name", c.coefficient},
                                    {"found", c.found},
                                    {"law", c.law},
                                    {"max_deviation", c.max_deviation}});
    j["parametric"].push_back(lj);
  }
  return j.dump(2);
}

}  // namespace shaderfit
