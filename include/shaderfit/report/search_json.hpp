// A search's result as JSON, for programs (schema in docs/search.md, section "JSON").
//
//   SearchSummary s;
//   run_search(options, problem, &s);
//   std::ofstream("front.json") << search_json(s, options, {"fresnel-seed (seed 1)", "R", 0.004});
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "shaderfit/problem/problem.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {

// What the JSON says about the data, besides what the options and summary hold.
struct SearchDataInfo {
  std::string source;      // "data.csv" or "fresnel-seed (seed 1)"
  std::string target;      // the target column's name
  double load_time_s = 0;  // reading or generating the data, before the search's clock
  std::size_t rows = 0;
  std::vector<std::string> inputs;
  // How the data was made (written as "problem"), so that `shaderfit report` can make it again.
  std::optional<ProblemSource> problem;
};

// The whole result: {"data", "options", "summary", "inputs", "front": [...]}; the options are
// every field of search_option_fields() by name, the members front_member_json's Result form.
std::string search_json(const SearchSummary& summary, const SearchOptions& options,
                        const SearchDataInfo& data);

// The "options" object alone: each described option under its name; numbers, booleans and
// lists of numbers as JSON values, choices and operator lists as their text, an unset optional
// as null, the stop target as {"max_loss", "max_cost"}.
nlohmann::json search_options_json(const SearchOptions& options);

// A problem's source as JSON (the "problem" object of a run's JSON; docs/reference.md): the
// fields that are set, a shader function's source text whole. problem_source_from_json reads it
// back; throws shaderfit::Error located at `where` for an object it cannot read.
nlohmann::json problem_source_json(const ProblemSource& source);
ProblemSource problem_source_from_json(const nlohmann::json& j, const std::string& where);

}  // namespace shaderfit
