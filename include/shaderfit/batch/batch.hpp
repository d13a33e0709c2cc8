// Running a manifest (batch/manifest.hpp): every entry searched, each on one core with the
// cores shared among entries, a checkpoint per finished entry so that a batch run again skips
// what it finished (unless the entry changed), and one result: headers per shading language, a
// JSON of every front, one HTML report (batch/outputs.hpp). docs/batch.md.
//
//   Manifest m = read_manifest("lib.toml");
//   BatchOptions o;
//   o.checkpoint_directory = "out/entries";
//   o.on_entry = [](const BatchEntryResult& r) { std::cout << batch_entry_line(r) << "\n"; };
//   BatchResult result = run_batch(m, o);
//   write_batch_outputs(result, &m, "out");   // batch/outputs.hpp
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "shaderfit/batch/manifest.hpp"
#include "shaderfit/search/front/choice.hpp"
#include "shaderfit/search/communicator.hpp"
#include "shaderfit/search/front_member.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {

// The baseline (the formula in use today) on the entry's problem: its cost under the entry's
// cost target and its errors, as a front member's (float32 check included).
struct BaselineScore {
  std::string formula;
  double cost = 0;
  double loss = 0;  // the entry's loss
  ErrorMetrics metrics;
  double float32_max_abs = 0;
};

struct BatchEntryResult {
  std::string name;
  std::string hash;         // ManifestEntry::hash when it ran
  std::string description;  // the problem, for people: "tanh(x) on x in [0, 4], 10,001 samples"
  std::vector<std::string> inputs;
  std::string target;
  std::string loss_name;  // "max_abs"
  std::string cost_name;  // "instructions"
  BatchGoal goal;
  std::vector<FrontMember> front;  // cheapest first
  std::size_t chosen = 0;          // the goal's member (index into front)
  bool goal_met = false;
  std::string why;  // one line: why that member (search/choice.hpp's words, or the baseline's)
  std::optional<BaselineScore> baseline;
  std::string run_json;  // the entry's search JSON (report/search_json.hpp), as `search --json`
  double seconds = 0;    // the search's wall time when it ran
  bool from_checkpoint = false;  // finished by an earlier run, read back
  int rank = 0;  // the MPI rank that ran it (0 without MPI); kAllRanks: across_ranks
  static constexpr int kAllRanks = -1;
};

// The rule that picks an entry's member (search/choice.hpp) from its goal: beat-baseline is the
// most accurate member costing at most the baseline.
ChoiceRule batch_choice_rule(const BatchEntryResult& r);

// "fast_tanh  cost 4 (baseline 6)  max_abs 1.2e-03 (baseline 2.1e-02)  goal met  3.1 s": the
// line a batch prints per finished entry.
std::string batch_entry_line(const BatchEntryResult& r);

struct BatchProgress {
  std::size_t done = 0, total = 0;  // entries
  double elapsed_s = 0;
  std::vector<std::string> running;  // names of the entries being searched
};

struct BatchOptions {
  // Entries searched at once (each with its own options.threads, 1 by default); 0: the cores.
  int parallel_entries = 0;
  // Not empty: each finished entry is written there as NAME.json (its BatchEntryResult with
  // the hash) as soon as it finishes, and an entry whose file holds its current hash is read
  // back instead of run again.
  std::string checkpoint_directory;
  // Called on the calling thread as each entry finishes (or is read back), in finishing order.
  std::function<void(const BatchEntryResult&)> on_entry;
  std::function<void(const BatchProgress&)> on_progress;
  // Set from another thread or a signal handler: the running searches stop at once and are not
  // checkpointed (they run again from the start next time); run_batch returns what finished.
  const std::atomic<bool>* interrupt = nullptr;
  // Across ranks (run_batch_distributed): a rank that sends nothing for this long while it has
  // an entry is taken for dead, and its entry handed out again. Busy ranks beat every second
  // (or a quarter of this, when shorter).
  double rank_timeout_s = 10;
};

struct BatchResult {
  std::string manifest;                   // its path
  std::vector<BatchEntryResult> entries;  // in manifest order (those that finished)
  std::vector<BadManifestEntry> bad;      // the manifest's bad entries, and entries that failed
  bool interrupted = false;
  double seconds = 0;
  // What happened besides the entries, one line each: "rank 2 went silent while it searched
  // fast_erf: taken for dead, fast_erf handed out again".
  std::vector<std::string> notes;
};

// Runs every entry of `manifest` not already finished. Longest first (by time budget, then
// rows): the batch ends sooner when the long ones start early. An entry whose search throws is
// moved to `bad` with its message; the others go on.
BatchResult run_batch(const Manifest& manifest, const BatchOptions& options);

// The same across the ranks of `communicator`, every rank calling it with the same manifest
// (docs/batch.md, "Across machines"). First the entries marked across_ranks, one after another,
// each searched by every rank together; then rank 0 hands out the others longest first as ranks
// ask for work, runs entries itself on its own worker threads too, gathers the results, writes
// the checkpoints and calls the callbacks; the others search what they are given, one at a
// time. A rank that goes silent (BatchOptions::rank_timeout_s) while it searches a handed-out
// entry loses only that entry, which is handed out again; one that dies during an across_ranks
// entry ends the job, as in a distributed search. Rank 0's result holds every entry; the others
// return an empty one.
BatchResult run_batch_distributed(const Manifest& manifest, const BatchOptions& options,
                                  Communicator& communicator);

// One entry, on the calling thread: the search, the baseline's score and the goal's member.
// With a communicator, every rank calls it for the same entry and the search runs across them
// (SearchOptions::communicator); rank 0's result is the entry's, the others' front is empty.
BatchEntryResult run_batch_entry(const ManifestEntry& entry,
                                 const std::atomic<bool>* interrupt = nullptr,
                                 Communicator* communicator = nullptr);

// The checkpoint form of a result (JSON text) and back; from_json throws shaderfit::Error located
// at `source` for a file it cannot read.
std::string batch_entry_json(const BatchEntryResult& r);
BatchEntryResult batch_entry_from_json(const std::string& text, const std::string& source);

}  // namespace shaderfit
