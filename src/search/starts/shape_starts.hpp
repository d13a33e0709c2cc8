// Shading shapes as starts (internal; docs/search.md, "Shading shapes"): for a problem with a
// reference and a target > 0 on every row, after the descent from it, forms fitted to the rows
// that shading functions are made of and that rewriting the reference seldom reaches:
//  - products of factors of one varying input each, S F1(x1) F2(x2) ..., each factor searched
//    alone first: the target's log is split into a sum of polynomials of one input each (least
//    squares), and 2^polynomial of each input fitted by the one-input shapes below, the best at
//    each cost kept; then every product of those (an input's factor may be left out), screened on
//    the rows and the best few at each cost refitted together;
//  - one-input shapes: a + b x, a + x (b + c x), exp2(a + b x), exp2(a + x (b + c x)), a power of
//    a linear form (a + b x)^p and (a + b x^2)^p with p fitted, Schlick-like factors
//    a + b (c - x)^5 and a + b (c - x)^k, their exp2 form a + b exp2(k x), and
//    (a + b x) / (c + d x);
//  - a power of a linear form and of a quadratic in all the varying inputs,
//    S (1 + c1 x + c2 y + ...)^p (the phase functions).
// Under --uniform every coefficient is a quadratic in each per-material input (free per pixel).
// Offered to the front (SearchPhase::Shape) with their constants free, after the descent from the
// reference; a descent of their own follows.
#pragma once

#include <cstddef>
#include <vector>

#include "search/search_context.hpp"
#include "search/starts/start.hpp"

namespace shaderfit::search_detail {

// The share of the time limit (and of a candidate budget) the shapes' fits may use, and that of
// the descent from them, which follows the reference's own (descent.hpp).
inline constexpr double kShapeShare = 0.05;
inline constexpr double kShapeDescentShare = 0.1;
// Samples of a factor's one-input target; one-input shapes kept per factor; products refitted
// per cost level.
inline constexpr std::size_t kShapeFactorSamples = 64;
inline constexpr std::size_t kShapeFormsPerFactor = 4;
inline constexpr std::size_t kShapeRefitsPerCost = 2;

// The shapes for ctx's problem, fitted on descent_rows of it for ctx.options.loss (origin
// SearchPhase::Shape, `fitted`), cheapest first; empty unless the target is > 0 on every row
// and some input is not per-material. Stops when ctx stops or ctx.elapsed() passes `until_s`.
std::vector<StartFormula> shape_starts(SearchContext& ctx, double until_s);

}  // namespace shaderfit::search_detail
