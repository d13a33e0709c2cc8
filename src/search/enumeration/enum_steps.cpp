// What the enumeration computes at each cost level (steps), how that work is cut into tiles, and
// the computation of one tile.
#include <algorithm>
#include <cmath>

#include "search/enumeration/enum_costs.hpp"
#include "search/enumeration/enum_tile.hpp"
#include "search/enumeration/enumerator.hpp"

namespace shaderfit::search_detail {

namespace {

using Variant = Enumerator::Variant;

constexpr std::size_t kUnaryTile = 1024;     // classes per tile of a unary step
constexpr std::size_t kPairsPerTile = 2048;  // candidates per tile of a binary step, about
constexpr std::size_t kTriangleBlock = 48;   // a x a blocks when both operands share a level

// The operand orders and signs tried for each unordered pair {a, b}; negating the result is
// free, so a - b stands for b - a too.
int pair_variants(EKind kind, Variant* v) {
  switch (kind) {
    case EKind::AddSub:
    case EKind::FusedAdd:
    case EKind::Min:
    case EKind::Max:
      v[0] = {};
      v[1] = {false, false, true};
      return 2;
    case EKind::Div:
    case EKind::CopySign:  // copysign(b, a) too; signs are free (a's is dropped, b's negates)
      v[0] = {};
      v[1] = {true, false, false};
      return 2;
    case EKind::Pow:
    case EKind::Atan2:  // both orders, and b's sign (a's: the result's, free)
      v[0] = {};
      v[1] = {false, false, true};
      v[2] = {true, false, false};
      v[3] = {true, false, true};
      return 4;
    default: v[0] = {}; return 1;
  }
}

}  // namespace

void Enumerator::make_literal_groups() {
  const SearchOptions& o = ctx_.options;
  struct Form {
    EKind kind;
    Op op;
    bool left;
    Variant variants[2];
    int count;
  };
  std::vector<Form> forms;
  const auto on = [&](Op op) { return costs_->binary[static_cast<int>(op)] >= 0; };
  if (on(Op::Add)) forms.push_back({EKind::AddSub, Op::Add, false, {{}, {false, false, true}}, 2});
  if (on(Op::Mul)) forms.push_back({EKind::Mul, Op::Mul, false, {{}, {}}, 1});
  if (on(Op::Div)) {
    forms.push_back({EKind::Div, Op::Div, false, {{}, {}}, 1});
    forms.push_back({EKind::Div, Op::Div, true, {{true, false, false}, {}}, 1});
  }
  if (on(Op::Min)) forms.push_back({EKind::Min, Op::Min, false, {{}, {false, false, true}}, 2});
  if (on(Op::Max)) forms.push_back({EKind::Max, Op::Max, false, {{}, {false, false, true}}, 2});
  if (on(Op::Pow)) {
    forms.push_back({EKind::Pow, Op::Pow, false, {{}, {false, false, true}}, 2});
    forms.push_back({EKind::Pow, Op::Pow, true, {{true, false, false}, {true, false, true}}, 2});
  }
  for (const Form& f : forms) {
    std::vector<LiteralGroup> groups;
    for (std::size_t l = 0; l < literal_ids_.size(); ++l) {
      const double v = o.literals[l];
      if (v == 0.0) continue;
      const bool unit = std::abs(v) == 1.0;
      if (unit && (f.kind == EKind::Mul || (f.kind == EKind::Div && !f.left)))
        continue;  // a * 1, a / 1
      // a / c is a * (1 / c) at the same cost: skip it when 1 / c is a literal too (and products
      // are enumerated).
      if (f.kind == EKind::Div && !f.left && on(Op::Mul) &&
          std::any_of(o.literals.begin(), o.literals.end(),
                      [&](double u) { return std::abs(u * v) == 1.0; }))
        continue;
      const int inc = Costs::literal_increment(o, f.op, v, f.left);
      auto g = std::find_if(groups.begin(), groups.end(),
                            [&](const LiteralGroup& x) { return x.increment == inc; });
      if (g == groups.end()) {
        LiteralGroup ng;
        ng.kind = f.kind;
        ng.increment = inc;
        ng.variants[0] = f.variants[0];
        ng.variants[1] = f.variants[1];
        ng.variant_count = f.count;
        groups.push_back(ng);
        g = groups.end() - 1;
      }
      g->ids.push_back(literal_ids_[l]);
    }
    for (auto& g : groups) costs_->literal_groups.push_back(std::move(g));
  }
  for (std::size_t l = 0; l < literal_ids_.size(); ++l)
    if (o.literals[l] != 0.0) fused_leaf_ids_.push_back(literal_ids_[l]);
  fused_leaf_ids_.insert(fused_leaf_ids_.begin(), var_ids_.begin(), var_ids_.end());
}

std::vector<Enumerator::Step> Enumerator::make_steps(int level) const {
  const Costs& c = *costs_;
  std::vector<Step> steps;
  Step proto;
  proto.level = level;
  const auto at = [&](int cost) -> std::span<const std::uint32_t> {
    if (cost < 0 || cost >= level) return {};
    return level_ids_[static_cast<std::size_t>(cost)];
  };
  for (int o = 0; o < kOpCount; ++o) {
    const int d = c.unary[static_cast<std::size_t>(o)];
    if (d < 0 || at(level - d).empty()) continue;
    Step s = proto;
    s.kind = EKind::Unary;
    s.op = static_cast<Op>(o);
    s.a = at(level - d);
    s.order = level - d;
    s.variants[0] = {};
    s.variant_count = 1;
    if (sign_sensitive(s.op)) {
      s.variants[1] = {false, true, false};
      s.variant_count = 2;
    }
    steps.push_back(s);
  }
  for (const auto& [k, d] : c.powers) {
    if (at(level - d).empty()) continue;
    Step s = proto;
    s.kind = EKind::IPow;
    s.k = k;
    s.a = at(level - d);
    s.order = level - d;
    steps.push_back(s);
  }
  const std::pair<EKind, Op> binaries[] = {
      {EKind::AddSub, Op::Add},        {EKind::Mul, Op::Mul},    {EKind::Div, Op::Div},
      {EKind::Min, Op::Min},           {EKind::Max, Op::Max},    {EKind::Pow, Op::Pow},
      {EKind::CopySign, Op::CopySign}, {EKind::Atan2, Op::Atan2}};
  for (const auto& [kind, op] : binaries) {
    const int d = c.binary[static_cast<std::size_t>(op)];
    if (d < 0) continue;
    const int total = level - d;
    for (int i = 0; 2 * i <= total; ++i) {
      const int j = total - i;
      if (at(i).empty() || at(j).empty()) continue;
      Step s = proto;
      s.kind = kind;
      s.a = at(i);
      s.b = at(j);
      s.triangular = i == j;
      s.variant_count = pair_variants(kind, s.variants);
      s.order = j;
      steps.push_back(s);
    }
  }
  for (const LiteralGroup& g : c.literal_groups) {
    if (at(level - g.increment).empty()) continue;
    Step s = proto;
    s.kind = g.kind;
    s.a = at(level - g.increment);
    s.b = g.ids;
    s.variants[0] = g.variants[0];
    s.variants[1] = g.variants[1];
    s.variant_count = g.variant_count;
    s.order = level - g.increment;
    steps.push_back(s);
  }
  if (c.fused >= 0) {
    for (int m = 1; m < level; ++m) {
      std::span<const std::uint32_t> products = fusable_ids_[static_cast<std::size_t>(m)];
      if (products.empty()) continue;
      Step s = proto;
      s.kind = EKind::FusedAdd;
      s.a = products;
      s.variant_count = pair_variants(EKind::FusedAdd, s.variants);
      if (!at(level - m - c.fused).empty()) {
        s.b = at(level - m - c.fused);
        s.order = std::max(m, level - m - c.fused);
        steps.push_back(s);
      }
      if (!c.eager_fusion() && m + c.fused + c.literal == level && !literal_ids_.empty()) {
        s.b = literal_ids_;
        s.order = m;
        steps.push_back(s);
      }
    }
  }
  // By the costliest operand's level (the batches need that), then smallest step first: the
  // many small steps finish early, which is where most distinct formulas per unit of work are.
  const auto work = [](const Step& x) {
    const std::size_t pairs = x.triangular ? x.a.size() * (x.a.size() - 1) / 2
                                           : x.a.size() * std::max<std::size_t>(x.b.size(), 1);
    return pairs * static_cast<std::size_t>(x.variant_count);
  };
  std::stable_sort(steps.begin(), steps.end(), [&](const Step& x, const Step& y) {
    return x.order != y.order ? x.order < y.order : work(x) < work(y);
  });
  return steps;
}

std::vector<Enumerator::Tile> Enumerator::make_tiles(const std::vector<Step>& steps,
                                                     std::size_t* complete) const {
  std::vector<Tile> tiles;
  std::vector<std::uint32_t> rank;  // the tile's place in its step's order
  std::vector<std::uint8_t> phase;  // 0: a next level's first tiles, 1: the level's, 2: the rest
  std::vector<Tile> own;
  for (std::size_t si = 0; si < steps.size(); ++si) {
    const Step& s = steps[si];
    const auto id = static_cast<std::uint32_t>(si);
    const std::size_t na = s.a.size(), nb = s.b.size();
    own.clear();
    if (nb == 0) {
      for (std::size_t a0 = 0; a0 < na; a0 += kUnaryTile)
        own.push_back({id, static_cast<std::uint32_t>(a0),
                       static_cast<std::uint32_t>(std::min(na, a0 + kUnaryTile)), 0, 1});
    } else {
      // Blocks of about kPairsPerTile candidates, in diagonal order (by the sum of the block's
      // indices along a and b): the pairs of both lists' earliest classes come first.
      const std::size_t bb = std::min<std::size_t>(nb, s.triangular ? kTriangleBlock : 64);
      const std::size_t ba =
          s.triangular ? bb
                       : std::max<std::size_t>(
                             1, kPairsPerTile / (bb * static_cast<std::size_t>(s.variant_count)));
      const std::size_t blocks_a = (na + ba - 1) / ba, blocks_b = (nb + bb - 1) / bb;
      for (std::size_t d = 0; d + 1 < blocks_a + blocks_b; ++d) {
        for (std::size_t i = d >= blocks_b ? d - blocks_b + 1 : 0; i <= d && i < blocks_a; ++i) {
          const std::size_t j = d - i;
          const std::size_t a0 = i * ba, b0 = j * bb;
          if (s.triangular && b0 + bb <= a0) continue;  // below the diagonal: no pair i < j
          own.push_back({id, static_cast<std::uint32_t>(a0),
                         static_cast<std::uint32_t>(std::min(na, a0 + ba)),
                         static_cast<std::uint32_t>(b0),
                         static_cast<std::uint32_t>(std::min(nb, b0 + bb))});
        }
      }
    }
    // The next level's first tiles lead (they are few, and the next level's cheapest formulas
    // are likely the best new ones); its other tiles wait until this level is complete.
    for (std::size_t k = 0; k < own.size(); ++k) {
      tiles.push_back(own[k]);
      rank.push_back(static_cast<std::uint32_t>(k));
      phase.push_back(!s.next_level ? 1 : k < kHeadTiles ? 0 : 2);
    }
  }
  // Round robin over the steps: the k-th tiles of all steps before any (k+1)-th. Each step's
  // first tiles combine its operands' earliest (simplest) classes, where good formulas are most
  // often found, so no large step delays the first tiles of the steps after it.
  std::vector<std::size_t> order(tiles.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  // The trailing tiles go step by step, smallest step first (make_steps' order), so that small
  // steps complete early.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    if (phase[x] != phase[y]) return phase[x] < phase[y];
    return phase[x] == 2 ? tiles[x].step < tiles[y].step : rank[x] < rank[y];
  });
  *complete = static_cast<std::size_t>(
      std::count_if(phase.begin(), phase.end(), [](std::uint8_t p) { return p < 2; }));
  std::vector<Tile> sorted;
  sorted.reserve(tiles.size());
  for (const std::size_t i : order) sorted.push_back(tiles[i]);
  return sorted;
}

void Enumerator::process_tile(const Step& s, const Tile& t, TileOutput& out) const {
  const int level = s.level;
  out.screen_sums = costs_->eager_fusion() && s.kind != EKind::FusedAdd;
  const bool skip_fusable_sums = costs_->fused >= 0 && s.kind == EKind::AddSub;
  for (std::uint32_t ia = t.a0; ia < t.a1; ++ia) {
    const std::uint32_t ida = s.a[ia];
    const ClassRecord& ra = store_->record(ida);
    if (skip_fusable_sums && ra.has(ClassRecord::kFusable)) continue;  // m + b is one FMA
    ClassRecord rec = make_record(s.kind, static_cast<std::uint16_t>(level));
    rec.op = s.op;
    rec.k = static_cast<std::int8_t>(s.k);
    if (s.b.empty()) {
      for (int v = 0; v < s.variant_count; ++v) {
        rec.a = ida;
        rec.flags = s.variants[v].neg_a ? ClassRecord::kNegA : 0;
        stage(rec, store_->column(ida), nullptr, s.variants[v].neg_a, false, out);
      }
      continue;
    }
    for (std::uint32_t ib = t.b0; ib < t.b1; ++ib) {
      if (s.triangular && ib <= ia) continue;
      const std::uint32_t idb = s.b[ib];
      const ClassRecord& rb = store_->record(idb);
      if (skip_fusable_sums && rb.has(ClassRecord::kFusable)) continue;
      if (s.kind == EKind::FusedAdd && rb.has(ClassRecord::kFusable) &&
          (rb.cost < ra.cost || (rb.cost == ra.cost && idb <= ida)))
        continue;  // the pair with b as the product is (or was) enumerated
      for (int v = 0; v < s.variant_count; ++v) {
        const Variant& var = s.variants[v];
        rec.a = var.swap ? idb : ida;
        rec.b = var.swap ? ida : idb;
        rec.flags = var.neg_b ? ClassRecord::kNegB : 0;
        stage(rec, store_->column(rec.a), store_->column(rec.b), false, var.neg_b, out);
      }
    }
  }
  check_staged(out);
  out.fused.resize(out.records.size());
}

void Enumerator::stage(const ClassRecord& rec, const float* a, const float* b, bool neg_a,
                       bool neg_b, TileOutput& out) const {
  if (out.full) return;  // the column arena is spent: the enumeration ends
  const std::size_t n = screen_rows_;
  TileOutput::Staged& c = out.staged[out.staged_count];
  float* dst = out.staging.data() + out.staged_count * n;
  compute_column(rec.kind, rec.op, rec.k, a, b, neg_a, neg_b, dst, n);
  ++out.evaluated;
  c.record = rec;
  c.stats = ColumnStats{};
  column_key(dst, n, &c.stats);
  store_->prefetch_committed(c.stats);
  if (++out.staged_count == TileOutput::kStaged) check_staged(out);
}

void Enumerator::check_staged(TileOutput& out) const {
  const std::size_t k = out.staged_count;
  // The slots were asked for as the candidates were staged; now the columns they name.
  for (std::size_t i = 0; i < k; ++i) store_->prefetch_committed_column(out.staged[i].stats);
  for (std::size_t i = 0; i < k; ++i)
    check(out.staged[i].record, out.staged[i].stats, out.staging.data() + i * screen_rows_, out);
  out.staged_count = 0;
}

void Enumerator::check(const ClassRecord& rec_in, const ColumnStats& stats, const float* column,
                       TileOutput& out) const {
  const std::size_t n = screen_rows_;
  ColumnStats st = stats;
  std::int64_t improves = -1;
  if (const std::int64_t hit = store_->find_committed(column, st); hit >= 0) {
    // A committed class of a higher cost (made by the previous batch's steps of the next level,
    // see run()) gets this cheaper recipe; otherwise the candidate is a duplicate.
    if (store_->record(static_cast<std::uint32_t>(hit)).cost <= rec_in.cost) return;
    improves = hit;
  }
  const std::size_t mask = out.table.size() - 1;
  const std::uint64_t fp = st.hash >> 32;
  std::size_t slot = st.hash & mask;
  for (;; slot = (slot + 1) & mask) {
    const std::uint64_t v = out.table[slot];
    if (v == 0) break;
    if ((v >> 32) != fp) continue;
    const std::size_t j = static_cast<std::size_t>(v & 0xffffffffu) - 1;
    const bool negate = out.stats[j].canonical_neg != st.canonical_neg;
    if (columns_equivalent(column, out.column(j), negate, std::max(st.scale, out.stats[j].scale),
                           n))
      return;
  }
  column_loss(column, target_, &st);  // only for candidates that are new
  if (!st.valid) return;
  float* dst = out.next_column();
  if (dst == nullptr) {  // the column arena is spent: the enumeration ends
    out.full = true;
    return;
  }
  std::copy(column, column + n, dst);
  const std::size_t idx = out.records.size();
  out.table[slot] = (fp << 32) | (idx + 1);
  ClassRecord rec = rec_in;
  if (fusable(rec)) rec.flags |= ClassRecord::kFusable;
  out.records.push_back(rec);
  out.stats.push_back(st);
  out.improves.push_back(improves);
  out.keep_column();
  if (2 * out.records.size() > out.table.size()) {  // keep the local table at most half full
    std::vector<std::uint64_t> bigger(2 * out.table.size(), 0);
    const std::size_t m2 = bigger.size() - 1;
    for (std::size_t i = 0; i < out.records.size(); ++i) {
      std::size_t p = out.stats[i].hash & m2;
      while (bigger[p] != 0) p = (p + 1) & m2;
      bigger[p] = ((out.stats[i].hash >> 32) << 32) | (i + 1);
    }
    out.table.swap(bigger);
  }
  if (out.screen_sums && rec.has(ClassRecord::kFusable)) {
    out.fused.resize(out.records.size());
    out.fused[idx] = screen_fused_sums(out.column(idx), out);
  }
}

FusedBest Enumerator::screen_fused_sums(const float* m, TileOutput& out) const {
  const std::size_t leaves = fused_leaf_ids_.size();
  out.evaluated += 2 * leaves;     // m + c and m - c for each leaf (their negations come free)
  const Loss loss = target_.loss;  // the screening's
  if (loss == Loss::Mse || loss == Loss::Rmse) return screen_fused(m, fused_screen_);
  // No closed form (rel would need the sums over w / y^2, which overflow float32 on a high
  // dynamic range): compute each sum's column and analyse it.
  FusedBest best;
  for (std::size_t j = 0; j < leaves; ++j) {
    for (const bool nb : {false, true}) {
      compute_column(EKind::FusedAdd, Op::Const, 0, m, store_->column(fused_leaf_ids_[j]), false,
                     nb, out.scratch.data(), screen_rows_);
      const ColumnStats st = analyze_column(out.scratch.data(), target_);
      if (!st.valid) continue;
      const float l = std::min(st.loss_pos, st.loss_neg);
      if (l < best.loss) best = {l, static_cast<std::int16_t>(j), nb, st.loss_neg < st.loss_pos};
    }
  }
  return best;
}

}  // namespace shaderfit::search_detail
