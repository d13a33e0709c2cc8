// Random formulas, mutation and crossover on postfix expressions (internal).
//
// Every routine takes the generator first and returns a new expression (the inputs are not
// changed); children that break a limit come back empty. Parameters are renumbered p0, p1, ...
// in order of appearance after every change.
#pragma once

#include <vector>

#include "shaderfit/core/random.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit::search_detail {

struct VariationLimits {
  std::vector<std::string> variables;  // the problem's inputs
  std::vector<Op> operators;           // as in SearchOptions (Op::IPow: 2 .. max_power)
  int max_power = 5;
  std::vector<double> literals;
  std::size_t max_nodes = 25;
  int max_parameters = 4;
  // Building blocks a mutation may insert instead of a random subtree (subtree_blocks); each
  // carries its parameters' values in Node::value.
  std::vector<std::vector<Node>> blocks;
};

// The distinct subtrees of 2 to kMaxBlockNodes nodes of the given formulas, in order of
// appearance, at most kMaxBlocks: the parts of the front's formulas, for mutations to reuse
// anywhere (a sub-formula that explains part of the data in one member often does in another).
inline constexpr std::size_t kMaxBlockNodes = 9;
inline constexpr std::size_t kMaxBlocks = 256;
std::vector<std::vector<Node>> subtree_blocks(const std::vector<const Expression*>& formulas);

// A random formula grown to at most `depth` operator levels.
Expression random_formula(Rng& rng, const VariationLimits& limits, int depth);

// One random mutation: a point change (operator or leaf), a new random subtree (half the time one
// of limits.blocks, when there are any), hoisting a
// child over its parent, wrapping a subtree in a new operator, turning a literal into a free
// parameter, scaling or shifting a subtree by a new parameter, or jittering a parameter.
Expression mutate(Rng& rng, const Expression& e, const VariationLimits& limits);

// Subtree crossover: a random subtree of `a` replaced by a random subtree of `b`.
Expression crossover(Rng& rng, const Expression& a, const Expression& b,
                     const VariationLimits& limits);

// The formula with its Param nodes renumbered in order of appearance and unused parameters
// dropped; empty when there are more than limits.max_parameters or more than max_nodes nodes.
Expression normalize_parameters(Expression e, const VariationLimits& limits);

// a * e + b with two new parameters (the optimal linear scaling's form).
Expression with_linear_scaling(const Expression& e, double a, double b);

// e with each number literal turned into a parameter at the literal's value (no limits).
Expression with_literals_as_parameters(const Expression& e);

}  // namespace shaderfit::search_detail
