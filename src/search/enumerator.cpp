#include "search/enumerator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <thread>
#include <cstdio>  // DEBUG
#include <ctime>  // DEBUG
#include <cstdlib>  // DEBUG

#include "search/enum_costs.hpp"
#include "search/enum_tile.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/expr/simplify.hpp"

namespace shaderfit::search_detail {
int g_full_scores = 0;  // DEBUG

namespace {

// A class is scored on every row when its screen loss is within this factor of the best screen
// loss on the front at its cost or below. Both are measured on the same rows, so their ratio is
// far less noisy than either loss; see docs/search.md for the measured miss rate.
constexpr double kScreenMargin = 1.5;
// Elite classes kept per level as seeds for the evolution.
constexpr std::size_t kElitePerLevel = 64;

}  // namespace

Enumerator::Enumerator(SearchContext& ctx, Rng& rng)
    : ctx_(ctx), costs_(std::make_unique<Costs>(ctx.options)) {
  const SearchOptions& o = ctx.options;
  time_share_s_ = o.evolve ? o.max_enumeration_share * o.time_limit_s : o.time_limit_s;
  setup_screen(rng);
  store_ = std::make_unique<ClassStore>(screen_rows_, o.max_classes);
  const std::size_t levels = static_cast<std::size_t>(std::max(o.max_enumeration_cost, 0)) + 2;
  level_ids_.resize(levels);
  fusable_ids_.resize(levels);
  materialized_.assign(levels, false);
  elite_levels_.resize(levels);
  add_leaves();
}

Enumerator::~Enumerator() = default;

void Enumerator::setup_screen(Rng& rng) {
  const std::size_t rows = ctx_.rows;
  const std::size_t wanted = ctx_.options.screen_rows;
  std::vector<std::size_t> picked;
  if (rows <= wanted) {
    for (std::size_t i = 0; i < rows; ++i) picked.push_back(i);
  } else {
    // Partial Fisher-Yates: `wanted` distinct rows, uniformly; sorted for locality.
    std::vector<std::size_t> all(rows);
    for (std::size_t i = 0; i < rows; ++i) all[i] = i;
    for (std::size_t i = 0; i < wanted; ++i) {
      const std::size_t j = i + static_cast<std::size_t>(uniform_index(rng, rows - i));
      std::swap(all[i], all[j]);
    }
    picked.assign(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(wanted));
    std::sort(picked.begin(), picked.end());
  }
  const std::size_t real = picked.size();
  screen_rows_ = std::max<std::size_t>(kHashRows, (real + 7) / 8 * 8);
  while (picked.size() < screen_rows_) picked.push_back(picked.front());  // padding, weight 0
  screen_rows_picked_ = picked;

  const SearchProblem& p = ctx_.problem;
  const LossKind loss = ctx_.options.loss;
  screen_y_.resize(screen_rows_);
  screen_w_.resize(screen_rows_);
  screen_log2_y_.resize(screen_rows_);
  double sum_w = 0;
  for (std::size_t i = 0; i < screen_rows_; ++i) {
    const std::size_t r = picked[i];
    const double w = i < real ? (p.weights.empty() ? 1.0 : p.weights[r]) : 0.0;
    const double y = p.target[r];
    screen_y_[i] = static_cast<float>(y);
    screen_log2_y_[i] = y > 0 ? static_cast<float>(std::log2(y)) : 0.0f;
    double wi = w;
    if (loss == LossKind::Relative) wi = y != 0 ? w / (y * y) : 0.0;
    if (loss == LossKind::MaxAbs) wi = w > 0 ? 1.0 : 0.0;
    screen_w_[i] = static_cast<float>(wi);
    sum_w += w;
  }
  if (loss != LossKind::MaxAbs && sum_w > 0) {
    for (float& w : screen_w_) w = static_cast<float>(w / sum_w);
  }
  double wyy = 0;
  for (std::size_t i = 0; i < screen_rows_; ++i)
    wyy += static_cast<double>(screen_w_[i]) * screen_y_[i] * screen_y_[i];
  target_ = {screen_y_.data(), screen_w_.data(), screen_log2_y_.data(), wyy, loss, screen_rows_};
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
    const std::uint32_t id = store_->insert(col.data(), stats, rec);
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
    fs.leaf_values.push_back(literal ? static_cast<float>(lits[static_cast<std::size_t>(r.k)]) : 0.0f);
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
  if (ctx_.elapsed() >= time_share_s_) exhausted_.store(true, std::memory_order_relaxed);
  return exhausted_.load(std::memory_order_relaxed);
}

void Enumerator::run() {
  const int max_cost = ctx_.options.max_enumeration_cost;
  const bool deferred_fusion = costs_->eager_fusion();
  for (int level = cost_completed_ + 1; level <= max_cost; ++level) {
    if (enumeration_should_stop()) break;
    // Steps whose operands all come from below level - 1 need none of level - 1's fused sums:
    // they run before those are materialised. (Steps hold spans into the level lists, so the
    // late ones are made after the materialisation has grown them.)
    const auto early_of = [&](const Step& s) { return s.order < level - 1; };
    std::vector<Step> steps = make_steps(level);
    steps.erase(std::partition_point(steps.begin(), steps.end(), early_of), steps.end());
    run_batch(level, steps, false);
    if (deferred_fusion && level >= 2 && !enumeration_should_stop()) materialize_fused(level - 1);
    if (!enumeration_should_stop()) {
      steps = make_steps(level);
      steps.erase(steps.begin(), std::partition_point(steps.begin(), steps.end(), early_of));
      run_batch(level, steps, false);
    }
    auto& elite = elite_levels_[static_cast<std::size_t>(level)];
    if (elite.size() > kElitePerLevel) {
      std::nth_element(elite.begin(), elite.begin() + kElitePerLevel, elite.end());
      elite.resize(kElitePerLevel);
    }
    if (ctx_.stopped() || exhausted_.load(std::memory_order_relaxed)) break;
    cost_completed_ = level;
  }
}

void Enumerator::materialize_fused(int level) {
  const auto L = static_cast<std::size_t>(level);
  if (materialized_[L]) return;
  materialized_[L] = true;
  if (fusable_ids_[L].empty() || fused_leaf_ids_.empty()) return;
  Step s;
  s.kind = EKind::FusedAdd;
  s.a = fusable_ids_[L];
  s.b = fused_leaf_ids_;
  s.variants[1] = {false, false, true};
  s.variant_count = 2;
  s.order = level;
  run_batch(level, {s}, true);
}

void Enumerator::run_batch(int level, const std::vector<Step>& steps, bool materialize) {
  const std::vector<Tile> tiles = make_tiles(steps);
  const std::size_t n = tiles.size();
  if (n == 0) return;
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
    while (m < n && ready[m].load(std::memory_order_acquire) && !exhausted_.load(std::memory_order_relaxed)) {
      merge(level, *outputs[m], materialize);
      if (std::getenv("SF_DEBUG3") && (m + 1 == n || tiles[m + 1].step != tiles[m].step)) {
        const Step& st = steps[tiles[m].step];
        std::fprintf(stderr, "  L%d step %u done at %.1f ms: kind %d k %d |a|=%zu |b|=%zu order %d, candidates %llu\n", level, tiles[m].step, ctx_.elapsed() * 1e3, (int)st.kind, st.k, st.a.size(), st.b.size(), st.order, (unsigned long long)ctx_.candidates.load());
      }
      {
        std::lock_guard pl(pool_mutex);
        pool.push_back(std::move(outputs[m]));
      }
      merged.store(++m, std::memory_order_release);
    }
    ctx_.maybe_progress("enumeration");
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
      if (!out) out = std::make_unique<TileOutput>();
      out->clear(screen_rows_);
      const Tile& t = tiles[i];
      process_tile(level, steps[t.step], t, *out);
      ctx_.candidates.fetch_add(out->evaluated, std::memory_order_relaxed);
      ctx_.node_evaluations.fetch_add(out->evaluated * screen_rows_, std::memory_order_relaxed);
      outputs[i] = std::move(out);
      ready[i].store(true, std::memory_order_release);
    }
  };
  const std::uint32_t before = store_->size();
  const std::uint64_t cand_before = ctx_.candidates.load();
  const double t0 = ctx_.elapsed();
  timespec c0{}; clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
  parallel_for(threads, 1, worker, static_cast<int>(threads));
  store_->commit();
  if (std::getenv("SF_DEBUG")) {
    timespec c1{}; clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
    std::fprintf(stderr, "level %d%s: %zu steps, %zu tiles, %llu candidates -> %u classes (total %u), %.1f ms -> %.1f ms  cpu %.1f ms\n", level, materialize ? " (fused)" : "", steps.size(), n,
                 (unsigned long long)(ctx_.candidates.load() - cand_before), store_->size() - before, store_->size(), t0 * 1e3, ctx_.elapsed() * 1e3, (c1.tv_sec - c0.tv_sec) * 1e3 + (c1.tv_nsec - c0.tv_nsec) * 1e-6);
    std::fprintf(stderr, "   full scores so far: %d\n", g_full_scores);
    for (const Step& st : steps) std::fprintf(stderr, "    kind %d op %d k %d |a|=%zu |b|=%zu tri=%d var=%d order=%d\n", (int)st.kind, (int)st.op, st.k, st.a.size(), st.b.size(), (int)st.triangular, st.variant_count, st.order);
  }
}

void Enumerator::merge(int level, TileOutput& out, bool materialize) {
  const auto L = static_cast<std::size_t>(level);
  for (std::size_t i = 0; i < out.records.size(); ++i) {
    const float* col = out.column(i);
    const ColumnStats& st = out.stats[i];
    if (store_->find_pending(col, st) >= 0) continue;  // workers checked the committed classes
    if (store_->full()) {
      exhausted_.store(true, std::memory_order_relaxed);
      return;
    }
    const ClassRecord& rec = out.records[i];
    const std::uint32_t id = store_->insert(col, st, rec);
    level_ids_[L].push_back(id);
    if (rec.has(ClassRecord::kFusable)) fusable_ids_[L].push_back(id);
    if (materialize) {
      elite_levels_[L].push_back({std::min(st.loss_pos, st.loss_neg), id, st.loss_neg < st.loss_pos});
      continue;
    }
    consider_for_front(id, st, level);
    if (out.fused[i].leaf >= 0) consider_fused_for_front(id, out.fused[i], level);
  }
}

double Enumerator::front_threshold(int level) const {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [c, l] : screen_front_)
    if (c <= level) best = std::min(best, l);
  return kScreenMargin * best;
}

void Enumerator::consider_for_front(std::uint32_t id, const ColumnStats& stats, int level) {
  const float loss = std::min(stats.loss_pos, stats.loss_neg);
  auto& elite = elite_levels_[std::min(static_cast<std::size_t>(level), elite_levels_.size() - 1)];
  elite.push_back({loss, id, stats.loss_neg < stats.loss_pos});
  if (elite.size() >= 8 * kElitePerLevel) {
    std::nth_element(elite.begin(), elite.begin() + kElitePerLevel, elite.end());
    elite.resize(kElitePerLevel);
  }
  if (!(loss <= front_threshold(level))) return;
  const auto& names = ctx_.problem.input_names;
  const auto& lits = ctx_.options.literals;
  Expression e = build_class_expression(*store_, id, false, names, lits);
  offer_scored(e, [&] { return build_class_expression(*store_, id, true, names, lits); }, loss);
}

void Enumerator::consider_fused_for_front(std::uint32_t m, const FusedBest& best, int level) {
  if (!(best.loss <= front_threshold(level))) return;
  const auto& names = ctx_.problem.input_names;
  const auto& lits = ctx_.options.literals;
  const std::uint32_t leaf = fused_leaf_ids_[static_cast<std::size_t>(best.leaf)];
  Expression e = build_fused_expression(*store_, m, leaf, best.neg_leaf, false, names, lits);
  offer_scored(e, [&] { return build_fused_expression(*store_, m, leaf, best.neg_leaf, true, names, lits); },
               best.loss);
}

// Scores e on every row with both signs and offers the better one, tidied, to the front.
template <typename Negated>
void Enumerator::offer_scored(Expression e, Negated negated, float screen_loss) {
  ++g_full_scores;
  std::vector<double> f(ctx_.rows);
  ctx_.predict(e, f);
  const LossMetrics pos = ctx_.metrics_of(f);
  for (double& v : f) v = -v;
  const LossMetrics neg = ctx_.metrics_of(f);
  const LossKind kind = ctx_.options.loss;
  const bool negate = loss_value(kind, neg) < loss_value(kind, pos);
  if (negate) e = negated();
  Expression tidy = simplify(e);
  if (expression_cost(tidy, ctx_.options.cost) <= expression_cost(e, ctx_.options.cost)) e = std::move(tidy);
  const double cost = expression_cost(e, ctx_.options.cost);
  const double full = loss_value(kind, negate ? neg : pos);
  if (std::getenv("SF_DEBUG2")) std::fprintf(stderr, "full-score screen=%.3g full=%.3g ratio=%.3f best=%.3g\n", screen_loss, full, screen_loss / full, front_threshold(1000) / kScreenMargin);
  if (ctx_.offer(std::move(e), negate ? neg : pos, "enumeration")) screen_front_.emplace_back(cost, screen_loss);
}

std::vector<Expression> Enumerator::seeds(std::size_t count) const {
  std::vector<std::vector<Elite>> levels;
  for (auto lv : elite_levels_) {
    std::sort(lv.begin(), lv.end());
    if (!lv.empty()) levels.push_back(std::move(lv));
  }
  std::vector<Expression> out;
  for (std::size_t rank = 0; out.size() < count; ++rank) {
    bool any = false;
    for (const auto& lv : levels) {
      if (rank >= lv.size() || out.size() >= count) continue;
      any = true;
      const std::uint32_t id = lv[rank].id;
      if (store_->record(id).kind == EKind::Literal) continue;
      out.push_back(build_class_expression(*store_, id, lv[rank].negate, ctx_.problem.input_names,
                                           ctx_.options.literals));
    }
    if (!any) break;
  }
  return out;
}

}  // namespace shaderfit::search_detail
