// A fit's view of the built-in reference functions (reference/builtin.hpp): those offered to
// `shaderfit fit --reference` by name, each reading its arguments from the data columns of the
// same names (the reference language calls them, reference/language.hpp).
//
//   const reference::BuiltinFunction* r = find_builtin_reference("fresnel-exact");
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/reference/builtin.hpp"

namespace shaderfit {

// fresnel-schlick, fresnel-seed, fresnel-dielectric, fresnel-conductor, fresnel-exact (dielectric
// where ior_k = 0, else conductor), fv-schlick-smith-lh (Schlick x Hable's dot(L,H) visibility),
// fv-schlick-smith (Schlick x Schlick-Smith at n = h), fv-exact (exact dielectric Fresnel x exact
// Smith GGX at n = h), fv-exact-conductor. See reference/fv_reference.hpp for the FV conventions.
std::vector<const reference::BuiltinFunction*> builtin_references();

// The reference with this name, or nullptr.
const reference::BuiltinFunction* find_builtin_reference(std::string_view name);

// "name(arguments): description" lines, for help texts.
std::string describe_builtin_references();

}  // namespace shaderfit
