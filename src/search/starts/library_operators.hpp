// Which of the library-function operators (asin, acos, atan, atan2, tanh, erf) `auto` adds to a
// problem (internal; docs/search.md, "Operators"). They cost 17 to 33 GPU instructions but tanh,
// so they join only where the problem points at them, and never for a problem of one input (a
// function of one input is what a user approximates such a function by):
//  - a reference (SearchProblem::reference) whose program calls the function (erfc counts as
//    erf);
//  - data whose target is f of a simple function of the inputs: the target lies in f's range
//    (within [-pi/2, pi/2] for asin, [0, pi] for acos, (-pi/2, pi/2) for atan, (-1, 1) for tanh
//    and erf; within [-pi, pi] and beyond (-pi/2, pi/2) somewhere for atan2), and z = f^-1(y)
//    (sin, cos, tan, atanh, erf^-1; tan for atan2, whose y / x it is) is explained by a simple
//    model of the inputs and their sines and cosines -- a linear function, or a monomial (log |z|
//    linear in the log |x_i|, log |sin x_i|, log |cos x_i|) -- to 1 - R^2 <= kExplained, while the
//    target itself is not (its 1 - R^2 under the same models is at least kBetter times z's).
//    arcsin(lambda / (n d)), arcsin(n sin(theta)), tanh(m B / (k T)) and atan(x - y) show it;
//    smooth functions that merely lie in the range do not.
// The probe reads at most kRows rows (evenly spread) and fits a few least-squares models of
// (3 inputs + 1) columns: about a millisecond for a handful of inputs.
#pragma once

#include <cstddef>
#include <vector>

#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

inline constexpr std::size_t kLibraryProbeRows = 2000;
inline constexpr double kExplained = 1e-6;
inline constexpr double kBetter = 1e4;

// The operators of the list above that the problem points at, in that order.
std::vector<Op> suggested_library_operators(const SearchProblem& problem);

}  // namespace shaderfit::search_detail
