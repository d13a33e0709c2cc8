#include "shaderfit/data/sampling.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <string>

#include "data/number.hpp"

namespace shaderfit {

namespace {

constexpr std::size_t kMaxDesignDimensions = 6;
constexpr std::size_t kMaxSobolDimensions = 8;
constexpr int kSobolBits = 32;

// One row of Joe and Kuo's table (new-joe-kuo-6.21201) for dimensions 2 to 8: the degree s of
// the primitive polynomial, its coefficients a (the inner ones, as a bit field) and the initial
// direction numbers m_1 .. m_s.
struct SobolPolynomial {
  int s;
  unsigned a;
  std::array<std::uint32_t, 5> m;
};
constexpr std::array<SobolPolynomial, kMaxSobolDimensions - 1> kJoeKuo = {{
    {1, 0, {1}},
    {2, 1, {1, 3}},
    {3, 1, {1, 3, 1}},
    {3, 2, {1, 1, 1}},
    {4, 1, {1, 1, 3, 3}},
    {4, 4, {1, 3, 5, 13}},
    {5, 2, {1, 1, 5, 5, 17}},
}};

using Directions = std::array<std::uint32_t, kSobolBits>;

// The direction numbers v_1 .. v_32 of dimension `dim` (0-based), scaled by 2^32.
Directions sobol_directions(std::size_t dim) {
  Directions v{};
  if (dim == 0) {  // van der Corput: every m_k is 1
    for (int k = 0; k < kSobolBits; ++k) v[k] = std::uint32_t{1} << (kSobolBits - 1 - k);
    return v;
  }
  const SobolPolynomial& p = kJoeKuo[dim - 1];
  for (int k = 0; k < p.s; ++k) v[k] = p.m[k] << (kSobolBits - 1 - k);
  for (int k = p.s; k < kSobolBits; ++k) {
    std::uint32_t x = v[k - p.s] ^ (v[k - p.s] >> p.s);
    for (int l = 1; l < p.s; ++l) {
      if ((p.a >> (p.s - 1 - l)) & 1u) x ^= v[k - l];
    }
    v[k] = x;
  }
  return v;
}

// The Sobol points of `dims` dimensions in Gray-code order, one after another from point 0.
class SobolWalk {
 public:
  explicit SobolWalk(std::size_t dims) : x_(dims, 0) {
    for (std::size_t j = 0; j < dims; ++j) v_.push_back(sobol_directions(j));
  }
  // Moves from point i to point i + 1.
  void next() {
    ++i_;
    const int c = std::countr_zero(i_);
    for (std::size_t j = 0; j < x_.size(); ++j) x_[j] ^= v_[j][c];
  }
  // Coordinate j of the current point, in [0, 1).
  [[nodiscard]] double at(std::size_t j) const { return std::ldexp(x_[j], -kSobolBits); }

 private:
  std::vector<Directions> v_;
  std::vector<std::uint32_t> x_;
  std::uint64_t i_ = 0;
};

// lo + (hi - lo) u for u in [0, 1], kept inside [lo, hi].
double scale(const reference::DomainAxis& a, double u) {
  return std::clamp(a.lo + (a.hi - a.lo) * u, a.lo, a.hi);
}

// a * b, saturated at kMaxDesignPoints + 1 (so that sizes beyond the limit cannot overflow).
std::size_t capped_product(std::size_t a, std::size_t b) {
  constexpr std::size_t kCap = kMaxDesignPoints + 1;
  if (a == 0 || b == 0) return 0;
  return a > kCap / b ? kCap : std::min(a * b, kCap);
}

// `points` is a count from capped_product: kMaxDesignPoints + 1 stands for any larger one.
void check_size(std::size_t points, const SourceLocation& where) {
  if (points > kMaxDesignPoints) {
    throw Error("the sample design would have more than " +
                    data_detail::format_count(kMaxDesignPoints) + " points",
                where);
  }
}

SampleColumns grid_product(std::span<const reference::DomainAxis> axes,
                           const SourceLocation& where) {
  std::size_t rows = 1;
  for (const reference::DomainAxis& a : axes) rows = capped_product(rows, a.count);
  check_size(rows, where);
  SampleColumns out(axes.size(), std::vector<double>(rows));
  // Axis j repeats each of its points `inner` times (the product of the later axes' counts).
  std::size_t inner = rows;
  for (std::size_t j = 0; j < axes.size(); ++j) {
    inner /= axes[j].count;
    for (std::size_t r = 0; r < rows; ++r) out[j][r] = axes[j].at((r / inner) % axes[j].count);
  }
  return out;
}

// n >= 2 points from lo to hi: mid + half * (2i - (n-1)) / (n-1). The integer numerator is
// negated exactly between i and n-1-i, and the quotient of the same rational is the same double
// for every n, so the points mirror about mid bit for bit and a denser grid (n-1) k + 1 holds
// these at every k-th place.
std::vector<double> even_grid(const reference::DomainAxis& a, std::size_t n) {
  const double mid = 0.5 * a.lo + 0.5 * a.hi;  // 0 exactly where lo = -hi
  const double half = 0.5 * a.hi - 0.5 * a.lo;
  const auto last = static_cast<double>(n - 1);
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = (2.0 * static_cast<double>(i) - last) / last;
    x[i] = std::clamp(mid + half * t, a.lo, a.hi);
  }
  x.front() = a.lo;
  x.back() = a.hi;
  return x;
}

std::size_t face_points(std::size_t d, std::size_t samples) {
  const double m = std::round(
      std::pow(static_cast<double>(samples), static_cast<double>(d - 1) / static_cast<double>(d)));
  return std::max<std::size_t>(1, static_cast<std::size_t>(m));
}

SampleColumns sobol_design(std::span<const reference::DomainAxis> axes, std::size_t samples,
                           std::size_t density, const SourceLocation& where) {
  const std::size_t d = axes.size();
  const std::size_t corners = std::size_t{1} << d;
  const std::size_t face = capped_product(face_points(d, samples), density);
  const std::size_t inside = capped_product(samples, density);
  const std::size_t rows =
      std::min(corners + capped_product(2 * d, face) + inside, kMaxDesignPoints + 1);
  check_size(rows, where);

  SampleColumns out(d);
  for (auto& c : out) c.reserve(rows);
  // Corners: bit j of c puts axis j at hi.
  for (std::size_t c = 0; c < corners; ++c) {
    for (std::size_t j = 0; j < d; ++j) out[j].push_back((c >> j) & 1u ? axes[j].hi : axes[j].lo);
  }
  // Faces: axis `fixed` at lo, then at hi; the other axes, in order, from a Sobol set.
  for (std::size_t fixed = 0; fixed < d; ++fixed) {
    for (const bool at_hi : {false, true}) {
      SobolWalk walk(d - 1);
      for (std::size_t i = 1; i <= face; ++i) {
        walk.next();
        std::size_t k = 0;
        for (std::size_t j = 0; j < d; ++j) {
          if (j == fixed) {
            out[j].push_back(at_hi ? axes[j].hi : axes[j].lo);
          } else {
            out[j].push_back(scale(axes[j], walk.at(k++)));
          }
        }
      }
    }
  }
  SobolWalk walk(d);
  for (std::size_t i = 1; i <= inside; ++i) {
    walk.next();
    for (std::size_t j = 0; j < d; ++j) out[j].push_back(scale(axes[j], walk.at(j)));
  }
  return out;
}

}  // namespace

std::size_t default_sample_count(std::size_t dimensions) {
  if (dimensions <= 1) return 10'001;
  if (dimensions == 2) return 4'096;
  return 8'192;
}

SampleColumns sample_domain(std::span<const reference::DomainAxis> axes, std::size_t samples,
                            std::size_t density, const SourceLocation& where) {
  if (axes.empty()) throw Error("no domain: give each variable an interval (x=lo:hi)", where);
  const auto counted = std::count_if(axes.begin(), axes.end(),
                                     [](const reference::DomainAxis& a) { return a.count > 0; });
  if (counted == static_cast<std::ptrdiff_t>(axes.size())) return grid_product(axes, where);
  if (counted > 0) {
    const auto with = std::find_if(axes.begin(), axes.end(),
                                   [](const reference::DomainAxis& a) { return a.count > 0; });
    const auto without = std::find_if(axes.begin(), axes.end(),
                                      [](const reference::DomainAxis& a) { return a.count == 0; });
    throw Error("'" + with->name + "' has a number of points and '" + without->name +
                    "' has none: give every variable one (a grid) or none (the sample design)",
                where);
  }
  if (axes.size() > kMaxDesignDimensions) {
    throw Error(std::to_string(axes.size()) +
                    " variables: the sample design covers 1 to 6 (a grid of more takes a number "
                    "of points for each, x=lo:hi:count)",
                where);
  }
  if (density == 0) throw Error("a design's density must be at least 1, not 0", where);
  if (samples == 0) samples = default_sample_count(axes.size());

  if (axes.size() == 1) {
    if (samples < 2) {
      throw Error(
          "one variable needs at least 2 samples (both ends), not " + std::to_string(samples),
          where);
    }
    const std::size_t n = capped_product(samples - 1, density) + 1;
    check_size(n, where);
    return {even_grid(axes[0], n)};
  }
  return sobol_design(axes, samples, density, where);
}

std::vector<double> sobol_point(std::size_t dimensions, std::uint64_t i) {
  if (dimensions < 1 || dimensions > kMaxSobolDimensions) {
    throw Error("Sobol points have 1 to 8 dimensions, not " + std::to_string(dimensions),
                {"sobol_point"});
  }
  if (i >> kSobolBits) {
    throw Error("Sobol point " + std::to_string(i) + " is beyond the 2^32 points of 32 bits",
                {"sobol_point"});
  }
  const std::uint64_t gray = i ^ (i >> 1);
  std::vector<double> out(dimensions);
  for (std::size_t j = 0; j < dimensions; ++j) {
    const Directions v = sobol_directions(j);
    std::uint32_t x = 0;
    for (int k = 0; k < kSobolBits; ++k) {
      if ((gray >> k) & 1u) x ^= v[k];
    }
    out[j] = std::ldexp(x, -kSobolBits);
  }
  return out;
}

}  // namespace shaderfit
