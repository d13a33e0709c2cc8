// Expressions: a flat postfix array of plain nodes, shared by the parser, the evaluators, the
// fitters, the search, the cost model, code generation and the GPU.
//
//   Expression e = parse_formula("r0 + (x - r0) * x^4", {.variables = {"r0", "x"}});
//   // e.nodes, in postfix: r0 x r0 - x ipow(4) * +
//   e.nodes.back().op == Op::Add;
//
// A node's children precede it: the last child is at i - 1, the one before it ends just before
// that child's subtree begins (see `child_indices`).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "shaderfit/expr/op.hpp"

namespace shaderfit {

struct Node {
  Op op = Op::Const;
  std::uint8_t arity = 0;
  std::int16_t index = 0;   // variable or parameter index (Var, Param), exponent (IPow)
  std::uint32_t length = 0; // number of nodes in the subtrees below this node (0 for a leaf)
  double value = 0.0;       // the constant (Const)

  static Node constant(double v) { return Node{Op::Const, 0, 0, 0, v}; }
  static Node variable(int i) { return Node{Op::Var, 0, static_cast<std::int16_t>(i), 0, 0.0}; }
  static Node parameter(int i) { return Node{Op::Param, 0, static_cast<std::int16_t>(i), 0, 0.0}; }
  static Node ipow(int k) { return Node{Op::IPow, 1, static_cast<std::int16_t>(k), 0, 0.0}; }
  static Node op_node(Op o) { return Node{o, static_cast<std::uint8_t>(shaderfit::arity(o)), 0, 0, 0.0}; }

  friend bool operator==(const Node& a, const Node& b) {
    return a.op == b.op && a.arity == b.arity && a.index == b.index && a.length == b.length &&
           (a.op != Op::Const || a.value == b.value || (a.value != a.value && b.value != b.value));
  }
};

struct Expression {
  std::vector<Node> nodes;               // postfix
  std::vector<std::string> variables;    // names that Var nodes index
  std::vector<std::string> parameters;   // names that Param nodes index
  std::vector<double> parameter_values;  // one per parameter (fitted or given values)

  [[nodiscard]] std::size_t size() const { return nodes.size(); }
  [[nodiscard]] bool empty() const { return nodes.empty(); }

  // Recomputes Node::length and Node::arity for every node; call after editing `nodes`.
  // Throws shaderfit::Error if the postfix array is not one well-formed tree.
  void update_lengths();

  // Index of the first node of the subtree rooted at i.
  [[nodiscard]] std::size_t subtree_begin(std::size_t i) const { return i - nodes[i].length; }

  // The indices of node i's children, first operand first. Writes arity(i) entries.
  void child_indices(std::size_t i, std::span<std::size_t> out) const;

  // Removes the variables no Var node uses and renumbers the rest, keeping their order.
  void drop_unused_variables();

  // Copies the subtree rooted at i as an expression with the same variable and parameter tables.
  [[nodiscard]] Expression subtree(std::size_t i) const;

  // Structural equality: same nodes and the same names for the variables and parameters used.
  friend bool operator==(const Expression& a, const Expression& b);
};

// Structural hash of the subtree rooted at each node (same size as e.nodes). Commutative operators
// combine their children's hashes in an order-independent way, so `a + b` and `b + a` hash alike.
// Variables hash by name, so expressions over different variable tables compare meaningfully.
std::vector<std::uint64_t> subtree_hashes(const Expression& e);
std::uint64_t structural_hash(const Expression& e);

// Number of nodes that are not leaves.
std::size_t operator_count(const Expression& e);

// The prefix of the names a printer gives its own values (prefix0, prefix1, ...): `letter` with
// as many leading underscores as it takes that no variable or parameter of e is named the prefix
// followed by digits.
std::string unused_name_prefix(const Expression& e, char letter);

}  // namespace shaderfit
