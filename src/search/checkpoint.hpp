// Checkpoints of a search: its state in a file, written atomically, and read back to resume
// (internal; the format and what resuming does are in docs/reliability.md).
//
//   Checkpoint c = read_checkpoint("run.ckpt");        // throws Error: damaged, foreign, version
//   check_checkpoint_matches(c, options, problem, "run.ckpt");  // throws Error: other data/options
//
// A file is four header lines and a JSON body:
//   shaderfit checkpoint
//   format 1
//   shaderfit 0.1.0
//   fnv1a64 0123456789abcdef      (FNV-1a of the body's bytes)
//   {...}
// Doubles are JSON numbers written shortest-round-trip (NaN and infinities as strings), and the
// generators' states as operator<< writes them, so a resumed search continues bit for bit.
#pragma once

#include <cstdint>
#include <mutex>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "search/search_context.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/search/search.hpp"
#include "shaderfit/search/symmetry.hpp"

namespace shaderfit::search_detail {

inline constexpr int kCheckpointFormat = 1;

// One individual of an island, with the objectives the evolution ranked it by.
struct SavedIndividual {
  Expression expr;  // with its fitted parameter values
  double loss = 0, cost = 0, raw_loss = 0, raw_cost = 0;
  std::uint64_t hash = 0;
  bool scaled = false;
  double a = 1, b = 0;
};

struct SavedIsland {
  std::string rng;  // the island's generator, as operator<< writes it
  std::vector<SavedIndividual> population;
};

// The evolution at a generation boundary (between a synchronisation point and the next
// generation): nothing found is waiting to be offered and every count is in the context.
struct EvolutionState {
  std::vector<SavedIsland> islands;
  std::uint64_t generations = 0;
  bool polished = false;
};

// An island and an individual in the checkpoint's exact JSON, and back (throws BadExactJson or a
// nlohmann exception for anything else): also the form the ranks of a distributed search send.
nlohmann::json saved_island_json(const SavedIsland& island);
SavedIsland saved_island_from(const nlohmann::json& j);
nlohmann::json saved_individual_json(const SavedIndividual& individual);
SavedIndividual saved_individual_from(const nlohmann::json& j);

struct Checkpoint {
  SearchPhase phase = SearchPhase::Enumeration;  // Enumeration: the front so far; Evolution: all
  std::string shaderfit_version;
  std::uint64_t data_hash = 0;
  std::size_t rows = 0;
  std::vector<std::string> input_names;
  // The symmetry the search used: the data above is then its half (symmetric_half). Absent in
  // checkpoints of searches on the data as it is, those written before symmetry was detected
  // included, which therefore resume on the data as it is.
  std::optional<DataSymmetry> symmetry;
  std::vector<std::pair<std::string, std::string>> options;  // checkpoint_options()
  double elapsed_s = 0;                                      // search clock at the checkpoint
  std::uint64_t candidates = 0, node_evaluations = 0;
  std::vector<FrontMember> front;
  // Evolution phase only: what the enumeration left, and the search's generator when the
  // evolution was constructed (it draws the fit rows from it).
  double enumeration_time_s = 0;
  std::uint64_t distinct_candidates = 0;
  int enumeration_cost_completed = -1;
  std::string rng;
  EvolutionState evolution;
  // The ranks that ran it (SearchOptions::communicator; 1 in checkpoints of one process, and in
  // those written before searches ran across ranks). A run resumes on any number of ranks: the
  // islands are shared out again, and the result depends on the islands, not the ranks.
  int ranks = 1;
};

// The version of shaderfit that this build writes into checkpoints (and accepts in them).
std::string_view checkpoint_writer_version();

// Hash of the data: input names and the bits of every input, target and weight value.
std::uint64_t problem_hash(const SearchProblem& problem);
// The options that decide what the search does (OptionRole::Search), as (name, value) text
// (search_option_text). Budgets and how it runs (threads, device, checkpoint files) are left
// out, so a resumed run may be given a larger budget or other threads.
std::vector<std::pair<std::string, std::string>> checkpoint_options(const SearchOptions& o);

std::string checkpoint_text(const Checkpoint& c);
// Throws Error located at `path`: not a checkpoint, another format or shaderfit version, a
// checksum that does not match, or a body that does not hold what the format says.
Checkpoint parse_checkpoint(std::string_view text, const std::string& path);
// Writes path + ".tmp", flushes it to disk, then renames it over `path`, so `path` always holds
// a whole checkpoint. Throws Error when it cannot.
void write_checkpoint(const std::string& path, const Checkpoint& c);
Checkpoint read_checkpoint(const std::string& path);
// The file's bytes (throws Error when it cannot be opened), for parse_checkpoint.
std::string read_checkpoint_text(const std::string& path);
// Throws Error when the checkpoint was made for other data or with other options (an option it
// does not record counts as its default, so adding an option keeps checkpoints resumable).
void check_checkpoint_matches(const Checkpoint& c, const SearchOptions& options,
                              const SearchProblem& problem, const std::string& path);

// Takes the checkpoints of one search: at generation boundaries (every options.
// checkpoint_interval_s), at the end, and during the enumeration (the front so far).
class Checkpointer {
 public:
  // Checks at once that `options.checkpoint_path` can be written (throws Error otherwise).
  explicit Checkpointer(SearchContext& ctx);

  // What the enumeration left and the generator the evolution is constructed from; call just
  // before constructing the Evolution.
  void begin_evolution(double enumeration_time_s, std::uint64_t distinct_candidates,
                       int enumeration_cost_completed, const Rng& rng);
  // At a generation boundary: keeps the state (for at_end) and writes it when the interval has
  // passed since the last write.
  void at_boundary(const EvolutionState& state);
  // When the evolution ends: writes `current` (the state at the synchronisation point where it
  // stopped), or, when the generation after the last boundary was cut short, that boundary's.
  void at_end(bool generation_cut, const EvolutionState& current);
  // During the enumeration, from any thread: writes the front so far when the interval passed.
  void enumeration_tick();
  // Whether checkpoint_interval_s has passed since the last write.
  [[nodiscard]] bool due() const;
  // When the search ends without an evolution: the front so far, phase "enumeration".
  void write_enumeration();

 private:
  Checkpoint capture(SearchPhase phase);
  void write(const Checkpoint& c);

  SearchContext& ctx_;
  Checkpoint base_;  // fingerprint and enumeration results, filled once
  Checkpoint at_boundary_;
  bool have_boundary_ = false;
  double last_write_s_ = 0;
  std::string deferred_error_;  // a write that failed during the enumeration
  std::mutex write_mutex_;
};

}  // namespace shaderfit::search_detail
