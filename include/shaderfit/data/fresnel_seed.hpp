// The fresnel-seed data set (exact Fresnel reflectance of dielectrics and metals over the angle),
// and the registry of built-in data sets.
//
//   Rng rng(1);
//   Dataset d = make_fresnel_seed_dataset(rng);          // 4096 rows, theta in [0, pi]
//   auto half = make_builtin_dataset("fresnel-seed-half", rng);
//
// Each row draws, in this order (the order is part of the reproducibility contract):
//   1. theta = uniform(0, pi), or uniform(0, pi/2) with half_range;
//   2. u = uniform01: u < 0.4 glass (IOR 1.5); u < 0.8 a dielectric with IOR uniform(1.34, 1.7)
//      (a third draw); otherwise one of the seven metals below, uniform_index(7) (a third draw).
// Metals (complex IOR n + ik): 0.3+3i, 0.15+4i, 0.3+3.35i, 1.4+7i, 1.84+3.73i, 2.1+4i, 2.9+3.1i.
//
// Columns, in order:
//   r0         normal-incidence reflectance: r0_from_ior(n) or r0_from_complex_ior(n, k)
//   cos_theta  |cos theta|: directions with theta > pi/2 (behind the surface) are mirrored to the
//              front: with a signed cosine, x would exceed 1 on half the rows, where Schlick-type
//              approximations mean nothing. So both ranges give the same distribution of
//              cos_theta (that of cos theta, theta uniform in [0, pi/2]); they differ only in the
//              random draws.
//   x          1 - cos_theta
//   R          exact unpolarized Fresnel reflectance: fresnel_dielectric(cos_theta, n) or
//              fresnel_conductor(cos_theta, n, k) (from air, eta = IOR)
//   ior_n      real part of the IOR
//   ior_k      imaginary part (0 for dielectrics)
//   kind       text: "dielectric" or "metal"
//   material   text: "ior1.5", "ior1.34-1.7" (every random dielectric), or "metal <n>+<k>i" with
//              the numbers as in the list above, e.g. "metal 0.3+3i", "metal 1.84+3.73i"
// Only uniform01, uniform and uniform_index are used, so a seed gives the same rows with every
// standard library.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/data/dataset.hpp"

namespace shaderfit {

struct FresnelSeedOptions {
  std::size_t rows = 4096;
  bool half_range = false;  // theta in [0, pi/2] instead of [0, pi]
};

// The data set described above; its source is "fresnel-seed" or "fresnel-seed-half".
Dataset make_fresnel_seed_dataset(Rng& rng, const FresnelSeedOptions& options = {});

// What a built-in data set is for: the columns formulas read and the one they approximate, and
// the search's operators for it, as text that parse_operator_list (search/options.hpp) reads
// (this area does not include search/). fresnel-seed and fresnel-seed-half: inputs r0, x;
// target R; operators "+,-,*,/,^" and evolution operators "pow,exp2".
struct BuiltinDatasetInfo {
  std::string name;
  std::vector<std::string> inputs;
  std::string target;
  std::string operators;
  std::string evolution_operators;
};

// The descriptor of the built-in data set with this name, or nullopt for an unknown name.
std::optional<BuiltinDatasetInfo> builtin_dataset_info(std::string_view name);

// Names of the built-in data sets: "fresnel-seed" (theta in [0, pi]) and "fresnel-seed-half"
// (theta in [0, pi/2]).
std::vector<std::string> builtin_dataset_names();

// The built-in data set with this name and number of rows, or nullopt for an unknown name.
std::optional<Dataset> make_builtin_dataset(std::string_view name, Rng& rng,
                                            std::size_t rows = FresnelSeedOptions{}.rows);

// As above, but an unknown name throws Error "unknown data set 'x' (built-in: fresnel-seed,
// fresnel-seed-half)" located at `where` (for example {"dataset"}).
Dataset builtin_dataset(std::string_view name, Rng& rng,
                        std::size_t rows = FresnelSeedOptions{}.rows,
                        const SourceLocation& where = {});

}  // namespace shaderfit
