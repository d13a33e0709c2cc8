// A member of a search's Pareto front, and its JSON: one writer and one reader, used by the
// search's JSON, its checkpoints, `codegen --front`, `plot front` and `report`. The schema is in
// docs/search.md (section "JSON").
//
//   nlohmann::json j = front_member_json(member, FrontJson::Result);      // for people and tools
//   nlohmann::json k = front_member_json(member, FrontJson::Exact);       // checkpoints
//   FrontFile f = read_front_file("run.json");                    // any front file, by formula
//   for (const FrontMember& m : f.front) use(m.expression, m.cost, m.metrics.mse);
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

// The two strategies of a search, in the order they run: the phase a search is in, and the one
// that found a front member.
// Start: the user's formulas (SearchOptions::start), as written and refitted.
// PowerSum: the exact power sum the search tries after the enumeration (docs/search.md).
// Polynomial: a least-squares polynomial of a one-input problem, tried there too.
// Material: a form with coefficients that are functions of the per-material inputs, tried there
// too (search/uniform_starts.hpp).
// Reference: the reference's own formula (reference/program_formula.hpp); Rewrite: a cheaper
// formula rewritten from it (docs/search.md, "Downward from the reference"); Shape: a shading
// shape fitted to the data (search/starts/shape_starts.hpp), a start of that descent.
enum class SearchPhase {
  Enumeration,
  Evolution,
  Start,
  PowerSum,
  Polynomial,
  Material,
  Reference,
  Rewrite,
  Shape
};
// "enumeration", "evolution", "start", "power_sum", "polynomial", "material", "reference",
// "rewrite", "shape" (and back; nullopt for anything else).
std::string_view search_phase_name(SearchPhase phase);
std::optional<SearchPhase> search_phase_from_name(std::string_view name);

// One formula of the Pareto front.
struct FrontMember {
  Expression expression;  // variables: the problem's input names; parameters hold fitted values
  std::string formula;    // infix that parse_formula reads (fitted constants written as numbers)
  double cost = 0;        // expression_cost(expression, options.cost, options.uniform)
  // With per-material inputs (SearchOptions::uniform): their names, and the SASS instructions
  // computed once per material (cost/per_material.hpp); `cost` is then the per-pixel part's.
  std::vector<std::string> uniform;
  double material_cost = 0;
  std::size_t nodes = 0;  // expression.size()
  ErrorMetrics metrics;   // on every row of the problem
  double loss = 0;        // the metric options.loss names
  double time_s = 0;      // when it was found, seconds since the search started
  SearchPhase origin = SearchPhase::Enumeration;  // the strategy that found it
  // Float32 against float64 on every row (docs/reliability.md): the largest absolute
  // difference (+inf when float32 is not finite on a row), and whether it is within
  // max(1e-4 * max |target|, 0.01 * metrics.max_abs). Filled in for the final front.
  double float32_max_abs_diff = 0;
  bool float32_stable = true;
  // The error of the formula computed in float32 operation by operation (inputs and constants
  // rounded to float, as a shader computes it) against the target, over the same points as
  // metrics.max_abs: the rows, and where a reference is known the points checked between them.
  double float32_max_abs = 0;
  double float32_max_rel = 0;
  // The same in half (eval/evaluate_in.hpp: inputs, constants and every operation rounded to
  // binary16) over the rows; +inf where half is not finite (overflow beyond 65504).
  double half_max_abs = 0;
  double half_max_rel = 0;
  // Where the problem has a reference (SearchProblem::reference): metrics.max_abs and max_rel
  // hold the largest error found between the samples as well as at them (verify/worst_case.hpp),
  // and worst_point the domain point of the largest |error| (domain order).
  bool checked_between_samples = false;
  std::vector<double> worst_point;
  // With SearchOptions::certify: a rigorous bound of |formula - reference| over the whole domain
  // (verify/certify.hpp; +inf when none was found), whether it met the tolerance, and its time.
  std::optional<double> certified_max_abs;
  bool certified_converged = false;
  double certify_time_s = 0;
  std::string certify_note;  // why not converged or no finite bound (verify/certify.hpp)
  // Lowers the loss of the cheaper member shown before it by less than SearchOptions::min_step:
  // kept, but not shown in tables and reports, nor taken as the knee.
  bool minor_step = false;
};

enum class FrontJson {
  // For people and tools (the search's --json): numbers that are not finite are null; adds the
  // parametric formula, the fitted parameters, LaTeX and the code in GLSL and CUDA.
  Result,
  // For checkpoints: the expression node by node and every double to the last bit (NaN and
  // infinities as the strings "nan", "inf", "-inf"), so that a resumed search continues exactly.
  Exact,
};
nlohmann::json front_member_json(const FrontMember& member, FrontJson style);

// How members are read.
struct FrontReadOptions {
  std::vector<std::string> inputs;      // overrides the file's "inputs" when not empty
  std::vector<std::string> parameters;  // names that are parameters in every formula
};

// A member as read: with an "expression" (a checkpoint's), that expression exactly and every
// field required; otherwise the "formula" parsed over `inputs` (with "parameters": a list of
// names, or an object of values), and the fields that are absent or null left NaN (cost, loss,
// metrics, time_s; origin Enumeration). Throws shaderfit::Error located at `where` for a member
// that is not an object or lacks what it needs, a formula that does not parse, or "parameters"
// that are neither names nor an object of numbers.
struct ReadFrontMember {
  FrontMember member;
  bool parameters_have_values = false;  // "parameters" gave values (baked into code)
};
ReadFrontMember front_member_from_json(const nlohmann::json& j,
                                       const std::vector<std::string>& inputs,
                                       const FrontReadOptions& options, const std::string& where);

// A front file: {"inputs": [...] (optional), "front": [member, ...], ...} as the search's
// --json writes it (or written by hand: members need only "formula").
struct FrontFile {
  std::vector<std::string> inputs;   // the file's, or options.inputs
  std::vector<std::string> uniform;  // the file's "uniform": per-material inputs (may be empty)
  std::vector<ReadFrontMember> front;
};
// Throws shaderfit::Error located at the file (and member) for: a file that cannot be read,
// JSON that does not parse, no "front" list, "inputs" that is not a list of names, or a member
// as front_member_from_json says.
FrontFile read_front_file(const std::string& path, const FrontReadOptions& options = {});
// The same for JSON text already in memory, or already parsed; `source` names it in error
// locations.
FrontFile parse_front_file(std::string_view json, const std::string& source,
                           const FrontReadOptions& options = {});
FrontFile front_file_from_json(const nlohmann::json& doc, const std::string& source,
                               const FrontReadOptions& options = {});

}  // namespace shaderfit
