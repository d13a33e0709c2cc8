// Exhaustive bottom-up enumeration by cost over cached screen columns (internal).
//
// Level L holds the distinct formulas of (additive) cost L. Each new candidate is one operator
// applied to classes of cheaper levels; its screen column is computed, analysed (loss, hash) in
// the same pass, and the candidate is kept only when no class computes the same values (up to
// sign: negation is free). Work is cut into tiles that any thread may compute; tiles are merged
// into the store strictly in order, so the result does not depend on the number of threads.
//
// Fused sums m +- c of a new product m with a leaf c (one FMA, the same cost as m) are screened
// in closed form as m is made, and only materialised as classes just before their level is
// first used as an operand. See docs/search.md for the ordering and the pruning rules.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "search/enumeration/class_store.hpp"
#include "search/search_context.hpp"
#include "shaderfit/core/random.hpp"

namespace shaderfit::search_detail {

class Enumerator {
 public:
  Enumerator(SearchContext& ctx, Rng& rng);
  ~Enumerator();

  // Enumerates level after level until every level up to options.max_enumeration_cost is done,
  // the store is full, the enumeration's share of the time is spent, or the search stops.
  void run();

  [[nodiscard]] int cost_completed() const { return cost_completed_; }
  // Across ranks: every rank's classes (those of an unfinished batch counted where they were
  // made, so two ranks' equivalent ones count twice).
  [[nodiscard]] std::uint64_t classes() const {
    return ctx_.ranks.distributed() ? joint_classes_ : store_->size();
  }
  // Up to `count` formulas with the lowest screen loss, spread over the cost levels: seeds for
  // the evolution.
  [[nodiscard]] std::vector<Expression> seeds(std::size_t count) const;
  // Across ranks, after run(): every rank's front members join rank 0's front, and rank 0
  // returns the seeds of all ranks' best classes (the others return none).
  std::vector<Expression> gather_at_leader(std::size_t count);

  // Public for the step generator (enum_steps.cpp).
  struct Variant {
    bool swap = false, neg_a = false, neg_b = false;
  };
  struct Step {
    EKind kind = EKind::Var;
    Op op = Op::Const;
    int k = 0;
    std::span<const std::uint32_t> a, b;  // operand lists; b empty for unary steps
    bool triangular = false;              // a and b are one list: pairs at positions i < j
    Variant variants[4];
    int variant_count = 1;
    int order = 0;  // the costliest operand's level; steps run by increasing order
    int level = 0;  // the cost of the step's candidates
    // A next level's step in the batch that completes the level below: its first kHeadTiles
    // tiles lead the batch, its others come last.
    bool next_level = false;
  };
  static constexpr std::size_t kHeadTiles = 4;
  struct Tile {
    std::uint32_t step;
    std::uint32_t a0, a1, b0, b1;
  };
  struct TileOutput;
  struct Costs;

 private:
  void setup_screen(Rng& rng);
  void add_leaves();
  void make_literal_groups();
  std::vector<Step> make_steps(int level) const;
  // The tiles of the steps in the order they are merged; the first `*complete` of them hold
  // every candidate of the steps that are not next_level.
  std::vector<Tile> make_tiles(const std::vector<Step>& steps, std::size_t* complete) const;
  // Runs the steps as one batch; `materialize` marks the batch that turns a level's screened
  // fused sums into classes (already offered to the front). Returns whether the batch's own
  // level is complete (false when the enumeration stopped before).
  bool run_batch(const std::vector<Step>& steps, bool materialize);
  // Computes and merges `tiles` in order on this rank's threads; returns how many were merged
  // (fewer when the enumeration stopped).
  // `positions`, across ranks: each tile's place in its batch (for found_at_).
  std::size_t run_tiles(const std::vector<Step>& steps, std::span<const Tile> tiles,
                        bool materialize, std::span<const std::uint32_t> positions = {});
  // Across ranks (enum_ranks.cpp, docs/distributed.md). A level's classes stay with the rank
  // that made them until the level is shared, once, before the first batch that needs it as the
  // lower operand of a step (a level below the leaves' level plus 3 as soon as it is
  // complete: a step may pair two of its classes). A step over shared levels only has its
  // tiles dealt out to the ranks (tile i of them to rank i mod R); a step over a level not yet
  // shared runs whole on every rank, over that rank's part of the level. The tiles run in rounds
  // of kRoundTiles per thread, after each of which the ranks agree on the count and on whether
  // to stop (agree returns true to stop; `complete`: this rank merged its part of the batch's
  // level; `done`: all its tiles).
  bool run_batch_across_ranks(const std::vector<Step>& steps, const std::vector<Tile>& tiles,
                              std::size_t complete, bool materialize);
  bool agree(bool complete, bool done, bool* level_complete, bool* all_done);
  // Shares every level the batch of `level` needs shared (see above).
  void share_levels_for(int level);
  void share_level(int level);
  [[nodiscard]] bool step_over_shared(const Step& s) const;
  bool enumeration_over();
  void materialize_fused(int level);
  void process_tile(const Step& step, const Tile& tile, TileOutput& out) const;
  // A candidate: its column and key are computed now, into the output's staging, and it is
  // checked against the committed and the tile's classes with the next ones (check_staged), in
  // the order staged.
  void stage(const ClassRecord& rec, const float* a, const float* b, bool neg_a, bool neg_b,
             TileOutput& out) const;
  void check_staged(TileOutput& out) const;
  void check(const ClassRecord& rec, const ColumnStats& stats, const float* column,
             TileOutput& out) const;
  FusedBest screen_fused_sums(const float* m, TileOutput& out) const;
  void merge(TileOutput& out, bool materialize, std::uint64_t found_at);
  // After a batch: applies the cheaper recipes found for committed classes, moves improved
  // classes to their new level lists, and offers them to the front.
  void finish_improvements(bool materialize);
  void setup_full_rows();
  const float* full_column(std::uint32_t id);
  const float* full_eval(std::uint32_t id);
  float* scratch_column();
  bool passes_full_rows(const float* column, int level);
  void prune_elite(int level);
  void consider_for_front(std::uint32_t id, const ColumnStats& stats, int level);
  void consider_fused_for_front(std::uint32_t m, const FusedBest& best, int level);
  template <typename Negated>
  void offer_scored(Expression e, Negated negated, float screen_loss);
  [[nodiscard]] bool fusable(const ClassRecord& r) const;
  [[nodiscard]] double front_threshold(int level) const;
  bool enumeration_should_stop();

  SearchContext& ctx_;
  std::unique_ptr<Costs> costs_;
  std::size_t screen_rows_ = 0;
  std::vector<std::size_t> screen_rows_picked_;  // data row of each screen row
  std::vector<float> screen_y_, screen_w_, screen_log2_y_;
  ScreenTarget target_;
  FusedScreen fused_screen_;
  struct FullRows {  // every row in float32, padded to a multiple of 8 with weight-0 rows
    std::size_t n = 0;
    std::vector<std::vector<float>> inputs, literals, scratch;
    std::vector<float> y, w, log2_y;
    double wyy = 0;
    ScreenTarget target;
    std::size_t next = 0;  // next free scratch column
  } full_;
  std::unique_ptr<ClassStore> store_;
  std::vector<std::vector<std::uint32_t>> level_ids_, fusable_ids_;
  std::vector<bool> materialized_;  // the level's fused sums are classes
  std::vector<std::uint32_t> var_ids_, literal_ids_;
  std::vector<std::uint32_t> fused_leaf_ids_;            // inputs and nonzero literals: c of m +- c
  std::vector<std::pair<double, double>> screen_front_;  // (cost, screen loss) of front entries
  struct Elite {
    float loss;
    std::uint32_t id;
    bool negate;
    bool operator<(const Elite& o) const { return loss < o.loss || (loss == o.loss && id < o.id); }
  };
  std::vector<std::vector<Elite>> elite_levels_;          // best classes per level, for seeds()
  std::vector<std::unique_ptr<TileOutput>> output_pool_;  // reused across batches
  // Cheaper recipes found during a batch (see run()): for committed classes, applied after it.
  struct Improvement {
    std::uint32_t id;
    const float* column;
    ColumnStats stats;
    ClassRecord record;
    FusedBest fused;
    std::uint64_t found_at = 0;  // across ranks (found_at_)
  };
  std::vector<Improvement> deferred_;
  std::vector<std::pair<std::uint32_t, int>> moved_;  // (class, its former level)
  std::unordered_set<std::uint32_t> improved_;        // committed classes improved this batch
  int cost_completed_ = -1;
  std::atomic<bool> exhausted_{false};  // store full or time share spent
  // The share of the time budget, in seconds of process CPU time per search thread, counted
  // from cpu_start_s_: when other processes share the cores the enumeration keeps its share of
  std::chrono::steady_clock::time_point wall_start_ = std::chrono::steady_clock::now();
  // the work (wall time would cut it short).
  double time_share_s_ = 0;
  double cpu_start_s_ = 0;
  // Across ranks: the candidates this rank counted before the enumeration and those it
  // evaluated since; the joint count at the last agreement; whether the ranks agreed to stop;
  // every rank's classes.
  std::uint64_t prior_candidates_ = 0;
  std::atomic<std::uint64_t> own_evaluated_{0};
  std::uint64_t round_base_ = 0;
  bool joint_end_ = false;
  std::uint64_t joint_classes_ = 0;
  // The shared levels, and the shared classes' ids: the same list on every rank, in the ranks'
  // order (a class's place in it is its name in messages); and the place of each class in it.
  std::vector<bool> shared_;
  std::vector<std::uint32_t> shared_ids_;
  std::vector<std::uint32_t> shared_index_;  // per class id; kNotShared for a rank's own
  std::vector<bool> shared_negative_;         // per place: its key's sign
  std::unordered_map<std::uint64_t, std::uint32_t> shared_keys_;  // hash -> place
  // Per class, where it was found: (batch, tile's place in the batch, survivor); a shared
  // level lists the ranks' classes in this order, as one process would have made them.
  std::vector<std::uint64_t> found_at_;
  std::uint64_t batches_ = 0;
  static constexpr std::uint32_t kNotShared = 0xffffffffu;
};

// Seeds from per-level lists, best first: the best of each level, then the second of each ...,
// until `count`; `take(level, k)` gives the k-th entry's formula, or nothing for one that holds
// its place but is never a seed (a literal).
template <typename Take>
std::vector<Expression> pick_seeds(const std::vector<std::size_t>& sizes, std::size_t count,
                                   Take take) {
  std::vector<Expression> out;
  for (std::size_t k = 0; out.size() < count; ++k) {
    bool any = false;
    for (std::size_t level = 0; level < sizes.size(); ++level) {
      if (k >= sizes[level] || out.size() >= count) continue;
      any = true;
      if (std::optional<Expression> e = take(level, k)) out.push_back(std::move(*e));
    }
    if (!any) break;
  }
  return out;
}

// The formula of class `id` (negated when `negate`), over `variables`. A Var leaf k stands for
// input k, or for terminals[k - variables.size()] past the inputs (uniform_terminals.hpp).
Expression build_class_expression(const ClassStore& store, std::uint32_t id, bool negate,
                                  const std::vector<std::string>& variables,
                                  std::span<const double> literals,
                                  std::span<const Expression> terminals = {});
// The formula m +- c (c a leaf class), negated when `negate`.
Expression build_fused_expression(const ClassStore& store, std::uint32_t m, std::uint32_t leaf,
                                  bool neg_leaf, bool negate,
                                  const std::vector<std::string>& variables,
                                  std::span<const double> literals,
                                  std::span<const Expression> terminals = {});

}  // namespace shaderfit::search_detail
