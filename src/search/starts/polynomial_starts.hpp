// Polynomial starts (internal; docs/search.md, "Polynomial starts"): for a problem of one input,
// after the enumeration unless the search is over, the polynomial of each degree fitted for the
// loss (minimax for max_abs and max_rel, by Lawson's reweighting; least squares in the loss's
// terms otherwise), in Horner form, is offered to the front and seeds the evolution as a start
// formula does (origin SearchPhase::Polynomial). The evolution rarely assembles a Horner chain of
// six or more terms, the form most published one-input approximations take. Where the data is
// odd, even or point-symmetric in x (DataSymmetry), the polynomials of that symmetry too:
// x P(x^2), P(x^2) and c + x P(x^2), symmetric on the whole data as written (no copysign or abs).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "shaderfit/search/options.hpp"
#include "shaderfit/search/search.hpp"
#include "shaderfit/search/symmetry.hpp"

namespace shaderfit::search_detail {

// Degrees 2 .. kPolynomialMaxDegree in x; 2 .. kSymmetricMaxTerms terms in x^2.
inline constexpr int kPolynomialMaxDegree = 10;
inline constexpr int kSymmetricMaxTerms = 8;
// The fits read at most this many rows, evenly spread over the sorted input (both ends kept).
inline constexpr std::size_t kPolynomialRows = 2048;
inline constexpr int kPolynomialMinimaxIterations = 60;
// A fit is kept when its error in the loss's terms (max w |r|, or sum w r^2) on those rows is at
// most this share of the best constant's.
inline constexpr double kPolynomialMinGain = 0.5;

// The polynomials over the problem's input fitted for `loss`, written with the variable x0 and
// constants in full precision, from the lowest degree up; empty unless the problem has exactly
// one input. A fit whose constants are not all finite, or that does not gain kPolynomialMinGain
// on a constant, is left out. `symmetry` (of input 0) adds its forms.
std::vector<std::string> polynomial_starts(const SearchProblem& problem,
                                           const std::optional<DataSymmetry>& symmetry, Loss loss);

}  // namespace shaderfit::search_detail
