// A fit's view of the built-in reference functions (reference/builtin.hpp): those offered to
// `shaderfit fit --reference`, each reading its arguments from the data columns of the same names.
//
//   const reference::BuiltinFunction* r = find_builtin_reference("fresnel-exact");
//   std::vector<double> target = evaluate_reference(*r, data);  // columns cos_theta, ior_n, ior_k
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/data/dataset.hpp"
#include "shaderfit/reference/builtin.hpp"

namespace shaderfit {

// fresnel-schlick, fresnel-seed, fresnel-dielectric, fresnel-conductor, fresnel-exact (dielectric
// where ior_k = 0, else conductor), fv-schlick-smith-lh (seed 002's reference), fv-schlick-smith
// (Schlick x Schlick-Smith at n = h), fv-exact (exact dielectric Fresnel x exact Smith GGX at
// n = h), fv-exact-conductor. See reference/fv_reference.hpp for the FV conventions.
std::vector<const reference::BuiltinFunction*> builtin_references();

// The reference with this name, or nullptr.
const reference::BuiltinFunction* find_builtin_reference(std::string_view name);

// "name(arguments): description" lines, for help texts.
std::string describe_builtin_references();

// The reference on every row of `data`, its arguments read from the numeric columns of the same
// names (Dataset::numeric's errors for a missing or text column).
std::vector<double> evaluate_reference(const reference::BuiltinFunction& function,
                                       const Dataset& data);

}  // namespace shaderfit
