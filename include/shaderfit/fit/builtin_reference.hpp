// Reference functions by name, for fitting a formula to a known function instead of a data
// column. Each reads its arguments from variables (data columns or sampled variables) with fixed
// names.
//
//   const BuiltinReference* r = find_builtin_reference("fresnel-exact");
//   std::vector<double> target = evaluate_reference(*r, data);  // columns cos_theta, ior_n, ior_k
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/data/dataset.hpp"

namespace shaderfit {

struct BuiltinReference {
  std::string_view name;
  std::string_view description;
  std::vector<std::string> arguments;  // variable names, in call order
  double (*function)(const double* arguments);
};

// fresnel-schlick, fresnel-seed, fresnel-dielectric, fresnel-conductor, fresnel-exact (dielectric
// where ior_k = 0, else conductor), fv-schlick-smith-lh (seed 002's reference), fv-schlick-smith
// (Schlick x Schlick-Smith at n = h), fv-exact (exact dielectric Fresnel x exact Smith GGX at
// n = h), fv-exact-conductor. See lut/fv_reference.hpp for the FV conventions.
std::span<const BuiltinReference> builtin_references();

// The reference with this name, or nullptr.
const BuiltinReference* find_builtin_reference(std::string_view name);

// "name(arguments): description" lines, for help texts.
std::string describe_builtin_references();

// The reference on every row of `data`, its arguments read from the numeric columns of the same
// names (Dataset::numeric's errors for a missing or text column).
std::vector<double> evaluate_reference(const BuiltinReference& reference, const Dataset& data);

}  // namespace shaderfit
