#include "shaderfit/data/fresnel_seed.hpp"

#include <cmath>
#include <numbers>

#include "data/fresnel_rows.hpp"
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
  return "metal " + data_detail::format_number(m.n) + "+" + data_detail::format_number(m.k) + "i";
}

}  // namespace

Dataset make_fresnel_seed_dataset(Rng& rng, const FresnelSeedOptions& options) {
  const double theta_max = options.half_range ? 0.5 * std::numbers::pi : std::numbers::pi;
  data_detail::FresnelRows rows;
  for (std::size_t i = 0; i < options.rows; ++i) {
    double theta = uniform(rng, 0.0, theta_max);
    double c = std::abs(std::cos(theta));
    double u = uniform01(rng);
    if (u < kGlassProbability) {
      rows.add(c, 1.5, 0.0, "ior1.5");
    } else if (u < kDielectricProbability) {
      rows.add(c, uniform(rng, 1.34, 1.7), 0.0, "ior1.34-1.7");
    } else {
      const Metal& m = kMetals[uniform_index(rng, kMetalCount)];
      rows.add(c, m.n, m.k, metal_name(m));
    }
  }

  Dataset d;
  d.source = options.half_range ? "fresnel-seed-half" : "fresnel-seed";
  rows.move_into(d);
  return d;
}

std::vector<std::string> builtin_dataset_names() { return {"fresnel-seed", "fresnel-seed-half"}; }

std::optional<BuiltinDatasetInfo> builtin_dataset_info(std::string_view name) {
  if (name != "fresnel-seed" && name != "fresnel-seed-half") return std::nullopt;
  return BuiltinDatasetInfo{std::string(name), {"r0", "x"}, "R", "+,-,*,/,^", "pow,exp2"};
}

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
