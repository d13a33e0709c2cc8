// Scenes: a picture rendered with a specular BRDF, and for every pixel the quantities its
// shading feeds one factor of that BRDF (the term a formula approximates): N·L, N·V, N·H, V·H,
// roughness, F0, ... by name. A search on a scene fits its inputs as they occur on screen, each
// sample weighing as the pixel it lights; the display loss judges the shaded pixel after
// exposure, tonemap and sRGB encoding; LDR-FLIP (image/flip.hpp) judges the picture
// (docs/scenes.md).
//
//   SceneSpec spec;                              // five spheres, the Fresnel factor
//   SceneSamples s = render_scene(spec);
//   std::vector<double> f = ...;                 // the term at each sample (s.column("v_dot_h"))
//   SceneImages im = scene_images(s, f_reference, f_approx);   // sRGB pictures and FLIP
//
// Shading, per light: radiance = E (n·l) (albedo / pi + D F V / 4) with GGX's D, Smith's
// height-correlated V = G2 / ((n·l)(n·v)) and the exact dielectric F of the material's F0
// (reference/'s convention, docs/lut.md); the term's samples replace that factor. Point lights fall
// off with the squared distance; a small ambient light keeps the unlit side visible.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/image/flip.hpp"

namespace shaderfit {

// sphere: one sphere per material in a row, seen by a perspective camera, lit by a key, a rim
// (from behind: grazing half vectors, where Fresnel rises) and a fill point light. plane: a
// floor seen at a grazing angle with two point lights above it, one stripe per material: the
// highlights near the horizon.
enum class SceneKind : std::uint8_t { Sphere, Plane };
std::optional<SceneKind> scene_kind_from_name(std::string_view name);  // "sphere", "plane"
std::string_view scene_kind_name(SceneKind kind);
std::string_view scene_kind_names();  // "sphere, plane"

// The factor of the specular BRDF D F V / 4 a formula stands for: F (Fresnel), V (visibility),
// D (distribution) or FV (F V, the combined Fresnel-visibility term).
enum class ShadingTerm : std::uint8_t { F, V, D, FV };
std::optional<ShadingTerm> shading_term_from_name(std::string_view name);  // "F", "V", "D", "FV"
std::string_view shading_term_name(ShadingTerm term);

struct SceneMaterial {
  double roughness = 0.5;  // perceptual; alpha = roughness^2
  double f0 = 0.04;        // normal-incidence reflectance (dielectric)
};

// The specular lobe alone, as a BRDF's textbook pictures show it (`plot sphere`): each sphere
// fills its cell, seen along -z by an orthographic camera and lit by one distant light from
// `direction` (towards the light; normalised inside) with the given irradiance; no diffuse,
// ambient or backdrop: SceneSamples::base is 0 on the spheres and NaN beside them, so a pixel's
// radiance is its sample's coefficient times the term.
struct LobeLighting {
  std::array<double, 3> direction = {0.8, 0.45, 0.4};
  double irradiance = 1.0;
};

struct SceneSpec {
  SceneKind kind = SceneKind::Sphere;
  // Set (the sphere kind only): the specular lobe alone, in place of the camera and the lights
  // described at SceneKind.
  std::optional<LobeLighting> lobe;
  // Required by render_scene (Error at "SceneSpec::term" when unset); a problem's scene takes it
  // from a built-in reference where not given (problem/problem.hpp).
  std::optional<ShadingTerm> term;
  // Pixels of one sphere's cell (the plane: the image's height, twice as wide); 0: 96.
  int size = 0;
  // Empty: five materials, roughness 0.2 .. 0.8 and F0 0.02 .. 0.08 together.
  std::vector<SceneMaterial> materials;
  // Linear radiance is multiplied by this before the tonemap.
  double exposure = 1.0;
};

// A scene by names: `kind` ("sphere", "plane") and `term` ("F", "V", "D", "FV"; "" : unset), the
// rest defaults. Throws shaderfit::Error located at "SceneSpec::kind" or "SceneSpec::term" for an
// unknown name, naming the known ones.
SceneSpec scene_spec_from_names(std::string_view kind, std::string_view term = "");

// The scene's quantities by name, in the column order of SceneSamples::quantities: n_dot_l,
// n_dot_v, n_dot_h, v_dot_h, l_dot_h (= v_dot_h), roughness, alpha (= roughness^2), f0, ior
// (the dielectric index with that F0).
std::span<const std::string_view> scene_quantity_names();

// One shading sample per pixel and light that lights it (n·l > 0, n·v > 0).
struct SceneSamples {
  SceneSpec spec;  // as rendered (defaults filled in)
  int width = 0, height = 0;
  std::vector<std::vector<double>> quantities;  // [scene_quantity_names() order][sample]
  std::vector<std::uint32_t> pixel;             // the sample's pixel, row-major, row 0 at the top
  // The sample adds coefficient * term to its pixel's radiance, in every channel (dielectric
  // highlights are white).
  std::vector<double> coefficient;
  // Per pixel, linear RGB (3 per pixel): what does not depend on the term (diffuse, ambient,
  // background).
  std::vector<double> base;

  [[nodiscard]] std::size_t samples() const { return pixel.size(); }
  // The column of a quantity; throws Error located at `where` naming the known ones.
  [[nodiscard]] std::span<const double> column(std::string_view name,
                                               const std::string& where = "scene") const;
};

// Throws shaderfit::Error located at "SceneSpec::size", "SceneSpec::materials" (line = the
// material's 1-based position), "SceneSpec::exposure" or "SceneSpec::lobe" for a size outside
// [16, 1024] (with lobe lighting [8, 4096]), a roughness outside (0, 1], an F0 outside (0, 1), an
// exposure that is not finite and > 0, or lobe lighting of the plane, from a direction that is not
// a finite non-zero vector or with an irradiance that is not finite and > 0.
SceneSamples render_scene(const SceneSpec& spec);

// The display transform, per channel: exposure, then the ACES filmic curve (Narkowicz's fit),
// clamped to [0, 1], then sRGB encoding. display_slope is its derivative in the linear value.
double display_encode(double linear, double exposure);
double display_slope(double linear, double exposure);

// Linear RGB per pixel (3 per pixel) with `term` (one value per sample) in place of the factor.
std::vector<double> shade(const SceneSamples& s, std::span<const double> term);
// That picture as the display shows it.
RgbImage display_image(const SceneSamples& s, std::span<const double> linear_rgb);

// The display loss's weights, one per sample: the squared first-order change of the displayed
// pixel per unit change of the term there, summed over the channels, at the picture with the
// reference term: coefficient^2 * sum_c display_slope(v_c)^2. A weighted squared error of the
// term with these weights is then the displayed pixels' squared error to first order (samples
// of one pixel add independently).
std::vector<double> display_weights(const SceneSamples& s, std::span<const double> reference_term);

// What the eye compares: both pictures, their FLIP map, and the displayed pixels' errors.
struct SceneImages {
  RgbImage reference, approximation;
  FlipResult flip;
  double display_rmse = 0;   // over every pixel and channel, in display units [0, 1]
  double display_max = 0;    // the largest displayed difference of one channel
  double visible_share = 0;  // share of pixels whose FLIP exceeds kFlipVisible
};

// FLIP above this is called visible: an error of a tenth of FLIP's range, which in flips between
// the images shows as a clearly noticed change (docs/scenes.md).
inline constexpr double kFlipVisible = 0.1;

// Throws Error located at "term" when a term has not one value per sample, or is not finite.
SceneImages scene_images(const SceneSamples& s, std::span<const double> reference_term,
                         std::span<const double> approximation_term);

// sRGB bytes (RGBRGB..., row 0 at the top) of a displayed picture, for PNG files.
std::vector<std::uint8_t> image_bytes(const RgbImage& image);

// The built-in references (reference/builtin.hpp) a scene can feed: the factor each stands for
// and the scene quantity for each argument, as a reference formula ("fresnel_dielectric_f0(v_dot_h,
// f0)"); nullopt for a name that is no built-in or takes an argument no scene provides.
struct SceneReference {
  ShadingTerm term;
  std::string formula;
};
std::optional<SceneReference> scene_reference(std::string_view builtin_name);

}  // namespace shaderfit
