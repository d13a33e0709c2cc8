// The problem options the commands share (problem/problem.hpp): what to approximate, as a CSV file
// (--data), a built-in data set (--dataset, --data-seed) or a reference sampled on a domain
// (--reference FORMULA or --reference-file FILE --function NAME, --domain, --define,
// --samples, --drop-nonfinite); and the columns a formula reads and approximates (--inputs,
// --target), inferred when not given.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "shaderfit/problem/problem.hpp"

namespace shaderfit::cli {

// Which of the options a command offers.
enum DataOptions : unsigned {
  DataFiles = 1u,   // --data, --dataset, --data-seed
  References = 2u,  // --reference, --reference-file, --function, --domain, --define, ...
  Inputs = 4u,      // --inputs
  Target = 8u,      // --target
  SeedAlias = 16u,  // --seed as another name of --data-seed
  Scenes = 32u,     // --scene, --term, --scene-size, --exposure (with References)
  NonFinite = 64u,  // --drop-nonfinite (References has it too)
  InputsTarget = Inputs | Target,
};

struct DataSource {
  ProblemSource problem;       // the flags write here, except:
  std::string reference_file;  // --reference-file: read when the problem is loaded
  std::string inputs;          // --inputs, comma-separated
  bool seed_given = false;     // --data-seed was given
  // --scene, --term, --scene-size, --exposure: read when the problem is loaded.
  std::string scene, term;
  int scene_size = 0;
  double exposure = 1.0;

  // Whether any source was given (--data, --dataset or a reference).
  [[nodiscard]] bool given() const;
};

void add_data_options(CLI::App* cmd, DataSource& src, unsigned options);

// --inputs as a list of names.
std::vector<std::string> input_names(const DataSource& src);

// The problem (problem/problem.hpp's load_problem) after reading --reference-file; *used, when
// given, receives the source as loaded (the file's text in it, the inputs and target chosen),
// which a run's JSON records. Throws shaderfit::Error for a file that cannot be read, and as
// load_problem does.
Problem load_problem(const DataSource& src, ProblemSource* used = nullptr);

// "inputs x, target y, ..." lines of Problem::notes, each prefixed for the command's output.
std::string problem_notes(const Problem& problem, const std::string& prefix);

}  // namespace shaderfit::cli
