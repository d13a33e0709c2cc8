// shaderfit fit: turning the command's options into a FixedFormProblem (the formula, scopes,
// constraints, transform) and its blocks (groups of a data set, cells of a grid, or samples).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "data_source.hpp"
#include "shaderfit/fit/fixed_form.hpp"

namespace shaderfit::cli {

struct FitArgs {
  DataSource data;
  std::string formula;
  std::vector<std::string> params;     // NAME or NAME=START
  std::vector<std::string> per_group;  // NAME:COLUMN
  std::vector<std::string> per_cell;   // NAME
  std::vector<std::string> grid;       // name=lo:hi:cells[:sqrt]
  std::vector<std::string> domain;     // name=lo:hi:count[:midpoints|endpoints]
  std::vector<std::string> defines;    // name = formula
  std::size_t random_samples = 0;
  std::uint64_t rng_seed = 1;
  std::string target, reference, weight, transform;
  std::string loss = "ls", solver = "auto";
  std::vector<std::string> constraints, baselines;
  std::string json_path, table_path;
  std::size_t max_rows = 40;
  int max_iterations = 100;
  int threads = 0;
};

// Where a block's rows come from, to evaluate baselines and raw errors on them.
struct BlockSource {
  const Dataset* data = nullptr;
  std::vector<std::size_t> rows;  // the block's rows of `data`
  std::vector<double> target;     // the reference at those rows
};

struct FitSetup {
  FixedFormProblem problem;
  FixedFormOptions options;
  std::vector<std::unique_ptr<Dataset>> datasets;  // owned data behind the sources
  std::vector<BlockSource> sources;                // one per block
  std::string data_description;                    // "fresnel-seed (seed 1), 4096 rows"
  std::string reference_description;               // "column R" or "fv-exact"
  std::string grouping;                            // "per material", "per cell of 16 x 16", ""
  std::size_t dropped_rows = 0;                    // data rows outside the grid
};

// Throws shaderfit::Error, located at the option, for any bad input.
FitSetup make_fit_setup(const FitArgs& a);

}  // namespace shaderfit::cli
