// LDR-FLIP after the paper (Andersson et al., HPG 2020), written to agree with NVIDIA's
// flip-evaluator (python/tests/flip_agreement_test.py measures the agreement):
//   colour: sRGB -> linear -> YCxCz; each channel blurred by the contrast sensitivity filter
//     (sums of Gaussians, one per channel); back to linear RGB, clamped to [0, 1]; CIELAB with
//     the Hunt adjustment; HyAB distance, raised to q_c and redistributed so that p_c of the
//     largest distance (green against blue) maps to p_t.
//   features: on the achromatic channel, the magnitudes of first (edge) and second (point)
//     Gaussian derivatives; their larger difference, scaled and raised to q_f.
//   error = colour ^ (1 - feature).
// All filters are separable and clamp to the edge, as the tool's are.
#include "shaderfit/image/flip.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <string>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

namespace {

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<Vec3, 3>;

// The paper's constants.
constexpr double kQc = 0.7;              // exponent of the colour distance
constexpr double kPc = 0.4;              // share of the largest distance ...
constexpr double kPt = 0.95;             // ... that maps to this error
constexpr double kFeatureWidth = 0.082;  // degrees: the feature detectors' width
constexpr double kQf = 0.5;              // exponent of the feature difference
constexpr double kPi = std::numbers::pi;

// The contrast sensitivity filter of one YCxCz channel: in the spatial domain, a sum of two
// Gaussians a * sqrt(pi / b) * exp(-pi^2 r^2 / b), r in degrees (a = 0 drops the second one).
struct Csf {
  double a1, b1, a2, b2;
};
constexpr std::array<Csf, 3> kCsf = {{
    {1.0, 0.0047, 0.0, 1e-5},   // achromatic (Y)
    {1.0, 0.0053, 0.0, 1e-5},   // red-green (Cx)
    {34.1, 0.04, 13.5, 0.025},  // blue-yellow (Cz)
}};

Vec3 mul(const Mat3& m, const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
          m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

Mat3 inverse(const Mat3& m) {
  const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  const double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  const double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  return {{{c00 / det, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det,
            (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det},
           {c01 / det, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det,
            (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det},
           {c02 / det, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det,
            (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det}}};
}

// Linear sRGB <-> CIE XYZ, derived from the sRGB primaries and D65 white point (IEC 61966-2-1);
// `white` is the XYZ of linear RGB (1, 1, 1), the reference white of YCxCz and CIELAB.
struct ColourSpace {
  Mat3 to_xyz{}, to_rgb{};
  Vec3 white{};
};

const ColourSpace& srgb() {
  static const ColourSpace space = [] {
    const auto xyz = [](double x, double y) { return Vec3{x / y, 1.0, (1.0 - x - y) / y}; };
    const Vec3 r = xyz(0.64, 0.33), g = xyz(0.30, 0.60), b = xyz(0.15, 0.06);
    const Mat3 primaries = {{{r[0], g[0], b[0]}, {r[1], g[1], b[1]}, {r[2], g[2], b[2]}}};
    const Vec3 s = mul(inverse(primaries), xyz(0.3127, 0.3290));  // scales that give white
    ColourSpace c;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) c.to_xyz[i][j] = primaries[i][j] * s[j];
    c.to_rgb = inverse(c.to_xyz);
    c.white = mul(c.to_xyz, {1.0, 1.0, 1.0});
    return c;
  }();
  return space;
}

double srgb_to_linear(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

// CIELAB of linear RGB, with the Hunt adjustment (a and b scaled by L / 100).
Vec3 hunt_lab(const Vec3& rgb) {
  const ColourSpace& cs = srgb();
  const Vec3 xyz = mul(cs.to_xyz, rgb);
  constexpr double d = 6.0 / 29.0;
  const auto f = [](double t) {
    return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
  };
  const double fx = f(xyz[0] / cs.white[0]), fy = f(xyz[1] / cs.white[1]),
               fz = f(xyz[2] / cs.white[2]);
  const double l = 116.0 * fy - 16.0;
  return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

// HyAB: city-block in lightness, Euclidean in the chromatic plane.
double hyab(const Vec3& p, const Vec3& q) {
  return std::abs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]);
}

// One image as planes: YCxCz (filtered in place later) and the achromatic channel y / y_white
// in [0, 1] that the feature detectors read.
struct Planes {
  std::array<std::vector<float>, 3> ycxcz;
  std::vector<float> gray;
};

Planes to_planes(const RgbImage& image) {
  const ColourSpace& cs = srgb();
  const std::size_t n = image.rgb.size() / 3;
  Planes p;
  for (auto& c : p.ycxcz) c.resize(n);
  p.gray.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 lin = {srgb_to_linear(image.rgb[3 * i]), srgb_to_linear(image.rgb[3 * i + 1]),
                      srgb_to_linear(image.rgb[3 * i + 2])};
    const Vec3 xyz = mul(cs.to_xyz, lin);
    const double x = xyz[0] / cs.white[0], y = xyz[1] / cs.white[1], z = xyz[2] / cs.white[2];
    p.ycxcz[0][i] = static_cast<float>(116.0 * y - 16.0);
    p.ycxcz[1][i] = static_cast<float>(500.0 * (x - y));
    p.ycxcz[2][i] = static_cast<float>(200.0 * (y - z));
    p.gray[i] = static_cast<float>(y);
  }
  return p;
}

// Separable filtering of a width x height plane with odd-length kernels centred on the pixel,
// reading clamped coordinates at the borders.
class Filter {
 public:
  Filter(int width, int height) : w_(width), h_(height), tmp_(plane_size()) {}

  // out = (column kernel) * ((row kernel) * in).
  void apply(std::span<const float> in, std::span<const float> row_kernel,
             std::span<const float> column_kernel, std::span<float> out) {
    rows(in, row_kernel, tmp_);
    columns(tmp_, column_kernel, out);
  }

 private:
  [[nodiscard]] std::size_t plane_size() const {
    return static_cast<std::size_t>(w_) * static_cast<std::size_t>(h_);
  }

  void rows(std::span<const float> in, std::span<const float> k, std::span<float> out) {
    const int r = static_cast<int>(k.size() / 2);
    padded_.resize(static_cast<std::size_t>(w_ + 2 * r));
    for (int y = 0; y < h_; ++y) {
      const float* src = in.data() + static_cast<std::size_t>(y) * w_;
      for (int x = -r; x < w_ + r; ++x) padded_[x + r] = src[std::clamp(x, 0, w_ - 1)];
      float* dst = out.data() + static_cast<std::size_t>(y) * w_;
      for (int x = 0; x < w_; ++x) {
        float sum = 0.0f;
        for (std::size_t j = 0; j < k.size(); ++j) sum += k[j] * padded_[x + j];
        dst[x] = sum;
      }
    }
  }

  void columns(std::span<const float> in, std::span<const float> k, std::span<float> out) const {
    const int r = static_cast<int>(k.size() / 2);
    for (int y = 0; y < h_; ++y) {
      float* dst = out.data() + static_cast<std::size_t>(y) * w_;
      std::fill(dst, dst + w_, 0.0f);
      for (int j = -r; j <= r; ++j) {
        const float kj = k[static_cast<std::size_t>(j + r)];
        const float* src = in.data() + static_cast<std::size_t>(std::clamp(y + j, 0, h_ - 1)) * w_;
        for (int x = 0; x < w_; ++x) dst[x] += kj * src[x];
      }
    }
  }

  int w_, h_;
  std::vector<float> tmp_, padded_;
};

// Blurs each YCxCz channel with its contrast sensitivity filter, in place. The 2-D filter is the
// sum of the two Gaussians sampled every 1 / ppd degrees over a square of the radius that covers
// the widest Gaussian (3 standard deviations), normalised to sum 1; each Gaussian is separable, so
// the sum is filtered term by term.
void csf_filter(Planes& p, Filter& filter, double ppd) {
  double widest = 0.0;
  for (const Csf& c : kCsf) widest = std::max({widest, c.b1, c.b2});
  const int radius = static_cast<int>(std::ceil(3.0 * std::sqrt(widest / (2.0 * kPi * kPi)) * ppd));
  const std::size_t n = p.gray.size();
  std::vector<float> term(n);
  for (std::size_t ch = 0; ch < 3; ++ch) {
    const Csf& c = kCsf[ch];
    const std::array<std::array<double, 2>, 2> gaussians = {{{c.a1, c.b1}, {c.a2, c.b2}}};
    std::array<std::vector<float>, 2> kernels;
    std::array<double, 2> scale{};
    double total = 0.0;
    for (std::size_t g = 0; g < 2; ++g) {
      const auto [a, b] = gaussians[g];
      double sum = 0.0;
      for (int x = -radius; x <= radius; ++x) {
        const double v = std::exp(-kPi * kPi * (x / ppd) * (x / ppd) / b);
        kernels[g].push_back(static_cast<float>(v));
        sum += v;
      }
      scale[g] = a * std::sqrt(kPi / b);
      total += scale[g] * sum * sum;
    }
    std::vector<float> out(n, 0.0f);
    for (std::size_t g = 0; g < 2; ++g) {
      if (scale[g] == 0.0) continue;
      filter.apply(p.ycxcz[ch], kernels[g], kernels[g], term);
      const auto s = static_cast<float>(scale[g] / total);
      for (std::size_t i = 0; i < n; ++i) out[i] += s * term[i];
    }
    p.ycxcz[ch] = std::move(out);
  }
}

// The feature detectors' 1-D kernels: the Gaussian of standard deviation 0.5 * 0.082 degrees
// (sum 1) and its first and second derivatives (positive and negative weights each summing to
// +1 and -1). A 2-D detector is a derivative along one axis times the Gaussian along the other.
struct FeatureKernels {
  std::vector<float> gaussian, first, second;
};

FeatureKernels feature_kernels(double ppd) {
  const double sd = 0.5 * kFeatureWidth * ppd;
  const int radius = static_cast<int>(std::ceil(3.0 * sd));
  std::vector<double> g, d1, d2;
  for (int x = -radius; x <= radius; ++x) {
    const double v = std::exp(-(x * x) / (2.0 * sd * sd));
    g.push_back(v);
    d1.push_back(-x * v);
    d2.push_back((x * x / (sd * sd) - 1.0) * v);
  }
  const auto normalise = [](const std::vector<double>& k) {
    double pos = 0.0, neg = 0.0;
    for (double v : k) (v > 0.0 ? pos : neg) += v;
    std::vector<float> out;
    for (double v : k)
      out.push_back(static_cast<float>(v > 0.0 ? v / pos : v < 0.0 ? -v / neg : 0.0));
    return out;
  };
  return {normalise(g), normalise(d1), normalise(d2)};
}

// Edge and point strengths of one achromatic plane: the magnitudes of the (x, y) responses.
struct Features {
  std::vector<float> edge, point;
};

Features features(std::span<const float> gray, Filter& filter, const FeatureKernels& k) {
  const std::size_t n = gray.size();
  std::vector<float> ax(n), ay(n);
  Features f{std::vector<float>(n), std::vector<float>(n)};
  const auto magnitude = [&](std::vector<float>& out) {
    for (std::size_t i = 0; i < n; ++i) out[i] = std::sqrt(ax[i] * ax[i] + ay[i] * ay[i]);
  };
  filter.apply(gray, k.first, k.gaussian, ax);
  filter.apply(gray, k.gaussian, k.first, ay);
  magnitude(f.edge);
  filter.apply(gray, k.second, k.gaussian, ax);
  filter.apply(gray, k.gaussian, k.second, ay);
  magnitude(f.point);
  return f;
}

void check_image(const RgbImage& image, const char* name) {
  if (image.width <= 0 || image.height <= 0)
    throw Error(
        "empty image (" + std::to_string(image.width) + " x " + std::to_string(image.height) + ")",
        {name});
  const std::size_t expected =
      3 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  if (image.rgb.size() != expected)
    throw Error("expected " + std::to_string(expected) + " values (3 per pixel), got " +
                    std::to_string(image.rgb.size()),
                {name});
  for (std::size_t i = 0; i < image.rgb.size(); ++i) {
    if (std::isfinite(image.rgb[i])) continue;
    const std::size_t pixel = i / 3;
    throw Error("value not finite at pixel (" + std::to_string(pixel % image.width) + ", " +
                    std::to_string(pixel / image.width) + ") channel " + std::to_string(i % 3),
                {name});
  }
}

}  // namespace

double FlipResult::share_above(double threshold) const {
  if (error.empty()) return 0.0;
  const auto count =
      std::count_if(error.begin(), error.end(), [threshold](float e) { return e > threshold; });
  return static_cast<double>(count) / static_cast<double>(error.size());
}

FlipResult ldr_flip(const RgbImage& reference, const RgbImage& test, const FlipOptions& options) {
  check_image(reference, "reference");
  check_image(test, "test");
  if (test.width != reference.width || test.height != reference.height)
    throw Error("size " + std::to_string(test.width) + " x " + std::to_string(test.height) +
                    " differs from the reference's " + std::to_string(reference.width) + " x " +
                    std::to_string(reference.height),
                {"test"});
  const double ppd = options.pixels_per_degree;
  if (!std::isfinite(ppd) || ppd <= 0.0)
    throw Error("must be finite and positive", {"FlipOptions::pixels_per_degree"});

  const int w = reference.width, h = reference.height;
  Filter filter(w, h);
  Planes ref = to_planes(reference), tst = to_planes(test);
  const FeatureKernels kernels = feature_kernels(ppd);
  const Features ref_features = features(ref.gray, filter, kernels);
  const Features tst_features = features(tst.gray, filter, kernels);
  csf_filter(ref, filter, ppd);
  csf_filter(tst, filter, ppd);

  // Back from filtered YCxCz to linear RGB, clamped to the gamut, then Hunt-adjusted CIELAB.
  const ColourSpace& cs = srgb();
  const auto lab = [&cs](const Planes& p, std::size_t i) {
    const double y = (p.ycxcz[0][i] + 16.0) / 116.0;
    const Vec3 xyz = {(p.ycxcz[1][i] / 500.0 + y) * cs.white[0], y * cs.white[1],
                      (y - p.ycxcz[2][i] / 200.0) * cs.white[2]};
    Vec3 rgb = mul(cs.to_rgb, xyz);
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
    return hunt_lab(rgb);
  };
  // The largest colour distance, between green and blue, sets the scale of the redistribution.
  const double cmax = std::pow(hyab(hunt_lab({0.0, 1.0, 0.0}), hunt_lab({0.0, 0.0, 1.0})), kQc);
  const double pccmax = kPc * cmax;

  FlipResult result;
  result.width = w;
  result.height = h;
  result.error.resize(ref.gray.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < result.error.size(); ++i) {
    const double dc = std::pow(hyab(lab(ref, i), lab(tst, i)), kQc);
    const double colour =
        dc < pccmax ? kPt / pccmax * dc : kPt + (dc - pccmax) / (cmax - pccmax) * (1.0 - kPt);
    const double edge = std::abs(ref_features.edge[i] - tst_features.edge[i]);
    const double point = std::abs(ref_features.point[i] - tst_features.point[i]);
    const double feature = std::pow(std::max(edge, point) / std::sqrt(2.0), kQf);
    const double e = std::pow(colour, 1.0 - feature);
    result.error[i] = static_cast<float>(e);
    sum += e;
  }
  result.mean = sum / static_cast<double>(result.error.size());
  return result;
}

std::vector<std::uint8_t> flip_colormap(const FlipResult& r) {
  // magma (S. van der Walt and N. Smith, CC0), 256 entries as 0xRRGGBB sRGB bytes: the table
  // flip-evaluator shows its error maps with.
  static constexpr std::array<std::uint32_t, 256> kMagma = {
      0x000004, 0x010005, 0x010106, 0x010108, 0x020109, 0x02020b, 0x02020d, 0x03030f, 0x030312,
      0x040414, 0x050416, 0x060518, 0x06051a, 0x07061c, 0x08071e, 0x090720, 0x0a0822, 0x0b0924,
      0x0c0926, 0x0d0a29, 0x0e0b2b, 0x100b2d, 0x110c2f, 0x120d31, 0x130d34, 0x140e36, 0x150e38,
      0x160f3b, 0x180f3d, 0x19103f, 0x1a1042, 0x1c1044, 0x1d1147, 0x1e1149, 0x20114b, 0x21114e,
      0x221150, 0x241253, 0x251255, 0x271258, 0x29115a, 0x2a115c, 0x2c115f, 0x2d1161, 0x2f1163,
      0x311165, 0x331067, 0x341069, 0x36106b, 0x38106c, 0x390f6e, 0x3b0f70, 0x3d0f71, 0x3f0f72,
      0x400f74, 0x420f75, 0x440f76, 0x451077, 0x471078, 0x491078, 0x4a1079, 0x4c117a, 0x4e117b,
      0x4f127b, 0x51127c, 0x52137c, 0x54137d, 0x56147d, 0x57157e, 0x59157e, 0x5a167e, 0x5c167f,
      0x5d177f, 0x5f187f, 0x601880, 0x621980, 0x641a80, 0x651a80, 0x671b80, 0x681c81, 0x6a1c81,
      0x6b1d81, 0x6d1d81, 0x6e1e81, 0x701f81, 0x721f81, 0x732081, 0x752181, 0x762181, 0x782281,
      0x792282, 0x7b2382, 0x7c2382, 0x7e2482, 0x802582, 0x812581, 0x832681, 0x842681, 0x862781,
      0x882781, 0x892881, 0x8b2981, 0x8c2981, 0x8e2a81, 0x902a81, 0x912b81, 0x932b80, 0x942c80,
      0x962c80, 0x982d80, 0x992d80, 0x9b2e7f, 0x9c2e7f, 0x9e2f7f, 0xa02f7f, 0xa1307e, 0xa3307e,
      0xa5317e, 0xa6317d, 0xa8327d, 0xaa337d, 0xab337c, 0xad347c, 0xae347b, 0xb0357b, 0xb2357b,
      0xb3367a, 0xb5367a, 0xb73779, 0xb83779, 0xba3878, 0xbc3978, 0xbd3977, 0xbf3a77, 0xc03a76,
      0xc23b75, 0xc43c75, 0xc53c74, 0xc73d73, 0xc83e73, 0xca3e72, 0xcc3f71, 0xcd4071, 0xcf4070,
      0xd0416f, 0xd2426f, 0xd3436e, 0xd5446d, 0xd6456c, 0xd8456c, 0xd9466b, 0xdb476a, 0xdc4869,
      0xde4968, 0xdf4a68, 0xe04c67, 0xe24d66, 0xe34e65, 0xe44f64, 0xe55064, 0xe75263, 0xe85362,
      0xe95462, 0xea5661, 0xeb5760, 0xec5860, 0xed5a5f, 0xee5b5e, 0xef5d5e, 0xf05f5e, 0xf1605d,
      0xf2625d, 0xf2645c, 0xf3655c, 0xf4675c, 0xf4695c, 0xf56b5c, 0xf66c5c, 0xf66e5c, 0xf7705c,
      0xf7725c, 0xf8745c, 0xf8765c, 0xf9785d, 0xf9795d, 0xf97b5d, 0xfa7d5e, 0xfa7f5e, 0xfa815f,
      0xfb835f, 0xfb8560, 0xfb8761, 0xfc8961, 0xfc8a62, 0xfc8c63, 0xfc8e64, 0xfc9065, 0xfd9266,
      0xfd9467, 0xfd9668, 0xfd9869, 0xfd9a6a, 0xfd9b6b, 0xfe9d6c, 0xfe9f6d, 0xfea16e, 0xfea36f,
      0xfea571, 0xfea772, 0xfea973, 0xfeaa74, 0xfeac76, 0xfeae77, 0xfeb078, 0xfeb27a, 0xfeb47b,
      0xfeb67c, 0xfeb77e, 0xfeb97f, 0xfebb81, 0xfebd82, 0xfebf84, 0xfec185, 0xfec287, 0xfec488,
      0xfec68a, 0xfec88c, 0xfeca8d, 0xfecc8f, 0xfecd90, 0xfecf92, 0xfed194, 0xfed395, 0xfed597,
      0xfed799, 0xfed89a, 0xfdda9c, 0xfddc9e, 0xfddea0, 0xfde0a1, 0xfde2a3, 0xfde3a5, 0xfde5a7,
      0xfde7a9, 0xfde9aa, 0xfdebac, 0xfcecae, 0xfceeb0, 0xfcf0b2, 0xfcf2b4, 0xfcf4b6, 0xfcf6b8,
      0xfcf7b9, 0xfcf9bb, 0xfcfbbd, 0xfcfdbf,
  };
  std::vector<std::uint8_t> out;
  out.reserve(3 * r.error.size());
  for (float e : r.error) {
    const double v = std::isfinite(e) ? std::clamp(static_cast<double>(e), 0.0, 1.0) : 0.0;
    const std::uint32_t c = kMagma[static_cast<std::size_t>(std::lround(255.0 * v))];
    out.push_back(static_cast<std::uint8_t>(c >> 16));
    out.push_back(static_cast<std::uint8_t>(c >> 8));
    out.push_back(static_cast<std::uint8_t>(c));
  }
  return out;
}

}  // namespace shaderfit
