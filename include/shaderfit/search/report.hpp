// Search results for people (a table) and for programs (JSON; schema in docs/search.md).
//
//   SearchSummary s;
//   run_search(options, problem, &s);
//   std::cout << front_table(s);
//   std::ofstream("front.json") << search_json(s, options, {"fresnel-seed (seed 1)", "R", 0.004});
#pragma once

#include <string>

#include "shaderfit/search/search.hpp"

namespace shaderfit {

// What the JSON says about the data, besides what the options and summary hold.
struct SearchDataInfo {
  std::string source;      // "data.csv" or "fresnel-seed (seed 1)"
  std::string target;      // the target column's name
  double load_time_s = 0;  // reading or generating the data, before the search's clock
  std::size_t rows = 0;
  std::vector<std::string> inputs;
};

// The front as a table: cost, nodes, every metric, when found, and the formula, marked "!" (with
// a note below the table) when it is not stable in float32.
std::string front_table(const SearchSummary& summary, Loss loss = Loss::Mse);

// One line for a new front member, as printed while searching:
//   "[28.1 ms] mse=3.43e-04 cost=4  r0 + (x - r0) * x^4"
std::string front_member_line(const FrontMember& m, Loss loss);

// The whole result as JSON: {"data", "options", "summary", "inputs", "front": [...]}; every
// front member has formula, cost, nodes, loss, mse, rmse, max_abs, rel, log, time_s, origin,
// latex, code (GLSL and CUDA), float32_max_abs_diff (null when infinite) and float32_stable.
// Metrics that are not finite are null.
std::string search_json(const SearchSummary& summary, const SearchOptions& options,
                        const SearchDataInfo& data);

}  // namespace shaderfit
