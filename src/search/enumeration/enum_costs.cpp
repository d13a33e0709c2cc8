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
  // Odd (op(-a) = -op(a), and negating a class is free) and even ones are not; acos(-a) =
  // pi - acos(a) is.
  return op_info(op).parity == OpParity::None;
}

Enumerator::Costs::Costs(const SearchOptions& o) {
  const Node a = Node::variable(0), b = Node::variable(1), c = Node::variable(2);
  leaf = static_cast<int>(cost_of(o, {a}) + 0.5);
  literal = static_cast<int>(cost_of(o, {Node::constant(2.0)}) + 0.5);
  unary.fill(-1);
  binary.fill(-1);
  // The searchable operators of one and two operands; ipow (by its powers), + and - (one cost)
  // and the ternary ones apart.
  for (int i = 0; i < kOpCount; ++i) {
    const Op op = static_cast<Op>(i);
    if (op_info(op).search == 0 || !has(o, op) || op == Op::IPow) continue;
    if (arity(op) == 1)
      unary[static_cast<std::size_t>(i)] = at_least_one(cost_of(o, {a, Node::op_node(op)}) - leaf);
    else if (arity(op) == 2 && op != Op::Add && op != Op::Sub)
      binary[static_cast<std::size_t>(i)] =
          at_least_one(cost_of(o, {a, b, Node::op_node(op)}) - 2 * leaf);
  }
  if (has(o, Op::IPow)) {
    for (int k = 2; k <= o.max_power; ++k)
      powers.emplace_back(k, at_least_one(cost_of(o, {a, Node::ipow(k)}) - leaf));
  }
  if (has(o, Op::Add) || has(o, Op::Sub)) {
    binary[static_cast<int>(Op::Add)] =
        at_least_one(cost_of(o, {a, b, Node::op_node(Op::Add)}) - 2 * leaf);
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
