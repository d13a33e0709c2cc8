// The per-material values the search offers as free terminals (internal).
//
// With per-material inputs (SearchOptions::uniform), a subexpression that reads only them costs
// nothing per pixel (cost/per_material.hpp). The enumeration takes these values as leaves beside
// the inputs, and the evolution's mutations insert them as building blocks, so that per-pixel
// forms are built on them: for each uniform input u, 1/u, u^2, 1/u^2, sqrt(u), log2(u) and
// exp2(u), each kept where it is finite on every row, varies, and differs from the others
// (whatever operators the search may use per pixel: these run once per material). At most 100
// inputs and terminals together (the enumeration's leaf index is a byte).
#pragma once

#include <vector>

#include "shaderfit/expr/expression.hpp"
#include "shaderfit/search/options.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

// Over problem.input_names; empty without uniform inputs.
std::vector<Expression> uniform_terminals(const SearchProblem& problem,
                                          const SearchOptions& options);

}  // namespace shaderfit::search_detail
