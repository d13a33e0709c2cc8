// Building a fixed-form fit from a description in text: the formula and its parameters, the data
// (a data set's rows, or variables sampled over a domain), how the rows fall into blocks (groups
// of a column, cells of a grid), derived columns, the reference (a column, or a function in the
// reference language of reference/language.hpp), weights, a transform and constraints. What
// `shaderfit fit` runs; docs/fit.md describes each field's syntax.
//
//   FitSetup setup;
//   setup.data = make_builtin_dataset("fresnel-seed", rng);
//   setup.data_name = "fresnel-seed (seed 1)";
//   setup.formula = "r0 + (1 - r0 - s*cos_theta)*x^4";
//   setup.parameters = {"s=1"};
//   setup.per_group = {"s:material"};
//   setup.target = "R";
//   PreparedFit fit = prepare_fit(std::move(setup));
//   FixedFormSummary summary;
//   solve_fixed_form(fit.options, fit.problem, &summary);  // one s per material
//
// Bad input throws shaderfit::Error located at the field ("FitSetup::grid"; list fields add
// their 1-based position, "FitSetup::constraints 2"); errors in the reference language are
// located at "FitSetup::reference" or "FitSetup::definitions" (line: the definition's position)
// with their column, or at the shader file's line and column.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "shaderfit/data/dataset.hpp"
#include "shaderfit/fit/fixed_form.hpp"

namespace shaderfit {

struct FitSetup {
  // The rows to fit, or nothing when `domain` samples the variables instead.
  std::optional<Dataset> data;
  std::string data_name;  // names the data in reports ("data.csv")
  // Sampled variables "name=lo:hi[:count[:midpoints|endpoints]]" (reference/domain.hpp): the
  // Cartesian product of regular grids when every axis has a count, else the default design of
  // data/sampling.hpp of `samples` points (0: its default), in every cell of the grid.
  std::vector<std::string> domain;
  std::size_t samples = 0;
  std::size_t random_samples = 0;  // > 0: that many uniform points per cell instead
  std::uint64_t rng_seed = 1;      // of the random sampling
  std::vector<std::string> grid;   // conditioning variable name=lo:hi:cells[:sqrt]
  // Derived columns "name = formula" in the reference language (docs/reference.md), each over
  // the columns (or the grid's and domain's variables) and the names defined before it.
  std::vector<std::string> definitions;
  std::string formula;                   // over the columns (or sampled variables)
  std::vector<std::string> parameters;   // free parameter NAME or NAME=START
  std::vector<std::string> per_group;    // PARAM:COLUMN, one value of PARAM per value of COLUMN
  std::vector<std::string> per_cell;     // parameters with one value per grid cell
  std::string target;                    // the column the formula approximates, or
  std::string reference;                 // a reference-language formula over the columns
                                         // (a built-in's name alone: fv-exact), or
  std::string reference_source;          // the text of a GLSL or HLSL file whose function
  std::string function;                  // `function` is the reference, its parameters columns;
  std::string reference_path;            // the file's name, for error locations
  std::string weight;                    // per-row weights: a column or a formula (>= 0)
  std::string transform;                 // T(y) fitted as T(formula) to T(reference)
  std::vector<std::string> constraints;  // "C = 0", "f(x = 0) = f0", "df/dx(x = 1) = 0"
  std::vector<std::string> baselines;    // formulas compared with the fit on every block
  // The columns the formula may read (empty: any); a variable of the formula outside them is an
  // error, as is a name here that is no column.
  std::vector<std::string> inputs;
  // Rows (or sampled points) where the reference is NaN or infinite are left out and counted
  // (PreparedFit::dropped_nonfinite); otherwise the first of them is an error.
  bool drop_nonfinite = false;
  FixedFormOptions options;
};

// Where a block's rows come from, to evaluate other formulas and raw errors on them.
struct BlockSource {
  const Dataset* data = nullptr;
  std::vector<std::size_t> rows;  // the block's rows of `data`
  std::vector<double> target;     // the reference at those rows
};

struct PreparedFit {
  FixedFormProblem problem;
  FixedFormOptions options;
  std::vector<std::unique_ptr<Dataset>> datasets;  // owned data behind the sources
  std::vector<BlockSource> sources;                // one per block
  std::string data_description;                    // "fresnel-seed (seed 1), 4096 rows"
  std::string reference_description;               // "column R", "fv-exact", "g.glsl: G1"
  std::string grouping;                            // "per material", "per cell of 16 x 16", ""
  std::size_t dropped_rows = 0;                    // data rows outside the grid
  std::size_t dropped_nonfinite = 0;   // rows where the reference is not finite (drop_nonfinite)
  std::vector<std::string> baselines;  // FitSetup::baselines
};

// The fitted formula's and each baseline's error on one block's rows, in the original space,
// unweighted.
struct BlockComparison {
  double mse = 0;
  std::vector<double> baseline_mse;  // in the order of PreparedFit::baselines
};

// Throws shaderfit::Error, located at the field, for any bad input.
PreparedFit prepare_fit(FitSetup setup);

// How reports name a loss: "least squares", "log2 error (least squares)", "max error (minimax)".
const char* loss_description(Loss loss);

// One comparison per block of `summary` (the result of solving `fit`). Throws shaderfit::Error
// located at "FitSetup::baselines K" for a baseline that does not parse on the data.
std::vector<BlockComparison> compare_blocks(const PreparedFit& fit,
                                            const FixedFormSummary& summary);

}  // namespace shaderfit
