// The JSON documents of the fit, eval, cost and rational commands, written in one place. Each
// function returns the document as the command prints it (two-space indent, no final newline);
// the schemas are documented in docs/fit.md (shaderfit.fit/1), docs/eval-json.md
// (shaderfit.eval/1), docs/cost-model.md (shaderfit.cost/1) and docs/rational.md
// (shaderfit.rational/1).
//
//   PreparedFit fit = prepare_fit(std::move(setup));
//   FixedFormSummary summary;
//   solve_fixed_form(fit.options, fit.problem, &summary);
//   std::string text = fit_json(fit, summary, compare_blocks(fit, summary));
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/cost/per_material.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/fit/fit_setup.hpp"
#include "shaderfit/rational/rational_setup.hpp"

namespace shaderfit {

// shaderfit.fit/1: the fit, its options, and per block the parameters, costs and comparisons.
std::string fit_json(const PreparedFit& fit, const FixedFormSummary& summary,
                     const std::vector<BlockComparison>& comparisons);

// What `shaderfit eval` measured: formulas on a data set, overall and per group.
struct EvalReport {
  std::string data;  // names the data ("fresnel-seed (seed 1)")
  std::size_t rows = 0;
  std::string target;
  Precision precision = Precision::Double;  // what the formulas were computed in
  std::vector<std::string> groups;          // the grouping columns
  std::vector<std::string> uniform;         // per-material inputs: each formula's two costs
  std::vector<EvalFormulaResult> results;   // the baseline first, when there is one
  // The target each formula's cost counts on, when costs are shown (asked for, or with uniform
  // inputs, where it is sass unless asked).
  std::optional<InstructionTarget> cost_target;
};

// shaderfit.eval/1; metrics of candidates carry their change against the baseline.
std::string eval_json(const EvalReport& report);

// With per-material inputs: the split, and the per-material counts per target (the order of
// `costs`, which then count the per-pixel part).
struct MaterialCosts {
  std::vector<std::string> uniform;
  MaterialSplit split;
  std::vector<InstructionCost> material;
};

// What `shaderfit cost` shows: the counts on every target of kInstructionTargets (sass-half2
// is left out for an operator with no half form, unless it is `shown`) and which one's listing
// is shown. With uniform inputs the counts are the per-pixel part's, the per-material ones in
// `material`.
struct CostTable {
  std::vector<InstructionCost> costs;
  std::optional<MaterialCosts> material;
  std::size_t shown = 0;  // index into costs
  // The targets the formula has no code for, with why (sass-half2: "select has no half form").
  std::vector<std::pair<InstructionTarget, std::string>> unavailable;
};

// Throws shaderfit::Error at `uniform_where` for a bad uniform list (check_uniform_inputs), and
// for a formula the shown target cannot compile.
CostTable cost_table(const Expression& formula, InstructionTarget shown,
                     const std::vector<std::string>& uniform, const SourceLocation& uniform_where);

// shaderfit.cost/1: the counts per target and the listing of the shown one (with per-material
// inputs, the per-pixel counts and listing, and the per-material ones beside them).
std::string cost_json(const Expression& formula, const CostTable& table);

// shaderfit.rational/1.
std::string rational_json(const rational::RationalReport& report);

}  // namespace shaderfit
