// Exact power sums (internal; docs/search.md, "Exact power sums"): after the enumeration, unless
// the search is over, it tries whether the target is, to float64 rounding,
//
//   y = M * t^(1/p),  t = c0 + sum a_k m_k,  p in {1, -1, 2, -2, 1/2, -1/2},
//
// or y = s exp2(c0 + sum e_k log2 |x_k| + sum a_k m_k) (s = +-1; a Gaussian over its width),
// with at most kPowerSumTerms terms (one more for the logarithm), where M is a power product of
// the inputs (exponents fitted to log |y| and rounded to halves or to integers, the two farthest
// from integers also to the integers either side; or M = 1) and each m a power product of at most
// two inputs (three in the logarithm, where they are few) with exponents in {-2, -1, 1, 2}.
// rho / sqrt(1 - v^2 / c^2) (p = -2, M = rho, m1 = v^2 / c^2), mom sqrt(Bx^2 + By^2 + Bz^2),
// sqrt(w^2 / c^2 - pi^2 / d^2) and w^4 / (w^2 - w0^2)^2 are such sums, and so is a power product
// alone (t constant); the evolution rarely assembles them (needles of cost 5 or more among
// formulas of 3 or more inputs). The terms are chosen by a beam search over the normal equations
// (at most kPowerSumRows rows, evenly spread) and the best subsets are refitted by QR on the
// rows; one counts only when its 1 - R^2 in t is at most kPowerSumExact, so nothing is added
// where the data is not such a sum (or is noisy). Where the beam finds nothing, other forms whose
// terms it cannot choose one by one are fitted whole: the logarithm with D q(x), q a quadratic in
// the inputs and D one input's power (a Gaussian with a mean), the logarithm with one power
// product of any number of inputs (a Boltzmann factor exp(-m g x / (kb T))), and, for at most 4
// inputs, y = N / (1 + E) with N and E such D q(x) (a velocity sum); and y = M t^(1/p) with M
// made of the inputs whose log-fit exponents are integers and t of products of up to four of the
// others (mom / (kb T) (H + alpha M / (epsilon c^2))); and, for at most 5 inputs, y = C M0 / h(E),
// E = exp2(a m), h one of E - 1, E + 1, E + 1 / E, (E + 1) / (E - 1) (Planck's and Fermi's
// denominators, 1 / cosh, tanh). Whatever is found must hold on every row to 1e-9 of |y| + rms(y)
// as well. The formula found is offered
// to the front and seeds the evolution, as a start formula does (origin SearchPhase::PowerSum).
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

inline constexpr std::size_t kPowerSumRows = 256;
inline constexpr std::size_t kPowerSumTerms = 3;
inline constexpr double kPowerSumExact = 1e-12;
// Beyond this many inputs the monomials are too many to try (761 at 10). A function of one input
// is left to the enumeration, which reaches cost 4 and more for it within its share.
inline constexpr std::size_t kPowerSumInputs = 10;
inline constexpr std::size_t kPowerSumMinInputs = 2;

// The formula over the problem's inputs, written with the variables x0, x1, ... (input k is xk)
// and its constants in full precision; nullopt when the target is no such sum, or when an input
// or the target is 0 or not finite on a row read, or the problem has fewer than
// kPowerSumMinInputs or more than kPowerSumInputs inputs.
std::optional<std::string> exact_power_sum(const SearchProblem& problem);

}  // namespace shaderfit::search_detail
