#include "search/enumeration/enumerator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>

#include "core/cpu_clock.hpp"
#include "search/enumeration/enum_costs.hpp"
#include "search/enumeration/enum_tile.hpp"
#include "shaderfit/core/parallel.hpp"

namespace shaderfit::search_detail {

Enumerator::Enumerator(SearchContext& ctx, Rng& rng)
    : ctx_(ctx), costs_(std::make_unique<Costs>(ctx.options)) {
  const SearchOptions& o = ctx.options;
  time_share_s_ = o.evolve ? o.max_enumeration_share * o.time_limit_s : o.time_limit_s;
  cpu_start_s_ = process_cpu_seconds();
  wall_start_ = std::chrono::steady_clock::now();
  setup_screen(rng);
  setup_full_rows();
  // Formulas built from + - * / and powers are rational functions: two that agree on 64 random
  // points to 2e-5 are the same function. Piecewise operators can agree on many points and
  // differ elsewhere, so with them every screen row is checked.
  const bool piecewise = std::any_of(o.operators.begin(), o.operators.end(), is_piecewise);
  store_ = std::make_unique<ClassStore>(screen_rows_, o.max_classes, piecewise ? screen_rows_ : 64);
  const std::size_t levels = static_cast<std::size_t>(std::max(o.max_enumeration_cost, 0)) + 2;
  level_ids_.resize(levels);
  fusable_ids_.resize(levels);
  materialized_.assign(levels, false);
  elite_levels_.resize(levels);
  add_leaves();
  prior_candidates_ = ctx.candidates.load();
  round_base_ = prior_candidates_;
  joint_classes_ = store_->size();
  if (ctx.ranks.distributed()) {  // per class: reserved, so that growing never copies them
    found_at_.reserve(o.max_classes);
    shared_index_.reserve(o.max_classes);
  }
  // The leaves and literals, the same on every rank, are shared from the start.
  shared_.assign(levels, false);
  for (int k = 0; k <= cost_completed_; ++k) shared_[static_cast<std::size_t>(k)] = true;
  for (std::uint32_t id = 0; id < store_->size(); ++id) {
    shared_index_.push_back(id);
    shared_ids_.push_back(id);
    shared_negative_.push_back(store_->record(id).has(ClassRecord::kCanonicalNeg));
    shared_keys_.emplace(store_->hash(id), id);
  }
}

Enumerator::~Enumerator() = default;

void Enumerator::setup_screen(Rng& rng) {
  const std::size_t rows = ctx_.rows;
  const std::size_t wanted = ctx_.options.screen_rows;
  std::vector<std::size_t> all(rows);
  for (std::size_t i = 0; i < rows; ++i) all[i] = i;
  std::vector<std::size_t> picked =
      stratified_rows(ctx_.problem.target, std::move(all), wanted, rng);
  const std::size_t real = picked.size();
  screen_rows_ = std::max<std::size_t>(kMinScreenRows, (real + 7) / 8 * 8);
  while (picked.size() < screen_rows_) picked.push_back(picked.front());  // padding, weight 0
  screen_rows_picked_ = picked;

  const SearchProblem& p = ctx_.problem;
  const Loss loss = ctx_.options.loss;
  screen_y_.resize(screen_rows_);
  screen_w_.resize(screen_rows_);
  screen_log2_y_.resize(screen_rows_);
  double sum_w = 0;
  for (std::size_t i = 0; i < screen_rows_; ++i) {
    const std::size_t r = picked[i];
    const double w = i < real ? (p.weights.empty() ? 1.0 : p.weights[r]) : 0.0;
    const double y = p.target[r];
    const bool left_out = loss == Loss::Relative && !relative_screen_row(y);
    screen_y_[i] = left_out ? 1.0f : static_cast<float>(y);
    screen_log2_y_[i] = y > 0 ? static_cast<float>(std::log2(y)) : 0.0f;
    screen_w_[i] = left_out ? 0.0f : static_cast<float>(screen_weight(loss, w, y));
    sum_w += w;
  }
  if (screen_loss(loss) != Loss::MaxAbs && sum_w > 0) {
    for (float& w : screen_w_) w = static_cast<float>(w / sum_w);
  }
  double wyy = 0;
  for (std::size_t i = 0; i < screen_rows_; ++i)
    wyy += static_cast<double>(screen_w_[i]) * screen_y_[i] * screen_y_[i];
  target_ = {screen_y_.data(),  screen_w_.data(), screen_log2_y_.data(), wyy,
             screen_loss(loss), screen_rows_};
}

void Enumerator::add_leaves() {
  const SearchProblem& p = ctx_.problem;
  std::vector<float> col(screen_rows_);
  auto insert_leaf = [&](ClassRecord rec) {
    ColumnStats stats = analyze_column(col.data(), target_);
    if (!stats.valid) {  // a constant input or a literal: kept, never equal to a candidate
      stats.valid = true;
      stats.hash = 0x5bd1e995u + std::uint64_t{store_->size()};
    }
    const std::uint32_t id = store_->insert_copy(col.data(), stats, rec);
    consider_for_front(id, stats, rec.cost);
    return id;
  };
  for (std::size_t v = 0; v < p.inputs.size(); ++v) {
    for (std::size_t i = 0; i < screen_rows_; ++i)
      col[i] = static_cast<float>(p.inputs[v][screen_rows_picked_[i]]);
    ClassRecord rec = make_record(EKind::Var, static_cast<std::uint16_t>(costs_->leaf));
    rec.k = static_cast<std::int8_t>(v);
    const std::uint32_t id = insert_leaf(rec);
    var_ids_.push_back(id);
    level_ids_[static_cast<std::size_t>(costs_->leaf)].push_back(id);
  }
  // The uniform terminals: leaves past the inputs, free per pixel like them.
  for (std::size_t t = 0; t < ctx_.terminals.size(); ++t) {
    const float* full = full_.inputs[p.inputs.size() + t].data();
    for (std::size_t i = 0; i < screen_rows_; ++i) col[i] = full[screen_rows_picked_[i]];
    ClassRecord rec = make_record(EKind::Var, static_cast<std::uint16_t>(costs_->leaf));
    rec.k = static_cast<std::int8_t>(p.inputs.size() + t);
    const std::uint32_t id = insert_leaf(rec);
    var_ids_.push_back(id);
    level_ids_[static_cast<std::size_t>(costs_->leaf)].push_back(id);
  }
  const auto& lits = ctx_.options.literals;
  for (std::size_t l = 0; l < lits.size(); ++l) {
    std::fill(col.begin(), col.end(), static_cast<float>(lits[l]));
    ClassRecord rec = make_record(EKind::Literal, static_cast<std::uint16_t>(costs_->literal));
    rec.k = static_cast<std::int8_t>(l);
    rec.flags = ClassRecord::kLiteral;
    literal_ids_.push_back(insert_leaf(rec));
  }
  store_->commit();
  make_literal_groups();
  cost_completed_ = std::min(costs_->leaf, costs_->literal);

  // Closed-form screening of m +- c: the constants K(b, c) = sum w (b c - y)^2.
  FusedScreen& fs = fused_screen_;
  fs.y = screen_y_.data();
  fs.w = screen_w_.data();
  fs.n = screen_rows_;
  for (const std::uint32_t leaf : fused_leaf_ids_) {
    const ClassRecord& r = store_->record(leaf);
    const bool literal = r.kind == EKind::Literal;
    fs.leaf_columns.push_back(literal ? nullptr : store_->column(leaf));
    fs.leaf_values.push_back(literal ? static_cast<float>(lits[static_cast<std::size_t>(r.k)])
                                     : 0.0f);
    double kp = 0, km = 0;
    const float* c = store_->column(leaf);
    for (std::size_t i = 0; i < screen_rows_; ++i) {
      kp += static_cast<double>(screen_w_[i]) * (c[i] - screen_y_[i]) * (c[i] - screen_y_[i]);
      km += static_cast<double>(screen_w_[i]) * (c[i] + screen_y_[i]) * (c[i] + screen_y_[i]);
    }
    fs.k_plus.push_back(kp);
    fs.k_minus.push_back(km);
  }
}

bool Enumerator::fusable(const ClassRecord& r) const {
  if (costs_->fused < 0) return false;
  switch (r.kind) {
    case EKind::Mul: return true;
    case EKind::IPow: return r.k >= 2;
    case EKind::Div: {  // a / b = a * rcp(b), except 1 / b = rcp(b)
      const ClassRecord& a = store_->record(r.a);
      return !(a.kind == EKind::Literal &&
               std::abs(ctx_.options.literals[static_cast<std::size_t>(a.k)]) == 1.0);
    }
    default: return false;
  }
}

bool Enumerator::enumeration_should_stop() {
  if (ctx_.should_stop() || exhausted_.load(std::memory_order_relaxed)) return true;
  const std::optional<std::int64_t>& budget = ctx_.options.max_candidates;
  if (ctx_.ranks.distributed() && budget) {
    // A round's share of what is left of the budget: the other ranks evaluate about as many
    // candidates as this one in it (the ranks then agree on the count, and go on).
    const std::uint64_t now = ctx_.candidates.load(std::memory_order_relaxed);
    const auto ranks = static_cast<std::uint64_t>(ctx_.ranks.size());
    if (ranks * (now - round_base_) >= static_cast<std::uint64_t>(*budget) - round_base_)
      return true;
  }
  // CPU seconds per thread cannot exceed wall seconds: the process clock (a system call) is read
  // only once the wall clock has passed the share.
  const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - wall_start_;
  if (wall.count() < time_share_s_) return false;
  const double cpu_s = (process_cpu_seconds() - cpu_start_s_) / ctx_.threads;
  if (cpu_s >= time_share_s_) exhausted_.store(true, std::memory_order_relaxed);
  return exhausted_.load(std::memory_order_relaxed);
}

void Enumerator::run() {
  const int max_cost = ctx_.options.max_enumeration_cost;
  const bool deferred_fusion = costs_->eager_fusion();
  for (int level = cost_completed_ + 1; level <= max_cost; ++level) {
    if (enumeration_over()) break;
    if (deferred_fusion && level >= 2) materialize_fused(level - 1);
    if (ctx_.ranks.distributed()) share_levels_for(level);
    if (enumeration_over()) break;
    // The batch that completes a level also runs the next level's steps whose operands all lie
    // below the level (they need nothing more): their first tiles ahead of the level's own,
    // their others after. So a cheap formula of the next level is not held up by the largest
    // steps of this one. On the seed task that is where the target is: (x - r0) * x^4 is a
    // product of levels 1 and 2 at level 4, while level 3 spends most of its work on operands
    // of level 2. A candidate equivalent to a class made earlier at a higher cost gives that
    // class its cheaper recipe (merge and finish_improvements), so every class keeps the
    // cheapest recipe found.
    std::vector<Step> steps = make_steps(level);
    std::erase_if(steps, [&](const Step& s) { return s.order < level - 1; });
    if (level + 1 <= max_cost) {
      for (Step& s : make_steps(level + 1)) {
        if (s.order > level - 1) continue;
        s.next_level = true;
        steps.push_back(s);
      }
    }
    const bool complete = run_batch(steps, false);
    prune_elite(level);
    if (complete) cost_completed_ = level;
    if (ctx_.ranks.distributed() ? joint_end_
                                 : ctx_.stopped() || exhausted_.load(std::memory_order_relaxed))
      break;
  }
}

bool Enumerator::enumeration_over() {
  // Across ranks only what the ranks agreed on: each rank makes the same collective calls.
  return ctx_.ranks.distributed() ? joint_end_ : enumeration_should_stop();
}

void Enumerator::materialize_fused(int level) {
  const auto L = static_cast<std::size_t>(level);
  if (materialized_[L]) return;
  materialized_[L] = true;
  // Across ranks every rank takes part in the batch, with its part of the level's products.
  if (fused_leaf_ids_.empty() || (fusable_ids_[L].empty() && !ctx_.ranks.distributed())) return;
  Step s;
  s.kind = EKind::FusedAdd;
  s.a = fusable_ids_[L];
  s.b = fused_leaf_ids_;
  s.variants[1] = {false, false, true};
  s.variant_count = 2;
  s.order = level;
  s.level = level;
  run_batch({s}, true);
}

bool Enumerator::run_batch(const std::vector<Step>& steps, bool materialize) {
  std::size_t complete = 0;
  const std::vector<Tile> tiles = make_tiles(steps, &complete);
  // Across ranks every rank takes part, whatever its share (its part of a level may be empty).
  if (ctx_.ranks.distributed())
    return run_batch_across_ranks(steps, tiles, complete, materialize);
  if (tiles.empty()) return true;
  const bool whole = run_tiles(steps, tiles, materialize) >= complete;
  finish_improvements(materialize);
  store_->commit();
  return whole;
}

std::size_t Enumerator::run_tiles(const std::vector<Step>& steps, std::span<const Tile> tiles,
                                  bool materialize, std::span<const std::uint32_t> positions) {
  const std::size_t n = tiles.size();
  if (n == 0) return 0;
  const auto threads = static_cast<std::size_t>(ctx_.threads);
  std::vector<std::unique_ptr<TileOutput>> outputs(n);
  std::unique_ptr<std::atomic<bool>[]> ready(new std::atomic<bool>[n]);
  for (std::size_t i = 0; i < n; ++i) ready[i].store(false, std::memory_order_relaxed);
  std::atomic<std::size_t> next{0}, merged{0};
  std::mutex merge_mutex, pool_mutex;
  std::vector<std::unique_ptr<TileOutput>>& pool = output_pool_;

  // Whoever holds the merge lock merges the finished tiles that come next in order.
  auto try_merge = [&] {
    std::unique_lock lock(merge_mutex, std::try_to_lock);
    if (!lock.owns_lock()) return;
    std::size_t m = merged.load(std::memory_order_relaxed);
    while (m < n && ready[m].load(std::memory_order_acquire) &&
           !exhausted_.load(std::memory_order_relaxed)) {
      merge(*outputs[m], materialize,
            positions.empty() ? 0 : batches_ << 40 | std::uint64_t{positions[m]} << 16);
      {
        std::lock_guard pl(pool_mutex);
        pool.push_back(std::move(outputs[m]));
      }
      merged.store(++m, std::memory_order_release);
    }
    ctx_.maybe_progress(SearchPhase::Enumeration);
  };

  auto worker = [&](std::size_t, std::size_t) {
    while (true) {
      try_merge();
      if (enumeration_should_stop()) return;
      const std::size_t claimed = next.load(std::memory_order_relaxed);
      const std::size_t done = merged.load(std::memory_order_acquire);
      if (done >= n) return;
      if (claimed >= n || claimed - done > 4 * threads) {  // bound the tiles waiting to merge
        std::this_thread::yield();
        continue;
      }
      const std::size_t i = next.fetch_add(1, std::memory_order_relaxed);
      if (i >= n) continue;
      std::unique_ptr<TileOutput> out;
      {
        std::lock_guard pl(pool_mutex);
        if (!pool.empty()) {
          out = std::move(pool.back());
          pool.pop_back();
        }
      }
      if (!out) {
        out = std::make_unique<TileOutput>();
        out->store = store_.get();
      }
      out->clear(screen_rows_);
      const Tile& t = tiles[i];
      process_tile(steps[t.step], t, *out);
      ctx_.candidates.fetch_add(out->evaluated, std::memory_order_relaxed);
      own_evaluated_.fetch_add(out->evaluated, std::memory_order_relaxed);
      ctx_.node_evaluations.fetch_add(out->evaluated * screen_rows_, std::memory_order_relaxed);
      outputs[i] = std::move(out);
      ready[i].store(true, std::memory_order_release);
    }
  };
  parallel_for(threads, 1, worker, static_cast<int>(threads));
  return merged.load();
}

void Enumerator::merge(TileOutput& out, bool materialize, std::uint64_t found_at) {
  const bool track = ctx_.ranks.distributed();
  // The pending table and the columns it points to are larger than the cache: each survivor's
  // table slot is fetched 2k survivors ahead, and the column it names k ahead.
  constexpr std::size_t k = 8;
  const std::size_t n = out.records.size();
  for (std::size_t i = 0; i < std::min(n, 2 * k); ++i) store_->prefetch_pending(out.stats[i]);
  for (std::size_t i = 0; i < std::min(n, k); ++i) store_->prefetch_pending_column(out.stats[i]);
  for (std::size_t i = 0; i < n; ++i) {
    if (i + 2 * k < n) store_->prefetch_pending(out.stats[i + 2 * k]);
    if (i + k < n) store_->prefetch_pending_column(out.stats[i + k]);
    const float* col = out.column(i);
    const ColumnStats& st = out.stats[i];
    const ClassRecord& rec = out.records[i];
    const int level = rec.cost;
    const auto L = static_cast<std::size_t>(level);
    if (out.improves[i] >= 0) {  // a cheaper recipe for a committed class: applied after the batch
      const auto id = static_cast<std::uint32_t>(out.improves[i]);
      if (!improved_.insert(id).second) {  // the first in merge order wins
        out.spare.push_back(const_cast<float*>(col));
        continue;
      }
      deferred_.push_back({id, col, st, rec, out.fused[i], found_at + i});
      continue;
    }
    if (const std::int64_t p = store_->find_pending(col, st); p >= 0) {
      const auto id = static_cast<std::uint32_t>(p);
      const int old = store_->record(id).cost;
      if (old <= level) {  // workers checked the committed classes
        out.spare.push_back(const_cast<float*>(col));
        continue;
      }
      store_->improve(id, col, st, rec);  // a class of the next level, made earlier this batch
      moved_.emplace_back(id, old);
      if (track) found_at_[id] = found_at + i;
      if (materialize) continue;
      consider_for_front(id, st, level);
      if (out.fused[i].leaf >= 0) consider_fused_for_front(id, out.fused[i], level);
      continue;
    }
    if (store_->full()) {
      exhausted_.store(true, std::memory_order_relaxed);
      break;
    }
    const std::uint32_t id = store_->insert(col, st, rec);
    if (track) {
      found_at_.resize(store_->size(), 0);
      found_at_[id] = found_at + i;
    }
    level_ids_[L].push_back(id);
    if (rec.has(ClassRecord::kFusable)) fusable_ids_[L].push_back(id);
    if (materialize) {
      elite_levels_[L].push_back(
          {std::min(st.loss_pos, st.loss_neg), id, st.loss_neg < st.loss_pos});
      continue;
    }
    consider_for_front(id, st, level);
    if (out.fused[i].leaf >= 0) consider_fused_for_front(id, out.fused[i], level);
  }
  if (out.full) exhausted_.store(true, std::memory_order_relaxed);
}

void Enumerator::finish_improvements(bool materialize) {
  for (const Improvement& d : deferred_) {
    moved_.emplace_back(d.id, store_->record(d.id).cost);
    store_->improve(d.id, d.column, d.stats, d.record);
    if (d.id < found_at_.size()) found_at_[d.id] = d.found_at;
  }
  if (!moved_.empty()) {
    // Move each improved class to its new level's lists. A product whose new level's fused sums
    // are already classes keeps its place among the fusable classes of its former level, so that
    // its own sums are still made (one level late) when that level is materialised.
    std::vector<std::uint32_t> ids;
    for (const auto& [id, old] : moved_) ids.push_back(id);
    std::sort(ids.begin(), ids.end());
    const auto was_moved = [&](std::uint32_t id) {
      return std::binary_search(ids.begin(), ids.end(), id);
    };
    std::vector<int> olds;
    for (const auto& [id, old] : moved_) olds.push_back(old);
    std::sort(olds.begin(), olds.end());
    olds.erase(std::unique(olds.begin(), olds.end()), olds.end());
    for (const int old : olds) {
      const auto O = static_cast<std::size_t>(old);
      std::erase_if(level_ids_[O], was_moved);
      std::erase_if(fusable_ids_[O], [&](std::uint32_t id) {
        return was_moved(id) && !materialized_[store_->record(id).cost];
      });
    }
    for (const auto& [id, old] : moved_) {
      const ClassRecord& r = store_->record(id);
      level_ids_[r.cost].push_back(id);
      if (r.has(ClassRecord::kFusable) && !materialized_[r.cost])
        fusable_ids_[r.cost].push_back(id);
    }
  }
  if (!materialize) {
    for (const Improvement& d : deferred_) {
      consider_for_front(d.id, d.stats, d.record.cost);
      if (d.fused.leaf >= 0) consider_fused_for_front(d.id, d.fused, d.record.cost);
    }
  }
  deferred_.clear();
  moved_.clear();
  improved_.clear();
}

}  // namespace shaderfit::search_detail
