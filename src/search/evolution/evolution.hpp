// Island-model NSGA-II over expressions, seeded from the enumeration (internal).
//
// Each island evolves its own population with its own generator (derived from the seed and the
// island's number), ranking individuals by (loss on the fit rows, cost). A child that could enter
// the front is scored on every row; on large data it races first, on a larger sample of rows, and
// only a winner is scored on every row, so that the front holds losses on every row. Islands run in
// parallel between synchronisation points; at each one the candidates they found for the front
// are offered in island order, and every migration_interval generations each island sends its
// best individuals to the next (a ring). The result therefore depends on the seed and the
// number of islands, not on the number of threads, as long as the stop is not by the clock.
// Across ranks (SearchOptions::communicator) each rank evolves a block of the islands, and the
// ranks synchronise every migration_interval generations, where the migrants cross: every rank
// receives every island's candidates found since the last synchronisation and offers them in
// the order (generation, island), so all ranks hold the same front. Between synchronisations a
// rank ranks its candidates against that front and its own islands' finds. The result depends on
// the seed, the islands and the number of ranks (one rank is the synchronous model above).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "search/checkpoint.hpp"
#include "search/search_context.hpp"
#include "search/evolution/variation.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/gpu/evaluator.hpp"

namespace shaderfit::search_detail {

class Evolution {
 public:
  Evolution(SearchContext& ctx, Rng& rng);
  // Fills the islands from the seeds (and the front), then evolves until the search stops.
  void run(const std::vector<Expression>& seeds);
  // Continues from a checkpoint's state (the caller restored the front and the counters, and
  // constructed this from the generator the checkpoint recorded), exactly as the run that
  // wrote it would have gone on from that generation boundary.
  void resume(const EvolutionState& state);
  [[nodiscard]] std::uint64_t generations() const { return generations_; }
  // The state at a generation boundary, for checkpoints.
  [[nodiscard]] EvolutionState state() const;

 private:
  struct Individual {
    Expression expr;
    // Selection objectives: the raw formula's, or its optimal a * f + b's when that is better
    // (the scaling's cost included), so shapes count before their constants are right.
    double loss = 0;  // on the fit rows
    double cost = 0;
    std::uint64_t hash = 0;
    double raw_loss = 0, raw_cost = 0;
    bool scaled = false;
    double a = 1, b = 0;  // the optimal scaling
  };
  struct Candidate {  // for the front, scored on every row
    Expression expr;
    ErrorMetrics metrics;
    std::uint64_t generation = 0;  // in which it was found: candidates are offered in that order
  };
  struct Island {
    Rng rng;
    std::vector<Individual> population;
    std::vector<Candidate> found;
    std::uint64_t evaluated = 0;
    double busy_s = 0;  // across ranks: seconds spent evolving it since the last synchronisation
  };
  // With a reference that lowers into the operators: the fit rows as a problem, for the
  // cost-lowering rewrites (rewrites.hpp) that a quarter of the local mutants are.
  bool rewrites_ = false;
  SearchProblem rewrite_rows_;
  // Rows copied out of the problem, in the order given: the fit rows, the race rows.
  struct RowSample {
    std::vector<std::vector<double>> columns;  // one per input
    std::vector<const double*> pointers;       // into columns
    std::vector<double> target, weights;       // weights empty: all 1
    RowSample() = default;
    RowSample(const RowSample&) = delete;  // pointers point into columns
    RowSample& operator=(RowSample&&) = default;
    // The rows' weights are the problem's times `scale` (one per row; empty: 1).
    RowSample(const SearchProblem& p, std::span<const std::size_t> rows,
              std::span<const double> scale = {});
    [[nodiscard]] std::size_t size() const { return target.size(); }
  };
  using Snapshot = std::vector<std::pair<double, double>>;  // (cost, loss) of the front
  // What the ranks of a distributed search decide together at a synchronisation point.
  struct Joint {
    bool time_up = false;      // rank 0's clock passed the time limit
    bool interrupted = false;  // some rank's interrupt flag is set
    bool polish = false;       // rank 0's clock passed kPolishAt of the time limit
    bool checkpoint = false;   // rank 0's checkpoint interval has passed
    bool cut = false;          // some rank's last generation stopped early
  };

  // As checkpoints and messages hold them.
  static SavedIndividual saved(const Individual& ind);
  static Individual restored(const SavedIndividual& s);
  static SavedIsland saved_island(const Island& island);

  void init_island(Island& island, const std::vector<Expression>& seeds, std::size_t first,
                   std::size_t stride);
  void evolve();  // the generation loop
  // False when it stopped early (time or interrupt) with fewer children than usual.
  bool generation(Island& island, const Snapshot& front);
  bool evaluate(Individual& ind, Island& island, std::vector<double>& values) const;
  // Fits ind's free constants on the fit rows (a few warm-started steps).
  void fit_constants(Individual& ind) const;
  // Fits e's free constants on `rows` (at most `steps` warm-started LM steps), counting the work.
  void fit_constants(Expression& e, const RowSample& rows, int steps) const;
  // evaluate() for a batch of children, their losses non-finite where evaluate() is false: on
  // the CPU one by one, on the GPU in two launches (src/search/evolution/evolution_gpu.cpp).
  void evaluate_batch(std::vector<Individual>& batch, Island& island,
                      std::vector<double>& values) const;
  void evaluate_on_gpu(std::vector<Individual>& batch, Island& island) const;
  // Adds ind, and its scaled form, to the island's finds (scored on every row) where its loss on
  // the fit rows could enter the front and, racing, so could its loss on the race rows once
  // refitted there. `values` is scratch.
  void consider(const Individual& ind, Island& island, const Snapshot& front,
                std::vector<double>& values) const;
  // e refitted on every row (racing: as it is, refitted on the race rows) and, for a minimax loss
  // near front_loss (the front's loss at its cost), minimax fitted, then scored on every row.
  Candidate score_on_all_rows(Expression e, double front_loss) const;
  [[nodiscard]] const Individual& tournament(Island& island, const std::vector<int>& rank,
                                             const std::vector<double>& crowd) const;
  void migrate();
  // Every kRestartEvery generations one island (in turn) starts again: the front's cheaper half
  // and random formulas, so that a population stuck on one shape makes room for others.
  void restart_island();
  // Distributed, a reduction in two halves: every rank's islands' found candidates, evaluation
  // counts and votes go to rank 0 (gather_found), which offers them to its front in island
  // order and sends back only what entered, the total count and the joint decision
  // (share_entrants; the others offer those members to their fronts, which stay rank 0's).
  // Neither half's bytes per rank grow with the number of ranks.
  Joint gather_found(bool cut);
  Joint share_entrants(Joint joint, const std::vector<FrontMember>& entered,
                       std::uint64_t* evaluated);
  // Rank 0, at a synchronisation: islands dealt again by the time each took since the last one
  // (the longest first, each to the rank with the least work so far) when the busiest rank's
  // share exceeds the mean by kRebalanceAbove and the new deal lowers it (kRebalanceGain); the
  // current owners otherwise. An island evolves
  // the same on any rank (it ranks against the synchronised front and its own finds), so this
  // changes where, never what.
  [[nodiscard]] std::vector<int> balanced_owners() const;
  // Every rank: sends the islands it gives up to their new owners and takes its new ones.
  void move_islands(const std::vector<int>& owners);
  // Distributed: the state of every island at rank 0, from the ranks that own them (collective;
  // the others get an empty state).
  EvolutionState gathered_state();
  [[nodiscard]] bool owns(std::size_t island) const;
  [[nodiscard]] bool racing() const { return race_.size() > 0; }
  void polish_front();
  [[nodiscard]] bool out_of_time() const;

  SearchContext& ctx_;
  VariationLimits limits_;
  double scaling_cost_ = 1;  // cost(a * f + b) - cost(f)
  // The fit rows: each child's constants are fitted, and its loss for selection taken, there.
  RowSample fit_;
  // The race rows (racing, on data with many rows; else empty), disjoint from the fit rows, each
  // weighted by the rows it stands for: a front candidate is refitted and scored there before it
  // is scored on every row (kRaceRows in evolution.cpp).
  RowSample race_;
  std::vector<Island> islands_;
  std::vector<std::size_t> owned_;  // the islands this rank evolves (all in one process)
  std::vector<int> owner_;           // per island, the rank that evolves it
  std::uint64_t generations_ = 0;
  bool polished_ = false;
  std::unique_ptr<GpuEvaluator> gpu_;  // the fit rows on the GPU, when ctx.device is Cuda
};

}  // namespace shaderfit::search_detail
