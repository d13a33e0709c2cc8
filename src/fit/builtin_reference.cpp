#include "shaderfit/fit/builtin_reference.hpp"

#include "shaderfit/lut/fv_reference.hpp"
#include "shaderfit/reference/fresnel.hpp"

namespace shaderfit {

namespace {

namespace ref = shaderfit::reference;

double fresnel_exact(const double* a) {
  return a[2] == 0 ? ref::fresnel_dielectric(a[0], a[1]) : ref::fresnel_conductor(a[0], a[1], a[2]);
}

const std::vector<BuiltinReference>& table() {
  static const std::vector<BuiltinReference> t = {
      {"fresnel-schlick",
       "Schlick: r0 + (1 - r0)(1 - cos)^5",
       {"r0", "cos_theta"},
       [](const double* a) { return ref::fresnel_schlick(a[0], a[1]); }},
      {"fresnel-seed",
       "seed 001: r0 + (x - r0) x^4, x = 1 - cos",
       {"r0", "cos_theta"},
       [](const double* a) { return ref::fresnel_seed(a[0], a[1]); }},
      {"fresnel-dielectric",
       "exact unpolarized dielectric Fresnel",
       {"cos_theta", "ior"},
       [](const double* a) { return ref::fresnel_dielectric(a[0], a[1]); }},
      {"fresnel-conductor",
       "exact unpolarized conductor Fresnel, IOR n + ik",
       {"cos_theta", "ior_n", "ior_k"},
       [](const double* a) { return ref::fresnel_conductor(a[0], a[1], a[2]); }},
      {"fresnel-exact",
       "exact Fresnel: dielectric where ior_k = 0, else conductor",
       {"cos_theta", "ior_n", "ior_k"},
       fresnel_exact},
      {"fv-schlick-smith-lh",
       "seed 002: Schlick F x Schlick-Smith V in dot(L,H) (Hable)",
       {"dot_lh", "f0", "roughness"},
       [](const double* a) { return lut::fv_schlick_smith_lh(a[0], a[1], a[2]); }},
      {"fv-schlick-smith",
       "Schlick F x Schlick-Smith V at n = h",
       {"dot_lh", "f0", "roughness"},
       [](const double* a) { return lut::fv_schlick_smith_peak(a[0], a[1], a[2]); }},
      {"fv-exact",
       "exact dielectric F (IOR from f0) x exact Smith GGX V at n = h",
       {"dot_lh", "f0", "roughness"},
       [](const double* a) { return lut::fv_exact_dielectric(a[0], a[1], a[2]); }},
      {"fv-exact-conductor",
       "exact conductor F (n + ik) x exact Smith GGX V at n = h",
       {"dot_lh", "ior_n", "ior_k", "roughness"},
       [](const double* a) { return lut::fv_exact_conductor(a[0], a[1], a[2], a[3]); }},
  };
  return t;
}

}  // namespace

std::span<const BuiltinReference> builtin_references() { return table(); }

const BuiltinReference* find_builtin_reference(std::string_view name) {
  for (const BuiltinReference& r : table())
    if (r.name == name) return &r;
  return nullptr;
}

std::string describe_builtin_references() {
  std::string s;
  for (const BuiltinReference& r : table()) {
    std::string args;
    for (const std::string& a : r.arguments) args += (args.empty() ? "" : ", ") + a;
    s += std::string(r.name) + "(" + args + "): " + std::string(r.description) + "\n";
  }
  return s;
}

std::vector<double> evaluate_reference(const BuiltinReference& reference, const Dataset& data) {
  std::vector<const std::vector<double>*> columns;
  for (const std::string& a : reference.arguments) columns.push_back(&data.numeric(a).values);
  std::vector<double> out(data.rows()), args(columns.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    for (std::size_t k = 0; k < columns.size(); ++k) args[k] = (*columns[k])[i];
    out[i] = reference.function(args.data());
  }
  return out;
}

}  // namespace shaderfit
