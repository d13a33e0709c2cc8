#include "search/enumeration/enum_costs.hpp"

#include <algorithm>

namespace shaderfit::search_detail {

namespace {

double cost_of(const SearchOptions& options, std::vector<Node> nodes) {
  Expression e;
  e.nodes = std::move(nodes);
  e.variables = {"a", "b", "c"};
  e.update_lengths();
  return expression_cost(e, options.cost);
}

bool has(const SearchOptions& o, Op op) {
  return std::find(o.operators.begin(), o.operators.end(), op) != o.operators.end();
}

// Operator increments below 1 would let a level feed itself; the search treats them as 1.
int at_least_one(double c) { return std::max(1, static_cast<int>(c + 0.5)); }

}  // namespace

bool sign_sensitive(Op op) {
  switch (op) {
    case Op::Rcp:
    case Op::Abs:
    case Op::Sin:
    case Op::Cos:
    case Op::Sign:
    case Op::Asin:  // odd: op(-a) = -op(a), and negating a class is free
    case Op::Atan:
    case Op::Tanh:
    case Op::Erf: return false;
    default: return true;  // acos(-a) = pi - acos(a) among them
  }
}

Enumerator::Costs::Costs(const SearchOptions& o) {
  const Node a = Node::variable(0), b = Node::variable(1), c = Node::variable(2);
  leaf = static_cast<int>(cost_of(o, {a}) + 0.5);
  literal = static_cast<int>(cost_of(o, {Node::constant(2.0)}) + 0.5);
  unary.fill(-1);
  binary.fill(-1);
  for (Op op :
       {Op::Sqrt, Op::Rsqrt, Op::Rcp, Op::Exp2, Op::Log2, Op::Exp, Op::Log, Op::Abs, Op::Saturate,
        Op::Sin, Op::Cos, Op::Sign, Op::Asin, Op::Acos, Op::Atan, Op::Tanh, Op::Erf}) {
    if (has(o, op))
      unary[static_cast<int>(op)] = at_least_one(cost_of(o, {a, Node::op_node(op)}) - leaf);
  }
  if (has(o, Op::IPow)) {
    for (int k = 2; k <= o.max_power; ++k)
      powers.emplace_back(k, at_least_one(cost_of(o, {a, Node::ipow(k)}) - leaf));
  }
  if (has(o, Op::Add) || has(o, Op::Sub)) {
    binary[static_cast<int>(Op::Add)] =
        at_least_one(cost_of(o, {a, b, Node::op_node(Op::Add)}) - 2 * leaf);
  }
  for (Op op : {Op::Mul, Op::Div, Op::Min, Op::Max, Op::Pow, Op::CopySign, Op::Atan2}) {
    if (has(o, op))
      binary[static_cast<int>(op)] = at_least_one(cost_of(o, {a, b, Node::op_node(op)}) - 2 * leaf);
  }
  if (binary[static_cast<int>(Op::Add)] >= 0 && binary[static_cast<int>(Op::Mul)] >= 0) {
    const double product = cost_of(o, {a, b, Node::op_node(Op::Mul)});
    const double sum = cost_of(o, {a, b, Node::op_node(Op::Mul), c, Node::op_node(Op::Add)});
    const int f = static_cast<int>(sum - product - leaf + 0.5);
    if (f < binary[static_cast<int>(Op::Add)]) fused = std::max(0, f);
  }
}

int Enumerator::Costs::literal_increment(const SearchOptions& o, Op op, double value, bool left) {
  const Node a = Node::variable(0), k = Node::constant(value);
  const double leaf_cost = cost_of(o, {a}) + cost_of(o, {k});
  const double c =
      left ? cost_of(o, {k, a, Node::op_node(op)}) : cost_of(o, {a, k, Node::op_node(op)});
  return at_least_one(c - leaf_cost) + static_cast<int>(cost_of(o, {k}) + 0.5);
}

}  // namespace shaderfit::search_detail
