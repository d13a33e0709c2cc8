// Exact power sums (internal; docs/search.md, "Power sums"): before the enumeration, the search
// tries whether the target is, to float64 rounding,
//
//   y = M * (c0 + c1 m1 + ... + ck mk)^(1/p),   p in {1, -1, 2, -2}, k <= kPowerSumTerms,
//
// where M is a power product of the inputs (exponents fitted to log |y| and rounded to halves
// or to integers, or M = 1) and each m_j a power product of at most two inputs with exponents in
// {-2, -1, 1, 2}. rho / sqrt(1 - v^2 / c^2) (p = -2, M = rho, m1 = v^2 / c^2),
// mom sqrt(Bx^2 + By^2 + Bz^2) and sqrt(w^2 / c^2 - pi^2 / d^2) are such sums; the evolution
// rarely assembles them (a needle of cost 5 or more among formulas of 3 or 4 inputs). The terms
// are chosen by a beam search over the normal equations of the monomials (at most kPowerSumRows
// rows, evenly spread) and the best subset is refitted by QR on the rows; it counts only when its
// 1 - R^2 in the transformed target is at most kPowerSumExact, so it adds nothing where the data
// is not such a sum (or is noisy). The formula found is offered to the front and seeds the
// evolution, as a start formula does (origin SearchPhase::PowerSum).
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

inline constexpr std::size_t kPowerSumRows = 256;
inline constexpr std::size_t kPowerSumTerms = 3;
inline constexpr double kPowerSumExact = 1e-12;
// Beyond this many inputs the monomials are too many to try (761 at 10). Below kPowerSumMinInputs
// the enumeration reaches cost 4 within its share and finds short sums itself, and the seed
// task (two inputs, about 7 ms to its target) would pay about 3 ms for the try.
inline constexpr std::size_t kPowerSumInputs = 10;
inline constexpr std::size_t kPowerSumMinInputs = 3;

// The formula over the problem's inputs, written with the variables x0, x1, ... (input k is xk)
// and its constants in full precision; nullopt when the target is no such sum, or when an input
// or the target is 0 or not finite on a row read, or the problem has fewer than
// kPowerSumMinInputs or more than kPowerSumInputs inputs.
std::optional<std::string> exact_power_sum(const SearchProblem& problem);

}  // namespace shaderfit::search_detail
