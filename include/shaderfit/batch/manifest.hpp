// A shader library to approximate in one run (`shaderfit batch`, docs/batch.md): a TOML
// manifest with one [[function]] table per function and a [defaults] table every entry starts
// from.
//
//   [defaults]
//   time = 5                 # any search option by its library name (SearchOptions), or the
//   loss = "max_abs"         # aliases time (time_limit_s) and evals (max_candidates)
//
//   [[function]]
//   name = "fast_tanh"                  # the function's name in the headers: a C identifier
//   reference = "tanh(x)"               # the problem: reference + domain, data (a CSV) or dataset
//   domain = { x = [0.0, 4.0] }
//   baseline = "x / (1 + abs(x))"       # the formula in use today (optional)
//   goal = "beat-baseline"              # or "knee" (default), { cost = 6 }, { error = 1e-3 }
//
//   Manifest m = read_manifest("lib.toml");   // every entry checked, its problem loaded
//
// Entry keys: name; the problem (ProblemSource): data, dataset, data_seed, reference,
// reference_file, function, domain (a table of [lo, hi], [lo, hi, count] or "lo:hi" per
// variable, whose order is the inputs'), define (an array of "name = formula"), samples,
// drop_nonfinite, inputs, target, scene and term (with a reference: a scene's samples, "sphere"
// or "plane", the term F, V, D or FV; docs/scenes.md; loss = "display" needs one); weights (a
// numeric column that weighs the rows, left out of a CSV's inferred inputs); baseline;
// start_from_baseline; goal; across_ranks; every search option (search_option_fields(), by name;
// lists as TOML arrays or the option's text). [defaults] takes the same keys except name and
// baseline; a key of [defaults] holds for every entry that does not give it. The paths of data and
// reference_file are relative to the manifest's folder.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/problem/problem.hpp"
#include "shaderfit/search/options.hpp"

namespace shaderfit {

// Which member of an entry's front goes into the headers, and what counts as success.
struct BatchGoal {
  enum class Kind : std::uint8_t {
    Knee,          // the knee of the front (search/choice.hpp); always met
    MaxCost,       // the most accurate member costing at most `limit`; met when one exists
    MaxError,      // the cheapest member whose loss is at most `limit`; met when one exists
    BeatBaseline,  // the most accurate member costing at most the baseline; met when its loss is
                   // at most the baseline's too
  } kind = Kind::Knee;
  double limit = 0;
};

// "knee", "beat-baseline", "cost=N", "error=E" (as the manifest's goal key and the report say).
std::string batch_goal_text(const BatchGoal& goal);

struct ManifestEntry {
  std::string name;
  int line = 0;  // the line of its [[function]] header in the manifest
  // The problem as loaded: its paths resolved against the manifest's folder, a shader file's
  // text read, the inputs and target chosen (what a run's JSON records, report/search_json.hpp).
  ProblemSource problem;
  // The loaded problem (its data, inputs, target, reference), shared by whoever runs the entry.
  std::shared_ptr<const Problem> loaded;
  // [defaults] then the entry's own keys; threads is 1 unless a key sets it (a batch shares the
  // cores among entries: batch/batch.hpp).
  SearchOptions options;
  std::string baseline;  // "" : none; a formula over the problem's inputs
  // The search starts from the baseline, its constants refitted (SearchOptions::start); false:
  // the search alone (a yardstick that compares a search with the formula, not a refit of it).
  bool start_from_baseline = true;
  // Too large for one rank: across MPI ranks (run_batch_distributed) every rank searches it
  // together, the islands shared out as one distributed search shares them
  // (SearchOptions::communicator), before the other entries are handed out. Without MPI, an
  // entry like the others. Not in the hash: a finished entry is read back however many ranks
  // searched it (a shared search's front depends on their number: docs/distributed.md).
  bool across_ranks = false;
  BatchGoal goal;
  std::string weights;  // a column of row weights ("" : none)
  // Hex digest of everything that decides the entry's result (its problem with the paths as the
  // manifest writes them, the contents of its CSV, options, baseline, goal, weights): a finished
  // entry is run again only when this changes.
  std::string hash;
};

// An entry that could not be read: its name (or "function N" when it has none), its line, and
// why (the Error, located in the manifest).
struct BadManifestEntry {
  std::string name;
  int line = 0;
  std::string message;  // the whole line as a person reads it: "m.toml:12:1: entry 'f': ..."
};

struct Manifest {
  std::string path;
  std::vector<ManifestEntry> entries;  // in manifest order
  std::vector<BadManifestEntry> bad;
};

// Reads the manifest and loads every entry's problem. Throws shaderfit::Error located at the
// manifest's file, line and column for a file that cannot be read or is not TOML, an unknown
// top-level table or [defaults] key, a bad value in [defaults], or no [[function]] at all. An
// entry with an unknown key, no problem (or two), a reference that does not parse, a CSV that
// cannot be read, a bad option value, a goal it cannot meet (beat-baseline without a baseline),
// or a name that is no C identifier or is used twice is bad: with `strict` the first one throws
// (naming the entry and its line), otherwise it goes into Manifest::bad and the others stand.
Manifest read_manifest(const std::string& path, bool strict = false);

}  // namespace shaderfit
