#include "shaderfit/search/symmetry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <span>
#include <tuple>

#include "shaderfit/core/error.hpp"
#include "shaderfit/search/options.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {

namespace {

constexpr std::size_t kMinPairs = 8;

struct Pairs {
  std::vector<std::pair<std::size_t, std::size_t>> mirrored;  // (row with -x, row with x), x > 0
  std::vector<std::size_t> zero;                              // rows with x = 0
};

// The rows of `problem` matched in mirrored pairs in input k, or nullopt when some row has no
// mirror or two rows are alike.
std::optional<Pairs> mirrored_pairs(const SearchProblem& problem, std::size_t k) {
  const auto& inputs = problem.inputs;
  const std::vector<double>& x = inputs[k];
  // Cheap first: as many rows below 0 as above (most data fails here, before any sorting).
  const auto below = std::count_if(x.begin(), x.end(), [](double v) { return v < 0; });
  const auto above = std::count_if(x.begin(), x.end(), [](double v) { return v > 0; });
  if (below != above || static_cast<std::size_t>(below) < kMinPairs) return std::nullopt;
  std::vector<std::size_t> order(x.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  // By the other inputs, then |x|, then x: a row and its mirror end up side by side.
  auto less = [&](std::size_t a, std::size_t b) {
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      if (i == k) continue;
      if (inputs[i][a] != inputs[i][b]) return inputs[i][a] < inputs[i][b];
    }
    if (std::abs(x[a]) != std::abs(x[b])) return std::abs(x[a]) < std::abs(x[b]);
    return x[a] < x[b];
  };
  std::sort(order.begin(), order.end(), less);
  auto same_rest = [&](std::size_t a, std::size_t b) {
    for (std::size_t i = 0; i < inputs.size(); ++i)
      if (i != k && inputs[i][a] != inputs[i][b]) return false;
    return true;
  };
  Pairs p;
  std::size_t j = 0;
  while (j < order.size()) {
    const std::size_t a = order[j];
    if (x[a] == 0) {
      if (j + 1 < order.size() && x[order[j + 1]] == 0 && same_rest(a, order[j + 1]))
        return std::nullopt;  // two rows alike
      p.zero.push_back(a);
      j += 1;
      continue;
    }
    if (j + 1 >= order.size()) return std::nullopt;
    const std::size_t b = order[j + 1];
    if (!(x[a] < 0 && x[b] == -x[a] && same_rest(a, b))) return std::nullopt;
    if (j + 2 < order.size() && same_rest(b, order[j + 2]) && std::abs(x[order[j + 2]]) == x[b])
      return std::nullopt;  // a third row at +-x
    p.mirrored.emplace_back(a, b);
    j += 2;
  }
  return p;
}

// The kind, m and sign (DataSymmetry) of the target on the pairs, or nullopt.
std::optional<SymmetryKind> target_symmetry(const SearchProblem& problem, const Pairs& p,
                                            double tolerance, double* center, int* sign) {
  const std::vector<double>& y = problem.target;
  const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
  const double tol = tolerance * (*hi - *lo);
  if (!(tol > 0)) return std::nullopt;  // a constant target
  auto all_pairs = [&](auto ok) {
    return std::all_of(p.mirrored.begin(), p.mirrored.end(),
                       [&](const auto& ab) { return ok(y[ab.first], y[ab.second]); });
  };
  auto all_zero = [&](auto ok) {
    return std::all_of(p.zero.begin(), p.zero.end(), [&](std::size_t r) { return ok(y[r]); });
  };
  *center = 0;
  *sign = 1;
  // The sign of y - m on the half (x > 0: the pairs' second rows; x = 0, where it is ~0).
  auto half_sign = [&](double m) {
    auto all_half = [&](auto ok) {
      return std::all_of(p.mirrored.begin(), p.mirrored.end(),
                         [&](const auto& ab) { return ok(y[ab.second] - m); });
    };
    if (all_half([&](double t) { return t >= -tol; })) return 1;
    if (all_half([&](double t) { return t <= tol; })) return -1;
    return 0;
  };
  if (all_pairs([&](double n, double q) { return std::abs(n - q) <= tol; }))
    return SymmetryKind::Even;
  if (all_pairs([&](double n, double q) { return std::abs(n + q) <= tol; }) &&
      all_zero([&](double v) { return std::abs(v) <= tol; })) {
    *sign = half_sign(0);
    return SymmetryKind::Odd;
  }
  // m: the target at x = 0 where the data has it (acos(0) = pi/2 to the last bit), else the
  // mean of the pairs' midpoints (as offsets from the first, to keep the rounding small).
  const auto& zero = p.zero;
  const double base =
      zero.empty() ? 0.5 * (y[p.mirrored[0].first] + y[p.mirrored[0].second]) : y[zero[0]];
  double sum = 0;
  if (zero.empty())
    for (const auto& [n, q] : p.mirrored) sum += 0.5 * (y[n] + y[q]) - base;
  else
    for (std::size_t r : zero) sum += y[r] - base;
  const double m = base + sum / static_cast<double>(zero.empty() ? p.mirrored.size() : zero.size());
  if (all_pairs([&](double n, double q) { return std::abs(n + q - 2 * m) <= tol; }) &&
      all_zero([&](double v) { return std::abs(v - m) <= tol; })) {
    *center = m;
    *sign = half_sign(m);
    return SymmetryKind::Point;
  }
  return std::nullopt;
}

bool weights_mirrored(const SearchProblem& problem, const Pairs& p) {
  if (problem.weights.empty()) return true;
  const std::vector<double>& w = problem.weights;
  return std::all_of(p.mirrored.begin(), p.mirrored.end(), [&](const auto& ab) {
    return std::abs(w[ab.first] - w[ab.second]) <= 1e-12 * std::max(w[ab.first], w[ab.second]);
  });
}

// The residual (symmetry.hpp) of y at x and n at -x under `kind` about m.
double mirror_residual(SymmetryKind kind, double y, double n, double m) {
  switch (kind) {
    case SymmetryKind::Even: return y - n;
    case SymmetryKind::Odd: return y + n;
    case SymmetryKind::Point: return (y - m) + (n - m);
  }
  return y - n;
}

// The evidence of a symmetry found on mirrored pairs.
SymmetryEvidence pairs_evidence(const SearchProblem& problem, const Pairs& p, SymmetryKind kind,
                                double center) {
  const std::vector<double>& y = problem.target;
  const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
  double worst = 0;
  for (const auto& [n, q] : p.mirrored)
    worst = std::max(worst, std::abs(mirror_residual(kind, y[q], y[n], center)));
  if (kind != SymmetryKind::Even)
    for (std::size_t r : p.zero) worst = std::max(worst, std::abs(y[r] - center));
  return {SymmetryMethod::MirroredPairs, 2 * p.mirrored.size(), worst / (*hi - *lo), 0.0};
}

// ---- Symmetry by interpolation (symmetry.hpp) ----

constexpr std::size_t kMinSliceNodes = 8;  // distinct |x| on each side of every slice
constexpr double kMinOverlap = 0.5;        // the shorter side's reach / the longer side's
constexpr double kResidualRatio = 10;      // a residual / its local error estimate
// The largest noise, and error estimate of a compared row, relative to the target's range (the
// caller's tolerance where that is larger).
constexpr double kMaxNoise = 1e-6;
constexpr std::size_t kWindow = 8;  // nodes on either side for a local median
constexpr double kMinGap = 0.25;    // between nodes / the mean spacing about them
// Float64 roundings of the interpolation and the residual, relative to the values' size.
constexpr double kRoundings = 16 * std::numeric_limits<double>::epsilon();
// The median |residual| of Gaussian noise times this is its standard deviation.
constexpr double kMadToSigma = 1.4826;

// The polynomial through the nodes (u[i], v[i]), i in `at`, evaluated at t (Lagrange's form).
double polynomial_at(const std::vector<double>& u, const std::vector<double>& v,
                     std::span<const std::size_t> at, double t) {
  double sum = 0;
  for (std::size_t i : at) {
    double w = 1;
    for (std::size_t j : at)
      if (j != i) w *= (t - u[j]) / (u[i] - u[j]);
    sum += w * v[i];
  }
  return sum;
}

// The first index of a run of n nodes about position p in [0, size): p - 2, kept inside.
std::size_t stencil_start(std::size_t p, std::size_t n, std::size_t size) {
  return std::min(p < 2 ? 0 : p - 2, size - n);
}

// The rows of one side of 0 in a slice, as a function of u = |x| > 0.
struct Side {
  std::vector<std::size_t> rows;  // the rows, by ascending |x|
  std::vector<double> u, v;       // the nodes (build): |x| ascending, the mean target at each
  std::vector<double> loo;        // |leave-one-out residual| at each node
  std::vector<double> scale;      // the median of `loo` over the nodes within kWindow

  // The nodes of `rows` (ascending |x|): the distinct |x|, each with its mean target, less those
  // closer to the previous node than kMinGap times the mean spacing about them (their rows are
  // still compared): a cubic through nearly coincident nodes multiplies their rounding or noise.
  // Then each node's leave-one-out residual and the local scale. Less than kMinSliceNodes nodes:
  // no scale (the slice is not used).
  void build(const std::vector<double>& x, const std::vector<double>& y) {
    std::vector<double> du, dv;
    for (std::size_t k = 0; k < rows.size();) {
      std::size_t end = k;
      double sum = 0;
      while (end < rows.size() && std::abs(x[rows[end]]) == std::abs(x[rows[k]]))
        sum += y[rows[end++]];
      du.push_back(std::abs(x[rows[k]]));
      dv.push_back(sum / static_cast<double>(end - k));
      k = end;
    }
    const std::size_t d = du.size();
    if (d < kMinSliceNodes) return;
    for (std::size_t k = 0; k < d; ++k) {
      const std::size_t a = k < 4 ? 0 : k - 4, b = std::min(d - 1, k + 4);
      const double spacing = (du[b] - du[a]) / static_cast<double>(b - a);
      if (!u.empty() && du[k] - u.back() < kMinGap * spacing) continue;
      u.push_back(du[k]);
      v.push_back(dv[k]);
    }
    const std::size_t n = u.size();
    if (n < kMinSliceNodes) return;
    // Each node from the four nearest others (a cubic; extrapolated at the two ends).
    loo.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t lo = stencil_start(k, 5, n);
      std::array<std::size_t, 4> at{};
      std::size_t m = 0;
      for (std::size_t i = lo; i < lo + 5; ++i)
        if (i != k) at[m++] = i;
      loo[k] = std::abs(v[k] - polynomial_at(u, v, at, u[k]));
    }
    scale.resize(n);
    std::vector<double> window;
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t a = k < kWindow ? 0 : k - kWindow, b = std::min(n, k + kWindow + 1);
      window.assign(loo.begin() + static_cast<std::ptrdiff_t>(a),
                    loo.begin() + static_cast<std::ptrdiff_t>(b));
      const auto mid = window.begin() + static_cast<std::ptrdiff_t>(window.size() / 2);
      std::nth_element(window.begin(), mid, window.end());
      scale[k] = *mid;
    }
  }

  bool usable() const { return !scale.empty(); }
  bool covers(double t) const { return t >= u.front() && t <= u.back(); }

  // The first node at or after t, or the last.
  std::size_t position(double t) const {
    const auto p = static_cast<std::size_t>(std::lower_bound(u.begin(), u.end(), t) - u.begin());
    return std::min(p, u.size() - 1);
  }

  // The local leave-one-out scale at t: the larger of the two nodes' about it.
  double scale_at(double t) const {
    const std::size_t p = position(t);
    return std::max(scale[p], scale[p == 0 ? 0 : p - 1]);
  }

  // The side's value at t (covers(t)): the cubic through the four nearest nodes, and its error
  // estimate there: the larger of the next term (|quartic - cubic|) and the local scale times
  // the cubic's noise gain at t (the sum of its |Lagrange weights|).
  std::pair<double, double> at(double t) const {
    const std::size_t n = u.size(), p = position(t);
    const std::size_t lo4 = stencil_start(p, 4, n), lo5 = stencil_start(p, 5, n);
    const std::array<std::size_t, 4> cubic{lo4, lo4 + 1, lo4 + 2, lo4 + 3};
    const std::array<std::size_t, 5> quartic{lo5, lo5 + 1, lo5 + 2, lo5 + 3, lo5 + 4};
    const double v4 = polynomial_at(u, v, cubic, t), v5 = polynomial_at(u, v, quartic, t);
    double gain = 0;
    for (std::size_t i : cubic) {
      double w = 1;
      for (std::size_t j : cubic)
        if (j != i) w *= (t - u[j]) / (u[i] - u[j]);
      gain += std::abs(w);
    }
    return {v4, std::max(std::abs(v5 - v4), gain * scale_at(t))};
  }
};

// A row compared with its mirror: its target, the other side's value at -x, the error estimate.
struct Compared {
  double y, mirror, estimate;
};

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// The symmetry of input k by interpolation (symmetry.hpp), or nullopt.
std::optional<DataSymmetry> interpolated_symmetry(const SearchProblem& problem, std::size_t k,
                                                  double tolerance) {
  const auto& inputs = problem.inputs;
  const std::vector<double>& x = inputs[k];
  const std::vector<double>& y = problem.target;
  const auto below =
      static_cast<std::size_t>(std::count_if(x.begin(), x.end(), [](double v) { return v < 0; }));
  const auto above =
      static_cast<std::size_t>(std::count_if(x.begin(), x.end(), [](double v) { return v > 0; }));
  if (below < kSymmetryMinSideRows || above < kSymmetryMinSideRows) return std::nullopt;
  const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
  const double range = *hi - *lo;
  if (!(range > 0)) return std::nullopt;  // a constant target

  // Slices: the rows ordered by the other inputs, then x.
  std::vector<std::size_t> order(x.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto same_rest = [&](std::size_t a, std::size_t b) {
    for (std::size_t i = 0; i < inputs.size(); ++i)
      if (i != k && inputs[i][a] != inputs[i][b]) return false;
    return true;
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      if (i == k) continue;
      if (inputs[i][a] != inputs[i][b]) return inputs[i][a] < inputs[i][b];
    }
    return x[a] < x[b];
  });

  std::vector<Compared> compared;
  std::vector<std::size_t> zero;
  std::vector<double> loo;
  struct Count {
    std::size_t overlap = 0, compared = 0;  // rows whose mirror the other side covers; compared
  } below_rows, above_rows;
  // A row is compared where its error estimate is at most this.
  const double resolved = std::max(kMaxNoise, tolerance) * range;
  for (std::size_t begin = 0; begin < order.size();) {
    std::size_t end = begin + 1;
    while (end < order.size() && same_rest(order[begin], order[end])) ++end;
    Side neg, pos;
    for (std::size_t j = begin; j < end; ++j) {
      const std::size_t r = order[j];
      if (x[r] < 0)
        neg.rows.push_back(r);
      else if (x[r] > 0)
        pos.rows.push_back(r);
      else
        zero.push_back(r);
    }
    std::reverse(neg.rows.begin(), neg.rows.end());  // by ascending |x|
    neg.build(x, y);
    pos.build(x, y);
    if (!neg.usable() || !pos.usable()) return std::nullopt;
    const double reach = std::min(neg.u.back(), pos.u.back());
    if (reach < kMinOverlap * std::max(neg.u.back(), pos.u.back())) return std::nullopt;
    for (const auto& [side, other, count] :
         {std::tuple{&neg, &pos, &below_rows}, std::tuple{&pos, &neg, &above_rows}}) {
      for (std::size_t r : side->rows) {
        const double t = std::abs(x[r]);
        if (!other->covers(t)) continue;
        ++count->overlap;
        const auto [mirror, estimate] = other->at(t);
        const double e = std::max(estimate, side->scale_at(t));
        if (e > resolved) continue;  // the data does not resolve the function here
        compared.push_back({y[r], mirror, e});
        ++count->compared;
      }
      loo.insert(loo.end(), side->loo.begin(), side->loo.end());
    }
    begin = end;
  }
  for (const Count& c : {below_rows, above_rows})
    if (c.compared < kSymmetryMinSideRows || 2 * c.compared < c.overlap) return std::nullopt;
  const double noise = kMadToSigma * median(std::move(loo));
  if (noise > resolved) return std::nullopt;

  const double floor = tolerance * range;
  // The largest |residual| under `kind` about m, or nullopt where some row is beyond its bound.
  auto worst_residual = [&](SymmetryKind kind, double m) -> std::optional<double> {
    double worst = 0;
    for (const Compared& c : compared) {
      const double r = std::abs(mirror_residual(kind, c.y, c.mirror, m));
      const double roundings = kRoundings * (std::abs(c.y) + std::abs(c.mirror) + 2 * std::abs(m));
      if (!(r <= std::max(kResidualRatio * std::max(c.estimate, noise) + roundings, floor)))
        return std::nullopt;
      worst = std::max(worst, r);
    }
    if (kind != SymmetryKind::Even)
      for (std::size_t r : zero) {
        const double d = std::abs(y[r] - m);
        const double roundings = kRoundings * (std::abs(y[r]) + std::abs(m));
        if (!(d <= std::max(kResidualRatio * noise + roundings, floor))) return std::nullopt;
        worst = std::max(worst, d);
      }
    return worst;
  };
  // The sign of y - m on the half x > 0 (DataSymmetry::sign), within the noise.
  auto half_sign = [&](double m) {
    const double tol = std::max(floor, kResidualRatio * noise);
    bool up = true, down = true;
    for (std::size_t r = 0; r < x.size(); ++r) {
      if (!(x[r] > 0)) continue;
      up = up && y[r] - m >= -tol;
      down = down && y[r] - m <= tol;
    }
    return up ? 1 : down ? -1 : 0;
  };
  auto found = [&](SymmetryKind kind, double m, int sign, double worst) {
    return DataSymmetry{k,
                        problem.input_names[k],
                        kind,
                        m,
                        sign,
                        {SymmetryMethod::Interpolation, below_rows.compared + above_rows.compared,
                         worst / range, noise / range}};
  };
  if (const auto w = worst_residual(SymmetryKind::Even, 0))
    return found(SymmetryKind::Even, 0, 1, *w);
  if (const auto w = worst_residual(SymmetryKind::Odd, 0))
    return found(SymmetryKind::Odd, 0, half_sign(0), *w);
  // m: the mean target at x = 0 where the data has it, else the median midpoint.
  double m = 0;
  if (!zero.empty()) {
    for (std::size_t r : zero) m += y[r];
    m /= static_cast<double>(zero.size());
  } else {
    std::vector<double> mid(compared.size());
    for (std::size_t i = 0; i < compared.size(); ++i)
      mid[i] = 0.5 * (compared[i].y + compared[i].mirror);
    m = median(std::move(mid));
  }
  if (const auto w = worst_residual(SymmetryKind::Point, m))
    return found(SymmetryKind::Point, m, half_sign(m), *w);
  return std::nullopt;
}

}  // namespace

std::string_view symmetry_kind_name(SymmetryKind kind) {
  switch (kind) {
    case SymmetryKind::Even: return "even";
    case SymmetryKind::Odd: return "odd";
    case SymmetryKind::Point: return "point";
  }
  return "even";
}

std::optional<SymmetryKind> symmetry_kind_from_name(std::string_view name) {
  for (SymmetryKind k : {SymmetryKind::Even, SymmetryKind::Odd, SymmetryKind::Point})
    if (symmetry_kind_name(k) == name) return k;
  return std::nullopt;
}

std::string_view symmetry_method_name(SymmetryMethod method) {
  return method == SymmetryMethod::Interpolation ? "interpolation" : "mirrored_pairs";
}

std::optional<SymmetryMethod> symmetry_method_from_name(std::string_view name) {
  for (SymmetryMethod m : {SymmetryMethod::MirroredPairs, SymmetryMethod::Interpolation})
    if (symmetry_method_name(m) == name) return m;
  return std::nullopt;
}

std::optional<DataSymmetry> search_symmetry(const SearchOptions& options,
                                            const SearchProblem& problem) {
  if (!options.symmetry) return std::nullopt;
  const bool ratio_loss =
      options.loss == Loss::Relative || options.loss == Loss::MaxRel || options.loss == Loss::Log;
  if (!ratio_loss) return detect_symmetry(problem);
  const std::optional<DataSymmetry> s = detect_symmetry(problem);
  return s.has_value() && s->kind == SymmetryKind::Point ? std::nullopt : s;
}

std::optional<DataSymmetry> detect_symmetry(const SearchProblem& problem, double tolerance) {
  std::vector<bool> mirrored(problem.inputs.size(), false);
  for (std::size_t k = 0; k < problem.inputs.size(); ++k) {
    const std::optional<Pairs> p = mirrored_pairs(problem, k);
    mirrored[k] = p.has_value();
    if (!p || p->mirrored.size() < kMinPairs || !weights_mirrored(problem, *p)) continue;
    double center = 0;
    int sign = 1;
    if (const auto kind = target_symmetry(problem, *p, tolerance, &center, &sign)) {
      const SymmetryEvidence evidence = pairs_evidence(problem, *p, *kind, center);
      return DataSymmetry{k, problem.input_names[k], *kind, center, sign, evidence};
    }
  }
  for (std::size_t k = 0; k < problem.inputs.size(); ++k)
    if (!mirrored[k])
      if (auto s = interpolated_symmetry(problem, k, tolerance)) return s;
  return std::nullopt;
}

SearchProblem symmetric_half(const SearchProblem& problem, const DataSymmetry& symmetry) {
  SearchProblem half;
  half.input_names = problem.input_names;
  half.inputs.resize(problem.inputs.size());
  const std::vector<double>& x = problem.inputs[symmetry.input];
  for (std::size_t r = 0; r < x.size(); ++r) {
    if (!(x[r] >= 0)) continue;
    for (std::size_t i = 0; i < problem.inputs.size(); ++i)
      half.inputs[i].push_back(problem.inputs[i][r]);
    const double y = problem.target[r];
    half.target.push_back(symmetry.kind == SymmetryKind::Odd && symmetry.sign < 0 ? -y : y);
    if (!problem.weights.empty()) half.weights.push_back(problem.weights[r]);
  }
  return half;
}

namespace {

// g's nodes with `input_names` as variables and |x| for x, but for the leaf at `keep` (and x
// under an even integer power or abs, which ignore its sign).
Expression with_abs_input(const Expression& g, const DataSymmetry& symmetry,
                          const std::vector<std::string>& input_names,
                          std::size_t keep = static_cast<std::size_t>(-1)) {
  Expression e;
  e.variables = input_names;
  e.parameters = g.parameters;
  e.parameter_values = g.parameter_values;
  const int x = static_cast<int>(symmetry.input);
  for (std::size_t k = 0; k < g.size(); ++k) {
    const Node& n = g.nodes[k];
    if (n.op != Op::Var) {
      e.nodes.push_back(n);
      continue;
    }
    const auto at = std::find(input_names.begin(), input_names.end(),
                              g.variables.at(static_cast<std::size_t>(n.index)));
    if (at == input_names.end())
      throw Error("the formula names '" + g.variables[static_cast<std::size_t>(n.index)] +
                      "', which is not an input",
                  {"reflect_expression"});
    const int i = static_cast<int>(at - input_names.begin());
    e.nodes.push_back(Node::variable(i));
    // No |x| where the next node (whose operand this leaf is) ignores x's sign already.
    const bool sign_free =
        k + 1 < g.size() && ((g.nodes[k + 1].op == Op::IPow && g.nodes[k + 1].index % 2 == 0) ||
                             g.nodes[k + 1].op == Op::Abs);
    if (i == x && !sign_free && k != keep) e.nodes.push_back(Node::op_node(Op::Abs));
  }
  return e;
}

bool is_input(const Expression& g, const Node& n, const DataSymmetry& symmetry) {
  return n.op == Op::Var &&
         g.variables.at(static_cast<std::size_t>(n.index)) == symmetry.input_name;
}

}  // namespace

Expression reflect_expression(const Expression& g, const DataSymmetry& symmetry,
                              const std::vector<std::string>& input_names) {
  Expression e = with_abs_input(g, symmetry, input_names);
  const int x = static_cast<int>(symmetry.input);
  const bool point = symmetry.kind == SymmetryKind::Point;
  const auto op = [&](Op o) { e.nodes.push_back(Node::op_node(o)); };
  const auto center = [&] { e.nodes.push_back(Node::constant(symmetry.center)); };
  if (symmetry.kind == SymmetryKind::Even) {
    e.update_lengths();
    return e;
  }
  if (point) {  // the value relative to m: G - m, or m - G where y <= m on the half
    if (symmetry.sign < 0) {
      e.nodes.insert(e.nodes.begin(), Node::constant(symmetry.center));
    } else {
      center();
    }
    op(Op::Sub);
  }
  e.nodes.push_back(Node::variable(x));
  if (symmetry.sign == 0) {  // H * sign(x)
    op(Op::Sign);
    op(Op::Mul);
  } else {  // copysign(H, x), or copysign(H, -x) for odd data negative on the half
    if (symmetry.sign < 0 && !point) op(Op::Neg);
    op(Op::CopySign);
  }
  if (point) {  // m + that, or m - that
    e.nodes.insert(e.nodes.begin(), Node::constant(symmetry.center));
    op(symmetry.sign < 0 ? Op::Sub : Op::Add);
  }
  e.update_lengths();
  return e;
}

Expression unreflected_expression(const Expression& g, const DataSymmetry& symmetry) {
  Expression e = g;
  if (symmetry.kind == SymmetryKind::Odd && symmetry.sign < 0) {
    e.nodes.push_back(Node::op_node(Op::Neg));
    e.update_lengths();
  }
  return e;
}

std::optional<Expression> factored_expression(const Expression& g, const DataSymmetry& symmetry,
                                              const std::vector<std::string>& input_names) {
  if (symmetry.kind != SymmetryKind::Odd || g.size() < 3) return std::nullopt;
  const std::size_t root = g.size() - 1;
  const Op op = g.nodes[root].op;
  const std::size_t right = root - 1;  // the right operand's root; the left one ends before it
  const bool left_leaf = g.nodes[right].length + 3 == g.size();  // the left operand is node 0
  std::size_t keep;
  if ((op == Op::Mul || op == Op::Div) && left_leaf && is_input(g, g.nodes[0], symmetry))
    keep = 0;
  else if (op == Op::Mul && g.nodes[right].length == 0 && is_input(g, g.nodes[right], symmetry))
    keep = right;
  else
    return std::nullopt;
  Expression e = with_abs_input(g, symmetry, input_names, keep);
  e.update_lengths();
  return unreflected_expression(e, symmetry);
}

namespace {

// A subexpression's parity in x: Even includes not depending on x at all.
enum class Parity { Even, Odd, None };

// The parity of an operator's result from its operands' (not all Even).
Parity parity_of(const Node& n, std::span<const Parity> a) {
  const auto product = [](Parity p, Parity q) {
    if (p == Parity::None || q == Parity::None) return Parity::None;
    return (p == Parity::Odd) != (q == Parity::Odd) ? Parity::Odd : Parity::Even;
  };
  const auto sum = [](Parity p, Parity q) {
    return p == Parity::Odd && q == Parity::Odd ? Parity::Odd : Parity::None;
  };
  switch (n.op) {
    case Op::Add:
    case Op::Sub: return sum(a[0], a[1]);
    case Op::Mul:
    case Op::Div: return product(a[0], a[1]);
    case Op::Fma: return sum(product(a[0], a[1]), a[2]);
    case Op::IPow:
      return a[0] == Parity::Odd ? (n.index % 2 == 0 ? Parity::Even : Parity::Odd) : Parity::None;
    case Op::CopySign:  // |a| carries the sign of b
      if (a[0] == Parity::None) return Parity::None;
      return a[1];
    default:
      // An odd unary function keeps its operand's parity, an even one makes an odd operand even.
      switch (op_info(n.op).parity) {
        case OpParity::Odd: return a[0];
        case OpParity::Even: return a[0] == Parity::Odd ? Parity::Even : Parity::None;
        case OpParity::None: return Parity::None;
      }
      return Parity::None;
  }
}

}  // namespace

bool symmetric_as_written(const Expression& g, const DataSymmetry& symmetry) {
  if (symmetry.kind == SymmetryKind::Point) return false;
  std::vector<Parity> stack;
  for (const Node& n : g.nodes) {
    const auto k = static_cast<std::size_t>(n.arity);
    if (k == 0) {
      const bool x = n.op == Op::Var &&
                     g.variables.at(static_cast<std::size_t>(n.index)) == symmetry.input_name;
      stack.push_back(x ? Parity::Odd : Parity::Even);
      continue;
    }
    const std::span<const Parity> operands(stack.data() + stack.size() - k, k);
    const bool even =
        std::all_of(operands.begin(), operands.end(), [](Parity p) { return p == Parity::Even; });
    const Parity p = even ? Parity::Even : parity_of(n, operands);
    stack.resize(stack.size() - k);
    stack.push_back(p);
  }
  const Parity want = symmetry.kind == SymmetryKind::Odd ? Parity::Odd : Parity::Even;
  return stack.size() == 1 && stack[0] == want;
}

std::vector<Expression> whole_data_forms(const Expression& g, const DataSymmetry& symmetry,
                                         const std::vector<std::string>& input_names, bool scored) {
  std::vector<Expression> forms = {reflect_expression(g, symmetry, input_names)};
  if (auto f = factored_expression(g, symmetry, input_names)) forms.push_back(std::move(*f));
  if (scored || symmetric_as_written(g, symmetry))
    forms.push_back(unreflected_expression(g, symmetry));
  return forms;
}

std::string describe_symmetry(const DataSymmetry& symmetry) {
  const std::string& x = symmetry.input_name;
  switch (symmetry.kind) {
    case SymmetryKind::Even: return "even in " + x;
    case SymmetryKind::Odd: return "odd in " + x;
    case SymmetryKind::Point:
      return fmt::format("point-symmetric in {} about {}", x, symmetry.center);
  }
  return {};
}

std::string describe_symmetry_evidence(const DataSymmetry& symmetry) {
  const SymmetryEvidence& e = symmetry.evidence;
  if (e.method == SymmetryMethod::MirroredPairs)
    return fmt::format("{} mirrored pairs, largest residual {:.2g} of the range",
                       e.rows_compared / 2, e.max_residual);
  return fmt::format(
      "{} rows against the other side's interpolant, largest residual {:.2g} of the range, "
      "noise {:.2g}",
      e.rows_compared, e.max_residual, e.noise);
}

}  // namespace shaderfit
