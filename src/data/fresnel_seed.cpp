#include "shaderfit/data/fresnel_seed.hpp"

#include <cmath>
#include <numbers>

#include "data/number.hpp"
#include "shaderfit/reference/fresnel.hpp"

namespace shaderfit {

namespace {

struct Metal {
  double n, k;
};

// The metals of seed post 001.
constexpr Metal kMetals[] = {{0.3, 3.0},   {0.15, 4.0}, {0.3, 3.35}, {1.4, 7.0},
                             {1.84, 3.73}, {2.1, 4.0},  {2.9, 3.1}};
constexpr std::size_t kMetalCount = sizeof kMetals / sizeof kMetals[0];

constexpr double kGlassProbability = 0.4;
constexpr double kDielectricProbability = 0.8;  // glass or a random dielectric

std::string metal_name(const Metal& m) {
  return "metal " + data_internal::format_number(m.n) + "+" + data_internal::format_number(m.k) +
         "i";
}

}  // namespace

Dataset make_fresnel_seed_dataset(Rng& rng, const FresnelSeedOptions& options) {
  const std::size_t n_rows = options.rows;
  const double theta_max = options.half_range ? 0.5 * std::numbers::pi : std::numbers::pi;
  std::vector<double> r0(n_rows), cos_theta(n_rows), x(n_rows), reflectance(n_rows), ior_n(n_rows),
      ior_k(n_rows);
  std::vector<std::string> kind(n_rows), material(n_rows);

  for (std::size_t i = 0; i < n_rows; ++i) {
    double theta = uniform(rng, 0.0, theta_max);
    double c = std::abs(std::cos(theta));
    double u = uniform01(rng);
    double n = 1.5, k = 0.0;
    if (u < kGlassProbability) {
      material[i] = "ior1.5";
    } else if (u < kDielectricProbability) {
      n = uniform(rng, 1.34, 1.7);
      material[i] = "ior1.34-1.7";
    } else {
      const Metal& m = kMetals[uniform_index(rng, kMetalCount)];
      n = m.n;
      k = m.k;
      material[i] = metal_name(m);
    }
    bool metal = k > 0.0;
    kind[i] = metal ? "metal" : "dielectric";
    r0[i] = metal ? reference::r0_from_complex_ior(n, k) : reference::r0_from_ior(n);
    reflectance[i] =
        metal ? reference::fresnel_conductor(c, n, k) : reference::fresnel_dielectric(c, n);
    cos_theta[i] = c;
    x[i] = 1.0 - c;
    ior_n[i] = n;
    ior_k[i] = k;
  }

  Dataset d;
  d.source = options.half_range ? "fresnel-seed-half" : "fresnel-seed";
  d.add_numeric("r0", std::move(r0));
  d.add_numeric("cos_theta", std::move(cos_theta));
  d.add_numeric("x", std::move(x));
  d.add_numeric("R", std::move(reflectance));
  d.add_numeric("ior_n", std::move(ior_n));
  d.add_numeric("ior_k", std::move(ior_k));
  d.add_text("kind", std::move(kind));
  d.add_text("material", std::move(material));
  return d;
}

std::vector<std::string> builtin_dataset_names() { return {"fresnel-seed", "fresnel-seed-half"}; }

std::optional<Dataset> make_builtin_dataset(std::string_view name, Rng& rng, std::size_t rows) {
  if (name == "fresnel-seed") return make_fresnel_seed_dataset(rng, {rows, false});
  if (name == "fresnel-seed-half") return make_fresnel_seed_dataset(rng, {rows, true});
  return std::nullopt;
}

Dataset builtin_dataset(std::string_view name, Rng& rng, std::size_t rows,
                        const SourceLocation& where) {
  if (auto d = make_builtin_dataset(name, rng, rows)) return std::move(*d);
  std::string list;
  for (const std::string& n : builtin_dataset_names()) list += (list.empty() ? "" : ", ") + n;
  throw Error("unknown data set '" + std::string(name) + "' (built-in: " + list + ")", where);
}

}  // namespace shaderfit
