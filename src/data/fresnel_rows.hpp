// Internal: the columns every Fresnel data set shares (r0, cos_theta, x, R, ior_n, ior_k, kind,
// material), filled one sample at a time, so the seed generator and the angle sweep compute
// r0 and the exact reflectance the same way.
#pragma once

#include <string>
#include <vector>

#include "shaderfit/data/dataset.hpp"
#include "shaderfit/reference/fresnel.hpp"

namespace shaderfit::data_detail {

struct FresnelRows {
  std::vector<double> r0, cos_theta, x, reflectance, ior_n, ior_k;
  std::vector<std::string> kind, material;

  // One sample at |cos theta| = c of a material with IOR n + ik (k = 0: a dielectric).
  void add(double c, double n, double k, std::string label) {
    const bool metal = k > 0.0;
    r0.push_back(metal ? reference::r0_from_complex_ior(n, k) : reference::r0_from_ior(n));
    reflectance.push_back(metal ? reference::fresnel_conductor(c, n, k) : reference::fresnel_dielectric(c, n));
    cos_theta.push_back(c);
    x.push_back(1.0 - c);
    ior_n.push_back(n);
    ior_k.push_back(k);
    kind.push_back(metal ? "metal" : "dielectric");
    material.push_back(std::move(label));
  }

  // Appends the columns to d in the documented order: r0, cos_theta, x, R, ior_n, ior_k, kind,
  // material.
  void move_into(Dataset& d) {
    d.add_numeric("r0", std::move(r0));
    d.add_numeric("cos_theta", std::move(cos_theta));
    d.add_numeric("x", std::move(x));
    d.add_numeric("R", std::move(reflectance));
    d.add_numeric("ior_n", std::move(ior_n));
    d.add_numeric("ior_k", std::move(ior_k));
    d.add_text("kind", std::move(kind));
    d.add_text("material", std::move(material));
  }
};

}  // namespace shaderfit::data_detail
