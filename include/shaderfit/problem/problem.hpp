// What a command approximates, stated once for every command (search, eval, fit, rational,
// report) and the Python package: a CSV file, a built-in data set, or a reference (a formula in
// the reference language, or a function of a GLSL or HLSL file) sampled by shaderfit over a
// domain. docs/reference.md describes the reference side.
//
//   ProblemSource s;
//   s.reference.formula = "acos(x)";
//   s.domain = {"x=-1:1"};
//   Problem p = load_problem(s);   // 10,001 rows, inputs {"x"}, target "reference"
//   p.reference->target_at(...);   // the function itself, between the samples too
//
//   ProblemSource c;
//   c.csv_path = "xy.csv";         // columns x, y: inputs {"x"}, target "y", said in p.notes
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "shaderfit/data/dataset.hpp"
#include "shaderfit/reference/function.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/scene/scene.hpp"

namespace shaderfit {

struct ProblemSource {
  // Exactly one of these four: a CSV file, a built-in data set (with its generator's seed), a
  // reference (reference.formula, or reference.shader_source with its path and function; a
  // shader_path alone is read), or a material sweep. Errors about the choice are located at
  // "ProblemSource::csv_path", "ProblemSource::dataset", "ProblemSource::reference" or
  // "ProblemSource::materials"; the reference's own errors at its formula_source /
  // definitions_source / shader_path (reference/language.hpp).
  std::string csv_path;
  // A CSV's rows with a gap in a column of numbers (an empty or non-number cell) are an error,
  // or dropped when this is set (said in notes; data/csv.hpp, CsvOptions).
  bool drop_missing_rows = false;
  std::string dataset;
  std::uint64_t dataset_seed = 1;
  reference::ReferenceText reference;
  // The exact Fresnel reflectance of these materials swept over the angle of incidence, `angles`
  // angles from 0 to 90 degrees each (data/fresnel_sweep.hpp: columns theta_deg, r0, x, R, ...;
  // inputs r0, x and target R unless named): each a parse_material text ("aluminium", "1.5",
  // "0.3+3i"), or "seed" for seed 001's set. Errors at "ProblemSource::materials" (line = the
  // material's 1-based position) and "ProblemSource::angles".
  std::vector<std::string> materials;
  int angles = 181;
  // With a reference: one "name=lo:hi[:count[:spacing]]" per variable (reference/domain.hpp),
  // in any order (the reference's inputs take this order), and the sample design's size
  // (data/sampling.hpp; 0: its default; not with counts on the axes). Errors about an entry are
  // located at "ProblemSource::domain", line = its 1-based position.
  std::vector<std::string> domain;
  std::size_t samples = 0;
  // Samples where the target or an input is NaN or infinite are an error, or dropped when this
  // is set (said in notes).
  bool drop_nonfinite = false;
  // With a reference, instead of a domain: a scene (scene/scene.hpp), whose shading samples are
  // the rows. The reference is a formula of the scene's quantities, or the name of a built-in
  // reference the scene binds to them (scene_reference: "fresnel-dielectric-f0" reads v_dot_h and
  // f0, and stands for the factor F unless scene->term says otherwise). Each sample weighs as
  // the pixel it lights; the display loss's weights are Problem::display_weights. Errors at
  // "ProblemSource::scene".
  std::optional<SceneSpec> scene;
  // The columns the formulas read and the one they approximate. Empty: inferred (a CSV: the
  // numeric column named target, else y, else the last numeric one not among the inputs; the
  // numeric columns other than the target; a data set: its own (fresnel_seed.hpp,
  // BuiltinDatasetInfo); a reference: the domain's variables and "reference"), and said in
  // notes. A reference's inputs and target may name any of its columns (definitions too).
  std::vector<std::string> inputs;
  std::string target;
};

struct Problem {
  Dataset data;  // the rows: a reference's samples have its outputs as columns
  std::vector<std::string> inputs;
  std::string target;
  // Set for a reference: the function, known everywhere on its domain.
  std::shared_ptr<const reference::ReferenceFunction> reference;
  // For people: "xy.csv", "fresnel-seed (seed 1)", "acos(x) on x in [-1, 1], 10,001 samples",
  // "the Fresnel sweep of aluminium, ior1.5 (181 angles each)".
  std::string description;
  // What was inferred or done, one line each, in the library's words (no flag or field names):
  // "inputs x, target y (the column named y is the target, the other numeric columns the
  // inputs)", "text column material not used", "inputs r0, x, target R (the data set's own)",
  // "dropped 5,000 of 10,001 samples where the reference is NaN or infinite, first at x = -1;
  // they span x in [-1, -2e-04]".
  std::vector<std::string> notes;
  // A built-in data set's own search operators, "" for the rest (whose default is "auto").
  std::string operators;
  std::string evolution_operators;
  // The column of row weights ("" : every row weighs 1).
  std::string weights;
  // Set for a scene: its samples (the rows, in order), for pictures of the reference and of
  // formulas (scene_images), and the display loss's row weights (Loss::Display; scene/scene.hpp,
  // display_weights of the target), one per row.
  std::shared_ptr<const SceneSamples> scene;
  std::vector<double> display_weights;
};

// Throws shaderfit::Error located at the field ("ProblemSource::domain", the reference's source
// and column, the CSV file's line and column) for: none or more than one source; a domain,
// samples or definitions for data that is not a reference; a variable with no domain ("no
// domain for variable 'y' (give one: y=lo:hi)"), a domain for no variable, two for one; a bad
// domain (reference/domain.hpp) or design (data/sampling.hpp); a reference with no variable; a
// reference that is NaN or infinite at some samples, unless dropped ("the reference is NaN or
// infinite at 12 of 10,001 samples, first at x = 1.5; they span x in [1.2, 2] (narrow the
// domain, or have such points dropped)", at "ProblemSource::reference"); a CSV with one column
// (or one numeric column) when inputs or target are to be inferred ("xy.csv has one column
// ('x'): a target and at least one input are needed", at the header line); an input or target
// that is no column, or a text column, an input named twice, a target among the inputs (at
// "ProblemSource::inputs" / "ProblemSource::target", naming the numeric columns).
Problem load_problem(const ProblemSource& source);

}  // namespace shaderfit
