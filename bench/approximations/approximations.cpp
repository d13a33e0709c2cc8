// The yardstick (issue 16, item 1): published real-time approximations, each with a float64
// reference computed here or by the library's reference/ headers, a fixed deterministic sampling of
// its domain, and the published formula's cost and errors under shaderfit's own model.
//
//   build/release/bench/approximations OUT_DIR
//
// writes OUT_DIR/<case>.csv (the input columns, then `ref`) for every case, OUT_DIR/cases.json
// (an array: name, source, inputs, domain, reference, formula, notes, rows, cost, max_abs, max_rel,
// rmse), which it also prints, and OUT_DIR/manifest.toml: every case as a `shaderfit batch` entry
// (its CSV, the published formula as the baseline, goal beat-baseline under max_abs; `--time T`
// sets the seconds per case, default 5). bench/approximations/run.py runs that batch and prints
// the table; docs/approximations.md holds the sources and the table.
//
// Contracts: every reference is float64 and deterministic (closed forms, convergent series,
// midpoint quadrature); each is cross-checked once against an independent value where one exists
// (std::erf) and the program exits 1 on disagreement. Formulas are in parse_formula's syntax over
// the case's input names only; cost is expression_cost(..., CostTarget::Instructions) (the SASS
// model); errors are error_metrics of the formula evaluated in float64 against `ref`.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "shaderfit/core/random.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/cost/per_material.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/reference/fresnel.hpp"
#include "shaderfit/reference/fv_reference.hpp"
#include "shaderfit/reference/smith_ggx.hpp"

namespace {

namespace ref = shaderfit::reference;
constexpr double kPi = 3.14159265358979323846;

// ---- Reference math that the library does not have (kept here, not in the library) ----

// erf by the everywhere-convergent series of positive terms
//   erf(x) = 2/sqrt(pi) exp(-x^2) sum_n 2^n x^(2n+1) / (1*3*...*(2n+1)),
// which has no cancellation; for x >= 6, erf(x) = 1 to double precision (erfc(6) ~ 2e-17).
double erf_series(double x) {
  if (x < 0) return -erf_series(-x);
  if (x >= 6) return 1.0;
  double term = x, sum = x;
  for (int n = 1; n < 10000 && term > 1e-18 * sum; ++n) {
    term *= 2 * x * x / (2 * n + 1);
    sum += term;
  }
  return 2 / std::sqrt(kPi) * std::exp(-x * x) * sum;
}

// Smith masking for Beckmann: G1 = 1 / (1 + Lambda(a)), a = 1 / (alpha tan(theta)),
// Lambda(a) = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)) (Walter et al. 2007, eq. 25-27).
double beckmann_g1_of_a(double a) {
  double lambda = (erf_series(a) - 1) / 2 + std::exp(-a * a) / (2 * a * std::sqrt(kPi));
  return 1 / (1 + lambda);
}
double beckmann_g1(double n_dot_v, double alpha) {
  double tan_t = std::sqrt(1 - n_dot_v * n_dot_v) / n_dot_v;
  if (tan_t == 0) return 1.0;
  return beckmann_g1_of_a(1 / (alpha * tan_t));
}

// Beckmann distribution D(h) = exp(-tan^2 / alpha^2) / (pi alpha^2 cos^4), for n.h > 0.
double beckmann_d(double n_dot_h, double alpha) {
  double c2 = n_dot_h * n_dot_h;
  double tan2 = (1 - c2) / c2;
  return std::exp(-tan2 / (alpha * alpha)) / (kPi * alpha * alpha * c2 * c2);
}

// Height-correlated Smith GGX visibility V = G2 / (4 (n.l)(n.v)) (the 1/4 folded in, as in UE4 and
// Filament, whose approximations this reference is for).
double v_smith_ggx_correlated(double n_dot_l, double n_dot_v, double alpha) {
  return ref::smith_ggx_g2_height_correlated(n_dot_l, n_dot_v, alpha) / (4 * n_dot_l * n_dot_v);
}

// The split-sum environment BRDF (Karis 2013): scale A and bias B with
//   integral f_spec(l, v) (n.l) dl = f0 A + B, for the GGX microfacet BRDF with height-correlated
// Smith G2 (library) and Schlick's Fresnel weight (1 - v.h)^5, by midpoint quadrature of the
// GGX-importance-sampled estimator G2 (v.h) / ((n.h)(n.v)) over (u, phi): u in (0, 1) maps to
// cos(theta_h) = sqrt((1 - u) / (1 + (alpha^2 - 1) u)), phi in (0, pi) by symmetry.
struct Dfg {
  double scale, bias;
};
Dfg split_sum_dfg(double roughness, double n_dot_v) {
  constexpr int kU = 1024, kPhi = 128;
  double alpha = roughness * roughness;
  double a2 = alpha * alpha;
  double vx = std::sqrt(1 - n_dot_v * n_dot_v), vz = n_dot_v;
  double sa = 0, sb = 0;
  for (int i = 0; i < kU; ++i) {
    double u = (i + 0.5) / kU;
    double ch = std::sqrt((1 - u) / (1 + (a2 - 1) * u));
    double sh = std::sqrt(1 - ch * ch);
    for (int j = 0; j < kPhi; ++j) {
      double phi = kPi * (j + 0.5) / kPhi;
      double hx = sh * std::cos(phi), hz = ch;
      double v_dot_h = vx * hx + vz * hz;
      double n_dot_l = 2 * v_dot_h * hz - vz;
      if (n_dot_l <= 0 || v_dot_h <= 0) continue;
      double g = ref::smith_ggx_g2_height_correlated(n_dot_l, n_dot_v, alpha);
      double w = g * v_dot_h / (ch * n_dot_v);
      double fc = std::pow(1 - v_dot_h, 5);
      sa += (1 - fc) * w;
      sb += fc * w;
    }
  }
  return {sa / (kU * kPhi), sb / (kU * kPhi)};
}

// Hill's fit of the ACES RRT + sRGB ODT (Stephen Hill, BakingLab ACES.hlsl, 2016), per channel.
// For a grey input the fit's input and output matrices (rows summing to 1) map grey to grey, so
// on grey it is this rational function; its output is clamped to [0, 1] as in Hill's code.
double aces_hill_grey(double v) {
  double a = v * (v + 0.0245786) - 0.000090537;
  double b = v * (0.983729 * v + 0.4329510) + 0.238081;
  return std::clamp(a / b, 0.0, 1.0);
}

// Oren and Nayar's full model (Generalization of Lambert's Reflectance Model, SIGGRAPH 1994,
// the direct term L1 of eq. 30 with its C1, C2, C3), as f pi / rho: the BRDF over Lambert's. The
// interreflection term L2 is left out, as the qualitative model leaves it out. sigma in radians.
double oren_nayar_full(double cos_i, double cos_r, double cos_phi, double sigma) {
  double ti = std::acos(cos_i), tr = std::acos(cos_r);
  double alpha = std::max(ti, tr), beta = std::min(ti, tr);
  double s2 = sigma * sigma;
  double c1 = 1 - 0.5 * s2 / (s2 + 0.33);
  double c2 = 0.45 * s2 / (s2 + 0.09) *
              (cos_phi >= 0 ? std::sin(alpha) : std::sin(alpha) - std::pow(2 * beta / kPi, 3));
  double c3 = 0.125 * s2 / (s2 + 0.09) * std::pow(4 * alpha * beta / (kPi * kPi), 2);
  return c1 + cos_phi * c2 * std::tan(beta) +
         (1 - std::abs(cos_phi)) * c3 * std::tan((alpha + beta) / 2);
}

// sRGB transfer functions (IEC 61966-2-1), exact piecewise.
double srgb_to_linear(double s) {
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}
double linear_to_srgb(double l) {
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
}

// ---- Sampling ----

// n points from a to b, both ends included.
std::vector<double> linspace(double a, double b, int n) {
  std::vector<double> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = a + (b - a) * i / (n - 1);
  return v;
}

struct Samples {
  std::vector<std::vector<double>> columns;  // one per input
  std::vector<double> ref;
};

// The full grid over the given axes (first axis slowest), with ref = f(point).
Samples grid(const std::vector<std::vector<double>>& axes,
             const std::function<double(const std::vector<double>&)>& f) {
  Samples s;
  s.columns.resize(axes.size());
  std::vector<std::size_t> idx(axes.size(), 0);
  std::vector<double> point(axes.size());
  for (;;) {
    for (std::size_t k = 0; k < axes.size(); ++k) {
      point[k] = axes[k][idx[k]];
      s.columns[k].push_back(point[k]);
    }
    s.ref.push_back(f(point));
    std::size_t k = axes.size();
    while (k > 0) {
      --k;
      if (++idx[k] < axes[k].size()) break;
      idx[k] = 0;
      if (k == 0) return s;
    }
  }
}

// n points drawn uniformly from [a, b) by Rng(seed), ascending, with ref = f(x), redrawn until
// no point's mirror -x is another point (the symmetry of such samples is found from the function,
// not from pairs of rows; docs/search.md, "Symmetric data").
Samples uniform_unmirrored(double a, double b, int n, std::uint64_t seed,
                           const std::function<double(double)>& f) {
  shaderfit::Rng rng(seed);
  std::set<double> xs;
  while (xs.size() < static_cast<std::size_t>(n)) {
    const double x = shaderfit::uniform(rng, a, b);
    if (xs.count(-x) == 0) xs.insert(x);  // a repeat is not inserted: drawn again
  }
  Samples s;
  s.columns.emplace_back(xs.begin(), xs.end());
  for (double x : s.columns[0]) s.ref.push_back(f(x));
  return s;
}

// ---- The cases ----

// A published half-interval formula in x written for the whole interval: every x becomes abs(x),
// as the published code takes |x| first (the cost model counts the shared abs once).
std::string on_abs(const std::string& formula) {
  return std::regex_replace(formula, std::regex("\\bx\\b"), "abs(x)");
}

struct Case {
  std::string name;
  std::string source;     // author, title / venue or blog, year
  std::string reference;  // how `ref` is computed
  std::string domain;     // the sampling
  std::string formula;    // the published formula, parse_formula syntax
  std::string notes;      // sign-symmetric halves, pieces left out, conventions
  std::vector<std::string> inputs;
  std::function<Samples()> sample;
  // Inputs constant per material that the published form hoists (cost/per_material.hpp): its
  // cost is then per pixel, and the search is run with --uniform.
  std::vector<std::string> uniform = {};
};

// Rows of `s` whose ref is at least `floor` (a function that spans many decades, sampled where a
// pixel shows it).
Samples at_least(Samples s, double floor) {
  Samples out;
  out.columns.resize(s.columns.size());
  for (std::size_t r = 0; r < s.ref.size(); ++r) {
    if (!(s.ref[r] >= floor)) continue;
    for (std::size_t k = 0; k < s.columns.size(); ++k) out.columns[k].push_back(s.columns[k][r]);
    out.ref.push_back(s.ref[r]);
  }
  return out;
}

std::vector<Case> make_cases() {
  std::vector<Case> c;
  auto add = [&](Case k) { c.push_back(std::move(k)); };

  // Fresnel. r0 in [0.02, 0.25] (IOR 1.33 to 3), cos in [0, 1].
  auto fresnel_grid = [] {
    return grid({linspace(0.02, 0.25, 16), linspace(0.0, 1.0, 64)}, [](const auto& p) {
      return ref::fresnel_dielectric(p[1], ref::ior_from_f0(p[0]));
    });
  };
  const std::string fresnel_ref =
      "exact unpolarised dielectric Fresnel, eta from r0 (reference/fresnel.hpp, fv_reference.hpp)";
  add({"fresnel_schlick",
       "Schlick, An Inexpensive BRDF Model for Physically-based Rendering, CGF 1994",
       fresnel_ref,
       "r0 16 in [0.02,0.25] x cos_theta 64 in [0,1]",
       "r0 + (1 - r0)*(1 - cos_theta)^5",
       "",
       {"r0", "cos_theta"},
       fresnel_grid});
  add({"fresnel_sg",
       "Karis, Real Shading in Unreal Engine 4, SIGGRAPH 2013 course (after Lagarde 2012)",
       fresnel_ref,
       "r0 16 in [0.02,0.25] x cos_theta 64 in [0,1]",
       "r0 + (1 - r0)*exp2((-5.55473*cos_theta - 6.98316)*cos_theta)",
       "",
       {"r0", "cos_theta"},
       fresnel_grid});

  // Smith masking / visibility. Cosines from 0.05 (0.1 for V, whose values grow as 1/cos).
  add({"g1_ggx_schlick",
       "Karis, Real Shading in Unreal Engine 4, SIGGRAPH 2013 (Schlick G1, k = alpha/2)",
       "Smith G1 for GGX, closed form (reference/smith_ggx.hpp)",
       "nv 64 in [0.05,1] x alpha 16 in [0.05,1]",
       "nv/(nv*(1 - alpha/2) + alpha/2)",
       "",
       {"nv", "alpha"},
       [] {
         return grid({linspace(0.05, 1, 64), linspace(0.05, 1, 16)},
                     [](const auto& p) { return ref::smith_ggx_g1(p[0], p[1]); });
       }});
  auto v_grid = [] {
    return grid({linspace(0.1, 1, 16), linspace(0.1, 1, 16), linspace(0.05, 1, 8)},
                [](const auto& p) { return v_smith_ggx_correlated(p[0], p[1], p[2]); });
  };
  const std::string v_ref =
      "height-correlated Smith GGX V = G2/(4 nl nv), G2 closed form (reference/smith_ggx.hpp)";
  const std::string v_dom = "nl 16 x nv 16 in [0.1,1] x alpha 8 in [0.05,1]";
  add({"v_ggx_hammon",
       "Hammon, PBR Diffuse Lighting for GGX+Smith Microsurfaces, GDC 2017 (Filament "
       "V_SmithGGXCorrelatedFast)",
       v_ref,
       v_dom,
       "0.5/(2*nl*nv + alpha*(nl + nv - 2*nl*nv))",
       "lerp expanded",
       {"nl", "nv", "alpha"},
       v_grid});
  add({"v_ggx_schlick",
       "Karis, Real Shading in Unreal Engine 4, SIGGRAPH 2013 (Vis_Schlick, k = alpha/2)",
       v_ref,
       v_dom,
       "0.25/((nl*(1 - alpha/2) + alpha/2)*(nv*(1 - alpha/2) + alpha/2))",
       "",
       {"nl", "nv", "alpha"},
       v_grid});
  add({"v_ggx_separable",
       "Walter et al., Microfacet Models for Refraction, EGSR 2007 (separable Smith G1(l) G1(v)); "
       "Heitz, JCGT 2014",
       v_ref,
       v_dom,
       "1/((nl + sqrt(alpha^2 + (1 - alpha^2)*nl^2))*(nv + sqrt(alpha^2 + (1 - alpha^2)*nv^2)))",
       "uncorrelated form as an approximation of the correlated one",
       {"nl", "nv", "alpha"},
       v_grid});
  add({"g1_beckmann_schlick",
       "Schlick, An Inexpensive BRDF Model, CGF 1994 (k = alpha sqrt(2/pi))",
       "Smith G1 for Beckmann with erf by series (here)",
       "nv 64 in [0.05,1] x alpha 16 in [0.05,1]",
       "nv/(nv*(1 - 0.7978845608*alpha) + 0.7978845608*alpha)",
       "sqrt(2/pi) = 0.7978845608",
       {"nv", "alpha"},
       [] {
         return grid({linspace(0.05, 1, 64), linspace(0.05, 1, 16)},
                     [](const auto& p) { return beckmann_g1(p[0], p[1]); });
       }});
  add({"g1_beckmann_walter",
       "Walter et al., Microfacet Models for Refraction through Rough Surfaces, EGSR 2007, eq. 27",
       "Smith G1 for Beckmann in a = 1/(alpha tan), erf by series (here)",
       "a 512 in [0.02,1.6]",
       "(3.535*a + 2.181*a^2)/(1 + 2.276*a + 2.577*a^2)",
       "only the rational piece a < 1.6 (the published form is 1 above: a select)",
       {"a"},
       [] {
         return grid({linspace(0.02, 1.6, 512)},
                     [](const auto& p) { return beckmann_g1_of_a(p[0]); });
       }});
  add({"g1_beckmann_walter_full",
       "Walter et al., Microfacet Models for Refraction through Rough Surfaces, EGSR 2007, eq. 27",
       "Smith G1 for Beckmann in a = 1/(alpha tan), erf by series (here)",
       "a 1024 in [0.02,4]",
       "select(a >= 1.6, 1, (3.535*a + 2.181*a^2)/(1 + 2.276*a + 2.577*a^2))",
       "both pieces: the rational one for a < 1.6, 1 above (the published select)",
       {"a"},
       [] {
         return grid({linspace(0.02, 4, 1024)},
                     [](const auto& p) { return beckmann_g1_of_a(p[0]); });
       }});
  add({"d_blinn_phong_beckmann",
       "Walter et al., EGSR 2007 (Blinn-Phong exponent 2/alpha^2 - 2, normalised (n+2)/(2 pi))",
       "Beckmann D, closed form (here)",
       "nh 64 in [0.05,1] x alpha 16 in [0.1,1]",
       "pow(nh, 2/alpha^2 - 2)/(pi*alpha^2)",
       "high dynamic range: D up to 1/(pi 0.01) = 32",
       {"nh", "alpha"},
       [] {
         return grid({linspace(0.05, 1, 64), linspace(0.1, 1, 16)},
                     [](const auto& p) { return beckmann_d(p[0], p[1]); });
       }});
  add({"phong_lobe_sg",
       "Lagarde, Spherical Gaussian approximation for Blinn-Phong, Phong and Fresnel, blog 2012",
       "x^n, closed form",
       "x 64 in [0,1] x n 16 = 2^(0..8) geometric",
       "exp((n + 0.775)*(x - 1))",
       "",
       {"x", "n"},
       [] {
         std::vector<double> n;
         n.reserve(16);
         for (int i = 0; i < 16; ++i) n.push_back(std::pow(2.0, 8.0 * i / 15));
         return grid({linspace(0, 1, 64), n}, [](const auto& p) { return std::pow(p[0], p[1]); });
       }});

  // Oren-Nayar: four inputs, cosines from 0.1 (tan beta <= 10).
  add({"oren_nayar_qualitative",
       "Oren and Nayar, Generalization of Lambert's Reflectance Model, SIGGRAPH 1994 (qualitative "
       "model)",
       "Oren-Nayar full model, direct term L1 with C1, C2, C3, as f pi / rho (here)",
       "ci 8 x cr 8 in [0.1,1] x cphi 9 in [-1,1] x sigma 6 in [0,1] rad",
       "1 - 0.5*sigma^2/(sigma^2 + 0.33) + 0.45*sigma^2/(sigma^2 + 0.09)*max(cphi, 0)*"
       "sqrt(1 - min(ci, cr)^2)*sqrt(1 - max(ci, cr)^2)/max(ci, cr)",
       "sin(alpha) tan(beta) written with cosines: alpha = max angle = min cosine; interreflection "
       "L2 "
       "left out of both",
       {"ci", "cr", "cphi", "sigma"},
       [] {
         return grid(
             {linspace(0.1, 1, 8), linspace(0.1, 1, 8), linspace(-1, 1, 9), linspace(0, 1, 6)},
             [](const auto& p) { return oren_nayar_full(p[0], p[1], p[2], p[3]); });
       }});

  // Environment BRDF (split sum), Karis's mobile fit: scale and bias separately.
  const std::string env_src =
      "Karis, Physically Based Shading on Mobile, Unreal Engine blog 2014 (EnvBRDFApprox)";
  const std::string env_ref =
      "split-sum DFG of GGX with height-correlated Smith by 1024x128 midpoint quadrature (here)";
  const std::string env_dom = "rough 16 in [0,1] x nv 32 in [0.03,1]";
  const std::string a004 =
      "(min((1 - rough)^2, exp2(-9.28*nv))*(1 - rough) + 0.0425 - 0.0275*rough)";
  add({"envbrdf_karis_scale",
       env_src,
       env_ref,
       env_dom,
       "-1.04*" + a004 + " + 1.04 - 0.572*rough",
       "AB.x; the reference differs from UE4's LUT in its Smith term",
       {"rough", "nv"},
       [] {
         return grid({linspace(0, 1, 16), linspace(0.03, 1, 32)},
                     [](const auto& p) { return split_sum_dfg(p[0], p[1]).scale; });
       }});
  add({"envbrdf_karis_bias",
       env_src,
       env_ref,
       env_dom,
       "1.04*" + a004 + " + 0.022*rough - 0.04",
       "AB.y",
       {"rough", "nv"},
       [] {
         return grid({linspace(0, 1, 16), linspace(0.03, 1, 32)},
                     [](const auto& p) { return split_sum_dfg(p[0], p[1]).bias; });
       }});

  // Tonemapping.
  add({"aces_narkowicz",
       "Narkowicz, ACES Filmic Tone Mapping Curve, blog 2016 (input pre-exposed by 0.6)",
       "Hill's RRT+ODT fit on grey, clamped to [0,1] (ACES.hlsl 2016; a fit itself, not the ACES "
       "CTL)",
       "x = 16 t^2, t 512 in [0,1]",
       "saturate(0.6*x*(2.51*0.6*x + 0.03)/(0.6*x*(2.43*0.6*x + 0.59) + 0.14))",
       "",
       {"x"},
       [] {
         std::vector<double> x;
         for (double t : linspace(0, 1, 512)) x.push_back(16 * t * t);
         return grid({x}, [](const auto& p) { return aces_hill_grey(p[0]); });
       }});

  // sRGB transfer curves.
  auto s_axis = [] { return linspace(0, 1, 1024); };
  add({"srgb_to_linear_pow22",
       "gamma 2.2, e.g. Gritz and d'Eon, The Importance of Being Linear, GPU Gems 3, 2007",
       "IEC 61966-2-1 piecewise",
       "s 1024 in [0,1]",
       "pow(s, 2.2)",
       "",
       {"s"},
       [&] { return grid({s_axis()}, [](const auto& p) { return srgb_to_linear(p[0]); }); }});
  add({"srgb_to_linear_cubic",
       "Taylor, sRGB Approximations for HLSL, Chilliant blog 2012",
       "IEC 61966-2-1 piecewise",
       "s 1024 in [0,1]",
       "s*(s*(s*0.305306011 + 0.682171111) + 0.012522878)",
       "",
       {"s"},
       [&] { return grid({s_axis()}, [](const auto& p) { return srgb_to_linear(p[0]); }); }});
  add({"linear_to_srgb_pow",
       "gamma 1/2.2, e.g. Gritz and d'Eon, GPU Gems 3, 2007",
       "IEC 61966-2-1 piecewise",
       "l 1024 in [0,1]",
       "pow(l, 0.45454545454545453)",
       "",
       {"l"},
       [&] { return grid({s_axis()}, [](const auto& p) { return linear_to_srgb(p[0]); }); }});
  add({"linear_to_srgb_sqrt3",
       "Taylor, sRGB Approximations for HLSL, Chilliant blog 2012 (three roots)",
       "IEC 61966-2-1 piecewise",
       "l 1024 in [0,1]",
       "0.585122381*sqrt(l) + 0.783140355*sqrt(sqrt(l)) - 0.368262736*sqrt(sqrt(sqrt(l)))",
       "",
       {"l"},
       [&] { return grid({s_axis()}, [](const auto& p) { return linear_to_srgb(p[0]); }); }});
  add({"linear_to_srgb_sqrt4",
       "Taylor, sRGB Approximations for HLSL, Chilliant blog 2012 (roots and linear term)",
       "IEC 61966-2-1 piecewise",
       "l 1024 in [0,1]",
       "0.662002687*sqrt(l) + 0.684122060*sqrt(sqrt(l)) - 0.323583601*sqrt(sqrt(sqrt(l))) - "
       "0.0225411470*l",
       "",
       {"l"},
       [&] { return grid({s_axis()}, [](const auto& p) { return linear_to_srgb(p[0]); }); }});

  // acos: the published forms are r(|x|) = sqrt(1 - |x|) P(|x|) reflected to pi - r for x < 0 (a
  // select in the published code). Each is measured twice: on x >= 0 alone (the half where r
  // is the whole formula, cases without a suffix) and on the full interval [-1, 1] with the
  // reflection written as the published code does (cases `_full`).
  struct Published {
    std::string name, source, formula;
  };
  const std::vector<Published> acos_forms = {
      {"acos_as_4445", "Abramowitz and Stegun, Handbook of Mathematical Functions, 1964, 4.4.45",
       "sqrt(1 - x)*(1.5707288 + x*(-0.2121144 + x*(0.0742610 - 0.0187293*x)))"},
      {"acos_eberly1", "Eberly, Geometric Tools ACosEstimate, degree 1 (Lagarde's acosFast, 2014)",
       "sqrt(1 - x)*(1.5707963267948966 - 0.15658276442180141*x)"},
      {"acos_eberly2", "Eberly, Geometric Tools ACosEstimate, degree 2",
       "sqrt(1 - x)*(1.5707963267948966 + x*(-0.20347053865798365 + 0.046887774236182234*x))"},
      {"acos_eberly3", "Eberly, Geometric Tools ACosEstimate, degree 3",
       "sqrt(1 - x)*(1.5707963267948966 + x*(-0.21253291899190285 + x*(0.074773789639484223 - "
       "0.018823635069382449*x)))"},
  };
  const std::string half = "x >= 0 half only (x < 0 is pi - f(-x): a select)";
  for (const Published& f : acos_forms)
    add({f.name, f.source, "libm acos (float64)", "x 1024 in [0,1]", f.formula, half, {"x"}, [] {
           return grid({linspace(0, 1, 1024)}, [](const auto& p) { return std::acos(p[0]); });
         }});
  for (const Published& f : acos_forms) {
    const std::string r = on_abs(f.formula);
    add({f.name + "_full",
         f.source,
         "libm acos (float64)",
         "x 1025 in [-1,1]",
         "select(x >= 0, " + r + ", pi - " + r + ")",
         "full interval: r = f(|x|), pi - r for x < 0 (the published code's reflection)",
         {"x"},
         [] {
           return grid({linspace(-1, 1, 1025)}, [](const auto& p) { return std::acos(p[0]); });
         }});
  }

  // atan on [-1, 1]: both forms are odd and written with abs, so the whole interval is sampled.
  auto atan_grid = [] {
    return grid({linspace(-1, 1, 1025)}, [](const auto& p) { return std::atan(p[0]); });
  };
  add({"atan_rajan",
       "Rajan et al., Efficient Approximations for the Arctangent Function, IEEE SPM 2006",
       "libm atan (float64)",
       "x 1025 in [-1,1]",
       "0.7853981633974483*x - x*(abs(x) - 1)*(0.2447 + 0.0663*abs(x))",
       "",
       {"x"},
       atan_grid});
  add({"atan_eberly11",
       "Eberly, Geometric Tools (odd degree-11 minimax on [-1,1])",
       "libm atan (float64)",
       "x 1025 in [-1,1]",
       "x*(1 + x^2*(-0.33294527685374087 + x^2*(0.19498657165383548 + x^2*(-0.11921576270475498 + "
       "x^2*(0.05506335136696805 - 0.012490720064867844*x^2)))))",
       "",
       {"x"},
       atan_grid});
  add({"atan_mazzoli",
       "Mazzoli, Speeding up atan2f by 50x, blog 2021 (odd degree-11 polynomial)",
       "libm atan (float64)",
       "x 1025 in [-1,1]",
       "x*(0.99997726 + x^2*(-0.33262347 + x^2*(0.19354346 + x^2*(-0.11643287 + x^2*(0.05265332 - "
       "0.01172120*x^2)))))",
       "",
       {"x"},
       atan_grid});

  // erf: the published forms are sign(x) f(|x|) (odd). Measured on x >= 0 alone (no suffix) and
  // on [-4, 4] with the sign written as the published code does (`_full`).
  const std::string erf_ref = "erf by its positive-term series (here; checked against std::erf)";
  const std::string erf_half = "x >= 0 half only (x < 0 is -f(-x): sign)";
  const std::string erf_full = "full interval: sign(x) f(|x|) (the published code's symmetry)";
  const std::string winitzki_a = "; a = 8(pi - 3)/(3 pi (4 - pi))";
  const std::vector<Published> erf_forms = {
      {"erf_as_7125", "Abramowitz and Stegun 1964, 7.1.25 (after Hastings 1955)",
       "1 - (0.3480242/(1 + 0.47047*x) - 0.0958798/(1 + 0.47047*x)^2 + 0.7478556/(1 + "
       "0.47047*x)^3)*exp(-x^2)"},
      {"erf_as_7126", "Abramowitz and Stegun 1964, 7.1.26 (after Hastings 1955)",
       "1 - (1/(1 + 0.3275911*x))*(0.254829592 + (1/(1 + 0.3275911*x))*(-0.284496736 + (1/(1 + "
       "0.3275911*x))*"
       "(1.421413741 + (1/(1 + 0.3275911*x))*(-1.453152027 + 1.061405429/(1 + "
       "0.3275911*x)))))*exp(-x^2)"},
      {"erf_as_7127", "Abramowitz and Stegun 1964, 7.1.27 (after Hastings 1955)",
       "1 - 1/(1 + x*(0.278393 + x*(0.230389 + x*(0.000972 + 0.078108*x))))^4"},
      {"erf_winitzki",
       "Winitzki, A handy approximation for the error function and its inverse, 2008",
       "sqrt(1 - exp(-x^2*(4/pi + 0.1400122886866665*x^2)/(1 + 0.1400122886866665*x^2)))"},
  };
  for (const Published& f : erf_forms)
    add({f.name,
         f.source,
         erf_ref,
         "x 1024 in [0,4]",
         f.formula,
         erf_half + (f.name == "erf_winitzki" ? winitzki_a : ""),
         {"x"},
         [] {
           return grid({linspace(0, 4, 1024)}, [](const auto& p) { return erf_series(p[0]); });
         }});
  for (const Published& f : erf_forms)
    add({f.name + "_full",
         f.source,
         erf_ref,
         "x 1025 in [-4,4]",
         "sign(x)*(" + on_abs(f.formula) + ")",
         erf_full + (f.name == "erf_winitzki" ? winitzki_a : ""),
         {"x"},
         [] {
           return grid({linspace(-4, 4, 1025)}, [](const auto& p) { return erf_series(p[0]); });
         }});

  // Parabolic sine on [-pi, pi]: odd, written with abs.
  auto sin_grid = [] {
    return grid({linspace(-kPi, kPi, 1025)}, [](const auto& p) { return std::sin(p[0]); });
  };
  const std::string parabola = "(1.2732395447351628*x - 0.40528473456935109*x*abs(x))";
  add({"sin_parabolic",
       "Capen (Nick), Fast and accurate sine/cosine, devmaster.net forum 2006",
       "libm sin (float64)",
       "x 1025 in [-pi,pi]",
       parabola,
       "4/pi and 4/pi^2 as literals",
       {"x"},
       sin_grid});
  add({"sin_parabolic_refined",
       "Capen (Nick), Fast and accurate sine/cosine, devmaster.net 2006 (P = 0.225)",
       "libm sin (float64)",
       "x 1025 in [-pi,pi]",
       "0.225*(" + parabola + "*abs(" + parabola + ") - " + parabola + ") + " + parabola,
       "",
       {"x"},
       sin_grid});

  // The symmetric cases above (acos and erf `_full`, atan, the parabolic sines) on 20,000 uniform
  // random points of the same interval with no mirrored pair (issue 27): the same formulas and
  // references, each named NAME_uniform (NAME without `_full`).
  struct Interval {
    std::string prefix;
    double lo, hi;
    std::string text;
    std::function<double(double)> f;
  };
  const std::vector<Interval> intervals = {
      {"acos_", -1, 1, "[-1,1)", [](double x) { return std::acos(x); }},
      {"atan_", -1, 1, "[-1,1)", [](double x) { return std::atan(x); }},
      {"erf_", -4, 4, "[-4,4)", erf_series},
      {"sin_parabolic", -kPi, kPi, "[-pi,pi)", [](double x) { return std::sin(x); }},
  };
  // Per-material variants: the cases whose published form computes part of itself once per
  // material, with that input uniform (the same data unless said).
  struct MaterialVariant {
    std::string name;
    std::vector<std::string> uniform;
    std::string hoisted;  // what the published form computes per material
  };
  const std::vector<MaterialVariant> material = {
      {"fresnel_schlick", {"r0"}, "1 - r0"},
      {"v_ggx_schlick", {"alpha"}, "k = alpha/2 and 1 - k"},
      {"phong_lobe_sg", {"n"}, "n + 0.775"},
      {"oren_nayar_qualitative", {"sigma"}, "A and B from sigma^2"},
  };
  std::vector<Case> per_material;
  for (const Case& k : c) {
    for (const MaterialVariant& m : material) {
      if (k.name != m.name) continue;
      Case u = k;
      u.name = k.name + "_material";
      u.uniform = m.uniform;
      u.notes = "`" + k.name + "` with " + m.uniform.front() +
                " per material (hoisted: " + m.hoisted + ")" +
                (k.notes.empty() ? "" : "; " + k.notes);
      per_material.push_back(std::move(u));
    }
  }
  // Blinn-Phong for Beckmann as issue 28 sets it: alpha per material in [0.05, 0.5], NoH in
  // [0.01, 1] where D >= 0.01 (four decades).
  per_material.push_back(
      {"d_blinn_phong_beckmann_material",
       "Walter et al., EGSR 2007 (Blinn-Phong exponent 2/alpha^2 - 2, normalised (n+2)/(2 pi))",
       "Beckmann D, closed form (here)",
       "nh 64 in [0.01,1] x alpha 16 in [0.05,0.5], rows with D >= 0.01",
       "pow(nh, 2/alpha^2 - 2)/(pi*alpha^2)",
       "alpha per material (hoisted: the exponent and log2(pi alpha^2)); D from 0.01 to 127",
       {"nh", "alpha"},
       [] {
         return at_least(grid({linspace(0.01, 1, 64), linspace(0.05, 0.5, 16)},
                              [](const auto& p) { return beckmann_d(p[0], p[1]); }),
                         0.01);
       },
       {"alpha"}});
  // Walter's G1 in (nv, alpha) rather than a: 1/alpha per material.
  per_material.push_back(
      {"g1_beckmann_walter_material",
       "Walter et al., Microfacet Models for Refraction through Rough Surfaces, EGSR 2007, eq. 27",
       "Smith G1 for Beckmann, erf by series (here)",
       "nv 64 in [0.05,0.99] x alpha 16 in [0.05,0.5]",
       "select(nv/alpha*rsqrt(1 - nv^2) - 1.6 >= 0, 1, (3.535*(nv/alpha*rsqrt(1 - nv^2)) + "
       "2.181*(nv/alpha*rsqrt(1 - nv^2))^2)/(1 + 2.276*(nv/alpha*rsqrt(1 - nv^2)) + "
       "2.577*(nv/alpha*rsqrt(1 - nv^2))^2))",
       "a = nv/(alpha sqrt(1 - nv^2)) with 1/alpha per material; both pieces (the select)",
       {"nv", "alpha"},
       [] {
         return grid({linspace(0.05, 0.99, 64), linspace(0.05, 0.5, 16)},
                     [](const auto& p) { return beckmann_g1(p[0], p[1]); });
       },
       {"alpha"}});
  c.insert(c.end(), per_material.begin(), per_material.end());

  constexpr int kUniformRows = 20000;
  constexpr std::uint64_t kUniformSeed = 27;
  std::vector<Case> variants;
  for (const Case& k : c) {
    const bool full = k.name.size() > 5 && k.name.ends_with("_full");
    for (const Interval& in : intervals) {
      const bool odd_case = in.prefix == "atan_" || in.prefix == "sin_parabolic";
      if (!k.name.starts_with(in.prefix) || full == odd_case) continue;
      Case u = k;
      u.name = (full ? k.name.substr(0, k.name.size() - 5) : k.name) + "_uniform";
      u.domain = "x " + std::to_string(kUniformRows) + " uniform random in " + in.text +
                 " (seed 27), no mirrored pair";
      u.notes = "`" + k.name + "` on unmirrored samples" + (k.notes.empty() ? "" : "; " + k.notes);
      u.sample = [in] {
        return uniform_unmirrored(in.lo, in.hi, kUniformRows, kUniformSeed, in.f);
      };
      variants.push_back(std::move(u));
    }
  }
  c.insert(c.end(), variants.begin(), variants.end());
  return c;
}

// Checks the references that have an independent value: exits 1 on disagreement.
bool references_agree() {
  for (double x = 0; x <= 6.5; x += 0.01) {
    if (std::abs(erf_series(x) - std::erf(x)) > 1e-14) {
      std::fprintf(stderr, "approximations: erf series disagrees with std::erf at %g\n", x);
      return false;
    }
  }
  // DFG at roughness 0 is exactly (1 - Fc, Fc); A + B at full roughness lies in (0, 1).
  Dfg d = split_sum_dfg(0.0, 0.5);
  double fc = std::pow(0.5, 5);
  if (std::abs(d.scale - (1 - fc)) > 1e-9 || std::abs(d.bias - fc) > 1e-9) {
    std::fprintf(stderr, "approximations: DFG quadrature wrong at roughness 0\n");
    return false;
  }
  return true;
}

// A TOML basic string.
std::string toml_string(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// The yardstick as a batch manifest: one entry per case, its CSV beside the manifest, the
// published formula the baseline and the goal to beat it (at most its cost and its max |error|:
// run.py's rule). The search is not started from the published formula, so that the table
// compares a search with the formula, not a refit of it.
void write_manifest(const std::filesystem::path& dir, const nlohmann::json& cases, double time_s) {
  std::ofstream toml(dir / "manifest.toml");
  toml << "# The yardstick of bench/approximations (docs/approximations.md), made by\n"
          "# build/release/bench/approximations; run with shaderfit batch (run.py does).\n\n"
          "[defaults]\n"
       << "time = " << time_s << "\n"
       << "loss = \"max_abs\"\nseed = 1\noperators = \"auto\"\n"
          "evolution_operators = \"auto\"\ngoal = \"beat-baseline\"\n"
          "start_from_baseline = false\n";
  for (const auto& c : cases) {
    toml << "\n[[function]]\nname = " << toml_string(c["name"])
         << "\ndata = " << toml_string(c["name"].get<std::string>() + ".csv") << "\ninputs = [";
    const auto inputs = c["inputs"].get<std::vector<std::string>>();
    for (std::size_t i = 0; i < inputs.size(); ++i)
      toml << (i ? ", " : "") << toml_string(inputs[i]);
    toml << "]\ntarget = \"ref\"\nbaseline = " << toml_string(c["formula"]) << "\n";
    const auto uniform = c["uniform"].get<std::vector<std::string>>();
    if (!uniform.empty()) {
      toml << "uniform = [";
      for (std::size_t i = 0; i < uniform.size(); ++i)
        toml << (i ? ", " : "") << toml_string(uniform[i]);
      toml << "]\n";
    }
  }
  if (!toml) throw std::runtime_error("cannot write " + (dir / "manifest.toml").string());
}

// Writes every case's CSV into `dir`, and the manifest, and returns the cases' JSON; throws on any
// failure.
nlohmann::json write_cases(const std::filesystem::path& dir, double time_s) {
  std::filesystem::create_directories(dir);
  nlohmann::json all = nlohmann::json::array();
  for (const Case& k : make_cases()) {
    Samples s = k.sample();
    std::size_t n = s.ref.size();
    {
      std::ofstream csv(dir / (k.name + ".csv"));
      for (const auto& in : k.inputs) csv << in << ',';
      csv << "ref\n";
      char buf[32];
      for (std::size_t r = 0; r < n; ++r) {
        for (const auto& col : s.columns) {
          std::snprintf(buf, sizeof buf, "%.17g,", col[r]);
          csv << buf;
        }
        std::snprintf(buf, sizeof buf, "%.17g\n", s.ref[r]);
        csv << buf;
      }
      if (!csv) throw std::runtime_error("cannot write " + (dir / (k.name + ".csv")).string());
    }
    shaderfit::ParseOptions opts;
    opts.variables = k.inputs;
    opts.source = k.name;
    shaderfit::Expression e = shaderfit::parse_formula(k.formula, opts);
    std::vector<const double*> cols;
    cols.reserve(s.columns.size());
    for (const auto& col : s.columns) cols.push_back(col.data());
    std::vector<double> pred(n);
    shaderfit::evaluate(e, cols, pred, {.threads = 1});
    shaderfit::ErrorMetrics m = shaderfit::error_metrics(pred, s.ref);
    const shaderfit::SplitCost split =
        shaderfit::split_instruction_count(e, k.uniform, shaderfit::InstructionTarget::Sass);
    all.push_back({{"name", k.name},
                   {"source", k.source},
                   {"reference", k.reference},
                   {"domain", k.domain},
                   {"formula", k.formula},
                   {"notes", k.notes},
                   {"inputs", k.inputs},
                   {"rows", n},
                   {"uniform", k.uniform},
                   {"cost", split.per_pixel},
                   {"material_cost", split.per_material},
                   {"max_abs", m.max_abs},
                   {"max_rel", m.max_rel},
                   {"rmse", m.rmse},
                   {"nonfinite", m.nonfinite}});
  }
  write_manifest(dir, all, time_s);
  std::ofstream json(dir / "cases.json");
  json << all.dump(1) << '\n';
  if (!json) throw std::runtime_error("cannot write " + (dir / "cases.json").string());
  return all;
}

}  // namespace

int main(int argc, char** argv) {
  double time_s = 5;
  if (argc == 4 && std::string(argv[2]) == "--time") time_s = std::atof(argv[3]);
  if ((argc != 2 && argc != 4) || std::string(argv[1]) == "--help" || !(time_s > 0)) {
    std::fprintf(stderr,
                 "usage: approximations OUT_DIR [--time SECONDS]\n"
                 "writes OUT_DIR/<case>.csv (inputs, ref), OUT_DIR/cases.json and "
                 "OUT_DIR/manifest.toml (SECONDS per case, default 5)\n");
    return 2;
  }
  try {
    if (!references_agree()) return 1;
    std::cout << write_cases(argv[1], time_s).dump(1) << '\n';
    return 0;
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "approximations: %s\n", ex.what());
  } catch (...) {
    std::fprintf(stderr, "approximations: unknown error\n");
  }
  return 1;
}
