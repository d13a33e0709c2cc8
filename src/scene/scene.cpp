#include "shaderfit/scene/scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/reference/builtin.hpp"
#include "shaderfit/reference/fresnel.hpp"
#include "shaderfit/reference/fv_reference.hpp"
#include "shaderfit/reference/smith_ggx.hpp"

namespace shaderfit {

std::optional<SceneKind> scene_kind_from_name(std::string_view name) {
  if (name == "sphere") return SceneKind::Sphere;
  if (name == "plane") return SceneKind::Plane;
  return std::nullopt;
}

std::string_view scene_kind_name(SceneKind kind) {
  return kind == SceneKind::Plane ? "plane" : "sphere";
}

std::string_view scene_kind_names() { return "sphere, plane"; }

std::optional<ShadingTerm> shading_term_from_name(std::string_view name) {
  if (name == "F") return ShadingTerm::F;
  if (name == "V") return ShadingTerm::V;
  if (name == "D") return ShadingTerm::D;
  if (name == "FV") return ShadingTerm::FV;
  return std::nullopt;
}

SceneSpec scene_spec_from_names(std::string_view kind, std::string_view term) {
  SceneSpec spec;
  const std::optional<SceneKind> k = scene_kind_from_name(kind);
  if (!k)
    throw Error("unknown scene '" + std::string(kind) +
                    "' (known: " + std::string(scene_kind_names()) + ")",
                SourceLocation{"SceneSpec::kind"});
  spec.kind = *k;
  if (!term.empty()) {
    spec.term = shading_term_from_name(term);
    if (!spec.term)
      throw Error("unknown term '" + std::string(term) + "' (known: F, V, D, FV)",
                  SourceLocation{"SceneSpec::term"});
  }
  return spec;
}

std::string_view shading_term_name(ShadingTerm term) {
  switch (term) {
    case ShadingTerm::F: return "F";
    case ShadingTerm::V: return "V";
    case ShadingTerm::D: return "D";
    case ShadingTerm::FV: return "FV";
  }
  return "F";
}

namespace {

constexpr std::string_view kQuantities[] = {"n_dot_l",   "n_dot_v", "n_dot_h", "v_dot_h", "l_dot_h",
                                            "roughness", "alpha",   "f0",      "ior"};
enum Quantity : std::size_t { NL, NV, NH, VH, LH, Rough, Alpha, F0, Ior, kCount };

using Vec = std::array<double, 3>;

Vec operator+(Vec a, Vec b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec operator-(Vec a, Vec b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec operator*(double s, Vec a) { return {s * a[0], s * a[1], s * a[2]}; }
double dot(Vec a, Vec b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec normalized(Vec a) { return (1.0 / std::sqrt(dot(a, a))) * a; }

struct PointLight {
  Vec position;
  double intensity;  // radiance scale: irradiance = intensity / distance^2 at normal incidence
};

// Diffuse colours of the materials in turn (linear RGB), pale enough that the white highlights
// show on all of them.
constexpr Vec kAlbedo[] = {{0.50, 0.22, 0.16},
                           {0.20, 0.36, 0.55},
                           {0.42, 0.42, 0.40},
                           {0.22, 0.45, 0.22},
                           {0.55, 0.45, 0.20}};
constexpr double kAmbient = 0.04;
constexpr Vec kSky = {0.30, 0.36, 0.45};
constexpr Vec kBackdrop = {0.05, 0.05, 0.06};

// A surface point as the camera sees it.
struct Hit {
  Vec p, n, v;  // position, unit normal, unit direction towards the camera
  std::size_t material;
};

class Renderer {
 public:
  explicit Renderer(SceneSpec spec) : spec_(std::move(spec)) {
    out_.spec = spec_;
    const int s = spec_.size;
    const int cells = static_cast<int>(spec_.materials.size());
    out_.width = spec_.kind == SceneKind::Sphere ? s * cells : 2 * s;
    out_.height = s;
    out_.quantities.assign(kCount, {});
    out_.base.assign(
        static_cast<std::size_t>(out_.width) * static_cast<std::size_t>(out_.height) * 3, 0.0);
  }

  SceneSamples run() && {
    for (int y = 0; y < out_.height; ++y)
      for (int x = 0; x < out_.width; ++x) pixel(x, y);
    return std::move(out_);
  }

 private:
  void pixel(int x, int y) {
    const auto index = static_cast<std::uint32_t>(y * out_.width + x);
    const std::optional<Hit> hit = spec_.lobe                        ? lobe_hit(x, y)
                                   : spec_.kind == SceneKind::Sphere ? sphere_hit(x, y)
                                                                     : plane_hit(x, y);
    double* base = &out_.base[3 * std::size_t{index}];
    if (!hit) {
      const Vec bg = spec_.lobe                        ? Vec{NAN, NAN, NAN}
                     : spec_.kind == SceneKind::Sphere ? kBackdrop
                                                       : kSky;
      for (int c = 0; c < 3; ++c) base[c] = bg[static_cast<std::size_t>(c)];
      return;
    }
    const SceneMaterial& m = spec_.materials[hit->material];
    const Vec albedo = kAlbedo[hit->material % std::size(kAlbedo)];
    if (!spec_.lobe)
      for (int c = 0; c < 3; ++c) base[c] = kAmbient * albedo[static_cast<std::size_t>(c)];
    const double nv = dot(hit->n, hit->v);
    if (!(nv > 0)) return;
    if (spec_.lobe) {
      add_light(*hit, index, m, normalized(spec_.lobe->direction), spec_.lobe->irradiance, nullptr);
      return;
    }
    for (const PointLight& light : lights()) {
      const Vec to_light = light.position - hit->p;
      const double d2 = dot(to_light, to_light);
      add_light(*hit, index, m, normalized(to_light), light.intensity / d2, &albedo);
    }
  }

  // The sample of a light from unit direction l with irradiance e (at normal incidence) at a
  // surface point whose n.v > 0, when it lights it; its diffuse part joins the pixel's base when
  // an albedo is given.
  void add_light(const Hit& hit, std::uint32_t index, const SceneMaterial& m, const Vec& l,
                 double e, const Vec* albedo) {
    const double alpha = m.roughness * m.roughness;
    const double nv = dot(hit.n, hit.v);
    const double nl = dot(hit.n, l);
    if (!(nl > 0)) return;
    if (albedo != nullptr) {
      double* base = &out_.base[3 * std::size_t{index}];
      for (int c = 0; c < 3; ++c)
        base[c] += e * nl * (*albedo)[static_cast<std::size_t>(c)] / std::numbers::pi;
    }
    const Vec h = normalized(l + hit.v);
    const double nh = std::max(dot(hit.n, h), 0.0), vh = std::clamp(dot(hit.v, h), 0.0, 1.0);
    // The factors besides the term, in reference/'s convention: specular = D F V / 4 with
    // V = G2 / ((n.l)(n.v)).
    const double D = reference::ggx_distribution(nh, alpha);
    const double F = reference::fresnel_dielectric(vh, reference::ior_from_f0(m.f0));
    const double V = reference::smith_ggx_g2_height_correlated(nl, nv, alpha) / (nl * nv);
    double others = 0;
    switch (*spec_.term) {
      case ShadingTerm::F: others = D * V; break;
      case ShadingTerm::V: others = D * F; break;
      case ShadingTerm::D: others = F * V; break;
      case ShadingTerm::FV: others = D; break;
    }
    const double q[kCount] = {
        nl, nv, nh, vh, vh, m.roughness, alpha, m.f0, reference::ior_from_f0(m.f0)};
    for (std::size_t k = 0; k < kCount; ++k) out_.quantities[k].push_back(q[k]);
    out_.pixel.push_back(index);
    out_.coefficient.push_back(e * nl * others / 4);
  }

  // Cell by cell: a unit sphere touching the cell's edges, seen along -z by an orthographic
  // camera; both coordinates are measured from the cell's lower left corner.
  std::optional<Hit> lobe_hit(int x, int y) const {
    const int s = spec_.size;
    const double u = 2.0 * ((x % s) + 0.5) / s - 1.0, w = 2.0 * ((s - 1 - y) + 0.5) / s - 1.0;
    const double r2 = u * u + w * w;
    if (r2 >= 1) return std::nullopt;
    const Vec p = {u, w, std::sqrt(1 - r2)};
    return Hit{p, p, {0, 0, 1}, static_cast<std::size_t>(x / s)};
  }

  // Cell by cell: a unit sphere at the origin, the camera at distance 4 on +z with the sphere
  // filling 90% of the cell.
  std::optional<Hit> sphere_hit(int x, int y) const {
    const int s = spec_.size;
    const std::size_t cell = static_cast<std::size_t>(x / s);
    const double u = 2.0 * ((x % s) + 0.5) / s - 1.0, w = 1.0 - 2.0 * (y + 0.5) / s;
    constexpr double kDistance = 4.0;
    const double t = 1.0 / (0.9 * std::sqrt(kDistance * kDistance - 1.0));
    const Vec o = {0, 0, kDistance};
    const Vec dir = normalized({u * t, w * t, -1.0});
    const double b = dot(o, dir), c = dot(o, o) - 1.0, disc = b * b - c;
    if (!(disc > 0)) return std::nullopt;
    const double dist = -b - std::sqrt(disc);
    const Vec p = o + dist * dir;
    return Hit{p, normalized(p), -1.0 * dir, cell};
  }

  // A camera 1 above the floor y = 0 looking down the -z axis, tilted 14 degrees down, 60
  // degrees wide; stripes of materials across x; nothing beyond 40 units.
  std::optional<Hit> plane_hit(int x, int y) const {
    const double u = 2.0 * (x + 0.5) / out_.width - 1.0, w = 1.0 - 2.0 * (y + 0.5) / out_.height;
    const double half_width = std::tan(30.0 * std::numbers::pi / 180.0);
    const double aspect = static_cast<double>(out_.height) / out_.width;
    const double tilt = 14.0 * std::numbers::pi / 180.0;
    const Vec forward = {0, -std::sin(tilt), -std::cos(tilt)};
    const Vec up = {0, std::cos(tilt), -std::sin(tilt)};
    const Vec right = {1, 0, 0};
    const Vec dir = normalized(forward + (u * half_width) * right + (w * half_width * aspect) * up);
    const Vec o = {0, 1, 0};
    if (!(dir[1] < 0)) return std::nullopt;
    const double dist = -o[1] / dir[1];
    if (dist > 40) return std::nullopt;
    const Vec p = o + dist * dir;
    const double stripes = static_cast<double>(spec_.materials.size());
    // Stripes 1.2 units wide, centred on the view.
    const double k = std::floor(p[0] / 1.2 + stripes / 2);
    const auto material = static_cast<std::size_t>(std::clamp(k, 0.0, stripes - 1));
    return Hit{p, {0, 1, 0}, -1.0 * dir, material};
  }

  std::span<const PointLight> lights() const {
    // Sphere: key (upper right front), rim (behind, upper left), fill (lower left front).
    static constexpr PointLight kSphereLights[] = {
        {{2.2, 2.0, 2.6}, 32.0}, {{-2.4, 1.2, -1.2}, 40.0}, {{-2.8, -1.2, 2.4}, 3.0}};
    // Plane: a far light over the horizon and a near one to the right.
    static constexpr PointLight kPlaneLights[] = {{{0.0, 2.5, -22.0}, 300.0},
                                                  {{2.0, 1.2, -5.0}, 14.0}};
    if (spec_.kind == SceneKind::Sphere) return kSphereLights;
    return kPlaneLights;
  }

  SceneSpec spec_;
  SceneSamples out_;
};

void check_spec(const SceneSpec& s) {
  if (!s.term)
    throw Error("no term: which factor of the specular term (F, V, D or FV) the function is",
                {"SceneSpec::term"});
  const int min_size = s.lobe ? 8 : 16, max_size = s.lobe ? 4096 : 1024;
  if (s.size < min_size || s.size > max_size)
    throw Error("the scene's size must be in [" + std::to_string(min_size) + ", " +
                    std::to_string(max_size) + "] pixels, got " + std::to_string(s.size),
                {"SceneSpec::size"});
  if (s.lobe) {
    const Vec d = s.lobe->direction;
    if (s.kind != SceneKind::Sphere)
      throw Error("lobe lighting shows spheres only", {"SceneSpec::lobe"});
    if (!(dot(d, d) > 0) || !std::isfinite(dot(d, d)))
      throw Error("the light direction must be a finite non-zero vector", {"SceneSpec::lobe"});
    if (!(std::isfinite(s.lobe->irradiance) && s.lobe->irradiance > 0))
      throw Error("the irradiance must be finite and > 0", {"SceneSpec::lobe"});
  }
  if (s.materials.empty() || s.materials.size() > 16)
    throw Error("a scene needs 1 to 16 materials", {"SceneSpec::materials"});
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const SceneMaterial& m = s.materials[i];
    const SourceLocation where{"SceneSpec::materials", static_cast<int>(i + 1)};
    if (!(m.roughness > 0 && m.roughness <= 1))
      throw Error("roughness must be in (0, 1], got " + format_number(m.roughness), where);
    if (!(m.f0 > 0 && m.f0 < 1))
      throw Error("F0 must be in (0, 1), got " + format_number(m.f0), where);
  }
  if (!(std::isfinite(s.exposure) && s.exposure > 0))
    throw Error("the exposure must be finite and > 0", {"SceneSpec::exposure"});
}

// ACES filmic, Narkowicz's fit.
double aces(double x) { return x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14); }
double aces_slope(double x) {
  const double n = x * (2.51 * x + 0.03), d = x * (2.43 * x + 0.59) + 0.14;
  return ((5.02 * x + 0.03) * d - n * (4.86 * x + 0.59)) / (d * d);
}
double srgb_encode(double c) {
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
}
double srgb_slope(double c) {
  return c <= 0.0031308 ? 12.92 : 1.055 / 2.4 * std::pow(c, 1 / 2.4 - 1);
}

void check_term(const SceneSamples& s, std::span<const double> term) {
  if (term.size() != s.samples())
    throw Error(std::to_string(term.size()) + " values of the term for " +
                    std::to_string(s.samples()) + " samples",
                {"term"});
  for (std::size_t i = 0; i < term.size(); ++i)
    if (!std::isfinite(term[i]))
      throw Error("the term is not finite at sample " + std::to_string(i + 1), {"term"});
}

}  // namespace

std::span<const std::string_view> scene_quantity_names() { return kQuantities; }

std::span<const double> SceneSamples::column(std::string_view name,
                                             const std::string& where) const {
  for (std::size_t k = 0; k < std::size(kQuantities); ++k)
    if (kQuantities[k] == name) return quantities[k];
  std::string known;
  for (std::string_view q : kQuantities) known += (known.empty() ? "" : ", ") + std::string(q);
  throw Error("the " + std::string(scene_kind_name(spec.kind)) + " scene has no quantity '" +
                  std::string(name) + "' (it has " + known + ")",
              {where});
}

SceneSamples render_scene(const SceneSpec& given) {
  SceneSpec spec = given;
  if (spec.size == 0) spec.size = 96;
  if (spec.materials.empty())
    for (int i = 0; i < 5; ++i) spec.materials.push_back({0.2 + 0.15 * i, 0.02 + 0.015 * i});
  check_spec(spec);
  return Renderer(std::move(spec)).run();
}

double display_encode(double linear, double exposure) {
  const double x = std::max(linear * exposure, 0.0);
  return srgb_encode(std::clamp(aces(x), 0.0, 1.0));
}

double display_slope(double linear, double exposure) {
  const double x = std::max(linear * exposure, 0.0);
  const double t = aces(x);
  if (!(t > 0 && t < 1)) return 0;
  return srgb_slope(t) * aces_slope(x) * exposure;
}

std::vector<double> shade(const SceneSamples& s, std::span<const double> term) {
  check_term(s, term);
  std::vector<double> rgb = s.base;
  for (std::size_t i = 0; i < s.samples(); ++i)
    for (std::size_t c = 0; c < 3; ++c) rgb[3 * s.pixel[i] + c] += s.coefficient[i] * term[i];
  return rgb;
}

RgbImage display_image(const SceneSamples& s, std::span<const double> linear_rgb) {
  RgbImage im{s.width, s.height, std::vector<float>(linear_rgb.size())};
  for (std::size_t i = 0; i < linear_rgb.size(); ++i)
    im.rgb[i] = static_cast<float>(display_encode(linear_rgb[i], s.spec.exposure));
  return im;
}

std::vector<double> display_weights(const SceneSamples& s, std::span<const double> reference_term) {
  const std::vector<double> rgb = shade(s, reference_term);
  std::vector<double> w(s.samples());
  for (std::size_t i = 0; i < s.samples(); ++i) {
    double slope2 = 0;
    for (std::size_t c = 0; c < 3; ++c) {
      const double d = display_slope(rgb[3 * s.pixel[i] + c], s.spec.exposure);
      slope2 += d * d;
    }
    w[i] = s.coefficient[i] * s.coefficient[i] * slope2;
  }
  return w;
}

SceneImages scene_images(const SceneSamples& s, std::span<const double> reference_term,
                         std::span<const double> approximation_term) {
  SceneImages out;
  out.reference = display_image(s, shade(s, reference_term));
  out.approximation = display_image(s, shade(s, approximation_term));
  out.flip = ldr_flip(out.reference, out.approximation);
  double sum = 0;
  for (std::size_t i = 0; i < out.reference.rgb.size(); ++i) {
    const double d = std::abs(double{out.reference.rgb[i]} - double{out.approximation.rgb[i]});
    sum += d * d;
    out.display_max = std::max(out.display_max, d);
  }
  out.display_rmse = out.reference.rgb.empty()
                         ? 0
                         : std::sqrt(sum / static_cast<double>(out.reference.rgb.size()));
  out.visible_share = out.flip.share_above(kFlipVisible);
  return out;
}

std::vector<std::uint8_t> image_bytes(const RgbImage& image) {
  std::vector<std::uint8_t> out(image.rgb.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] =
        static_cast<std::uint8_t>(std::lround(std::clamp(double{image.rgb[i]}, 0.0, 1.0) * 255));
  return out;
}

std::optional<SceneReference> scene_reference(std::string_view builtin_name) {
  const reference::BuiltinFunction* f = nullptr;
  for (const reference::BuiltinFunction& b : reference::builtin_functions()) {
    std::string underscored(b.name);
    std::replace(underscored.begin(), underscored.end(), '-', '_');
    if (b.name == builtin_name || underscored == builtin_name) f = &b;
  }
  if (f == nullptr) return std::nullopt;
  const std::string_view name = f->name;
  ShadingTerm term;
  if (name.rfind("fresnel-", 0) == 0)
    term = ShadingTerm::F;
  else if (name.rfind("fv-", 0) == 0)
    term = ShadingTerm::FV;
  else if (name == "ggx-d")
    term = ShadingTerm::D;
  else
    return std::nullopt;
  std::string call(name);
  std::replace(call.begin(), call.end(), '-', '_');
  call += '(';
  for (std::size_t i = 0; i < f->arguments.size(); ++i) {
    const std::string_view a = f->arguments[i];
    std::string_view q;
    if (a == "cos" || a == "cos_theta")
      q = term == ShadingTerm::D ? "n_dot_h" : "v_dot_h";
    else if (a == "r0" || a == "F0" || a == "f0")
      q = "f0";
    else if (a == "dot_lh")
      q = "l_dot_h";
    else if (a == "ior" || a == "roughness" || a == "alpha")
      q = a;
    else
      return std::nullopt;  // ior_k, ...: no scene quantity
    call += (i ? ", " : "") + std::string(q);
  }
  return SceneReference{term, call + ")"};
}

}  // namespace shaderfit
