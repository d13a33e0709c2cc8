// Fresnel reflectance of chosen materials swept over the angle of incidence: the data behind
// reflectance-versus-angle curves.
//
//   std::vector<Material> m = {parse_material("aluminium"), parse_material("1.5")};
//   Dataset d = make_fresnel_sweep(m, 181);   // 0, 0.5, ..., 90 degrees for each material
//
// Columns: theta_deg, then those of fresnel-seed: r0, cos_theta, x (= 1 - cos_theta), R (exact
// unpolarized Fresnel), ior_n, ior_k, kind ("dielectric" / "metal"), material (its name).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/data/dataset.hpp"

namespace shaderfit {

struct Material {
  std::string name;  // "aluminium", "ior1.5", "metal 0.3+3i"
  double n = 1.5;
  double k = 0;      // 0 for a dielectric
  std::string note;  // where the optical constants come from, for captions
};

// Named metals at 632.8 nm (Sopra material library, as listed by the Filmetrics refractive-index
// database): aluminium 1.37289 + 7.617691i, gold 0.18104 + 3.068099i.
std::vector<Material> named_materials();

// "aluminium" or "gold"; a real IOR "1.5"; a complex IOR "0.3+3i" (n + k i, k >= 0). Names
// follow fresnel-seed's labels ("ior1.5", "metal 0.3+3i"). Throws shaderfit::Error located
// at `where` for anything else (a non-positive n, a negative k, unknown names).
Material parse_material(std::string_view text, const SourceLocation& where = {"Material"});

// The fixed materials of the fresnel-seed data set: IOR 1.5 and its seven metals.
std::vector<Material> seed_materials();

// `angles` >= 2 evenly spaced angles from 0 to 90 degrees for each material, in order.
Dataset make_fresnel_sweep(const std::vector<Material>& materials, int angles = 181);

}  // namespace shaderfit
