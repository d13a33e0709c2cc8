// From enumerated classes to front members: the screen threshold, a float32 check on every
// row, then the exact formula, scored in float64 and offered to the front.
#include <algorithm>
#include <cmath>
#include <limits>

#include "search/enumeration/enum_costs.hpp"
#include "search/enumeration/enumerator.hpp"
#include "shaderfit/expr/simplify.hpp"

namespace shaderfit::search_detail {

namespace {

// A class whose screen loss is within this factor of the best screen loss on the front (at its
// cost or below) is checked on every row. Both are measured on the same rows, so the ratio is
// much steadier than either loss; the all-rows check below is cheap, so the factor is generous.
constexpr double kScreenMargin = 3.0;
// The float32 all-rows loss must be within this factor of the front's loss at the class's cost
// for the exact float64 scoring (float32 sums of squares are good to well under 1%).
constexpr double kFloatMargin = 1.02;
constexpr std::size_t kElitePerLevel = 64;

}  // namespace

void Enumerator::setup_full_rows() {
  const SearchProblem& p = ctx_.problem;
  const std::size_t rows = ctx_.rows;
  FullRows& f = full_;
  f.n = std::max<std::size_t>(kMinScreenRows, (rows + 7) / 8 * 8);
  auto padded = [&](const std::vector<double>& v) {
    std::vector<float> out(f.n);
    for (std::size_t i = 0; i < f.n; ++i) out[i] = static_cast<float>(v[i < rows ? i : 0]);
    return out;
  };
  for (const auto& c : p.inputs) f.inputs.push_back(padded(c));
  // The uniform terminals' columns, past the inputs (their Var leaves' k).
  std::vector<double> values(rows);
  for (const Expression& t : ctx_.terminals) {
    ctx_.predict(t, values);
    f.inputs.push_back(padded(values));
  }
  for (double v : ctx_.options.literals) f.literals.emplace_back(f.n, static_cast<float>(v));
  f.y = padded(p.target);
  f.w.assign(f.n, 0.0f);
  f.log2_y.assign(f.n, 0.0f);
  const Loss loss = ctx_.options.loss;
  double sum_w = 0;
  for (std::size_t i = 0; i < rows; ++i) sum_w += p.weights.empty() ? 1.0 : p.weights[i];
  f.wyy = 0;
  for (std::size_t i = 0; i < rows; ++i) {
    const double w = p.weights.empty() ? 1.0 : p.weights[i];
    const double y = p.target[i];
    double wi = screen_weight(loss, w, y);
    if (screen_loss(loss) != Loss::MaxAbs) wi /= sum_w;
    if (loss == Loss::Relative && !relative_screen_row(y)) {
      wi = 0;
      f.y[i] = 1.0f;
    }
    f.w[i] = static_cast<float>(wi);
    f.log2_y[i] = y > 0 ? static_cast<float>(std::log2(y)) : 0.0f;
    f.wyy += wi * static_cast<double>(f.y[i]) * f.y[i];
  }
  f.target = {f.y.data(), f.w.data(), f.log2_y.data(), f.wyy, screen_loss(loss), f.n};
}

// Class `id` on every row, in float32, by the same kernels as its screen column; each operator
// node takes the next scratch column (reset by full_column).
const float* Enumerator::full_eval(std::uint32_t id) {
  const ClassRecord& r = store_->record(id);
  if (r.kind == EKind::Var) return full_.inputs[static_cast<std::size_t>(r.k)].data();
  if (r.kind == EKind::Literal) return full_.literals[static_cast<std::size_t>(r.k)].data();
  const float* a = full_eval(r.a);
  const bool unary = r.kind == EKind::Unary || r.kind == EKind::IPow;
  const float* b = unary ? nullptr : full_eval(r.b);
  float* out = scratch_column();
  compute_column(r.kind, r.op, r.k, a, b, r.has(ClassRecord::kNegA), r.has(ClassRecord::kNegB), out,
                 full_.n);
  return out;
}

const float* Enumerator::full_column(std::uint32_t id) {
  full_.next = 0;
  return full_eval(id);
}

float* Enumerator::scratch_column() {
  if (full_.next == full_.scratch.size()) full_.scratch.emplace_back(full_.n);
  return full_.scratch[full_.next++].data();
}

double Enumerator::front_threshold(int level) const {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [c, l] : screen_front_)
    if (c <= level) best = std::min(best, l);
  return kScreenMargin * best;
}

bool Enumerator::passes_full_rows(const float* column, int level) {
  ColumnStats s;
  column_loss(column, full_.target, &s);
  if (!s.valid) return false;  // NaN or infinite on a row outside the screen
  return std::min(s.loss_pos, s.loss_neg) <= kFloatMargin * ctx_.front.best_loss_at(level);
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
  const EKind kind = store_->record(id).kind;
  const bool leaf = kind == EKind::Var || kind == EKind::Literal;  // (a literal is constant)
  if (!leaf && !passes_full_rows(full_column(id), level)) return;
  const auto& names = ctx_.problem.input_names;
  const auto& lits = ctx_.options.literals;
  const auto& terms = ctx_.terminals;
  Expression e = build_class_expression(*store_, id, false, names, lits, terms);
  offer_scored(
      e, [&] { return build_class_expression(*store_, id, true, names, lits, terms); }, loss);
}

void Enumerator::consider_fused_for_front(std::uint32_t m, const FusedBest& best, int level) {
  if (!(best.loss <= front_threshold(level))) return;
  const std::uint32_t leaf = fused_leaf_ids_[static_cast<std::size_t>(best.leaf)];
  const float* mc = full_column(m);
  float* sum = scratch_column();
  const float* c = full_eval(leaf);  // a leaf: its column, no scratch
  compute_column(EKind::FusedAdd, Op::Const, 0, mc, c, false, best.neg_leaf, sum, full_.n);
  if (!passes_full_rows(sum, level)) return;
  const auto& names = ctx_.problem.input_names;
  const auto& lits = ctx_.options.literals;
  const auto& terms = ctx_.terminals;
  Expression e = build_fused_expression(*store_, m, leaf, best.neg_leaf, false, names, lits, terms);
  offer_scored(
      e,
      [&] {
        return build_fused_expression(*store_, m, leaf, best.neg_leaf, true, names, lits, terms);
      },
      best.loss);
}

// Scores e on every row with both signs and offers the better one, tidied, to the front.
template <typename Negated>
void Enumerator::offer_scored(Expression e, Negated negated, float screen_loss) {
  std::vector<double> f(ctx_.rows);
  ctx_.predict(e, f);
  const Loss kind = ctx_.options.loss;
  const auto& target = ctx_.problem.target;
  const auto& weights = ctx_.problem.weights;
  const double pos = loss_of(kind, f, target, weights);
  for (double& v : f) v = -v;
  const double neg = loss_of(kind, f, target, weights);
  const bool negate = neg < pos;
  if (!negate)
    for (double& v : f) v = -v;
  if (negate) e = negated();
  Expression tidy = simplify(e);
  if (formula_cost(tidy, ctx_.options) <= formula_cost(e, ctx_.options)) e = std::move(tidy);
  const double cost = formula_cost(e, ctx_.options);
  if (!ctx_.front.would_enter(cost, std::min(pos, neg))) return;  // every metric only for entrants
  if (ctx_.offer(std::move(e), std::min(pos, neg), SearchPhase::Enumeration))
    screen_front_.emplace_back(cost, screen_loss);
}

void Enumerator::prune_elite(int level) {
  auto& elite = elite_levels_[static_cast<std::size_t>(level)];
  if (elite.size() > kElitePerLevel) {
    std::nth_element(elite.begin(), elite.begin() + kElitePerLevel, elite.end());
    elite.resize(kElitePerLevel);
  }
}

std::vector<Expression> Enumerator::seeds(std::size_t count) const {
  std::vector<std::vector<Elite>> levels;
  for (auto lv : elite_levels_) {
    std::sort(lv.begin(), lv.end());
    if (!lv.empty()) levels.push_back(std::move(lv));
  }
  std::vector<std::size_t> sizes;
  for (const auto& lv : levels) sizes.push_back(lv.size());
  return pick_seeds(sizes, count, [&](std::size_t level, std::size_t k) -> std::optional<Expression> {
    const Elite& e = levels[level][k];
    if (store_->record(e.id).kind == EKind::Literal) return std::nullopt;
    return build_class_expression(*store_, e.id, e.negate, ctx_.problem.input_names,
                                  ctx_.options.literals, ctx_.terminals);
  });
}

}  // namespace shaderfit::search_detail
