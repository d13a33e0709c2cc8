// Forward evaluation of a postfix expression, templated on the number type: the one walk over the
// nodes that every derivative evaluator runs (Taylor jets here, the Jacobian's batches of duals in
// fit/jacobian.cpp).
//
// A `Numbers` policy says what a number is and how the operators act on it:
//   using value_type;                                   // what the stack holds
//   value_type leaf(const Node& n, std::size_t depth);  // Const, Param, Var at stack depth `depth`
//   void unary(const Node& n, value_type& a);           // a = n.op(a) (IPow: exponent n.index)
//   void binary(Op op, value_type& a, const value_type& b);                      // a = op(a, b)
//   void ternary(Op op, value_type& a, const value_type& b, const value_type& c);  // fma, select
// PointNumbers below is the policy of a scalar-like type (double, Jet): each operator is
// expr/op.hpp's apply_* on it.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

// The value of e; `stack` is scratch the caller may reuse between calls. Throws
// shaderfit::Error for a malformed expression. Always inlined, so that a caller compiled for a
// wider ISA runs the policy's loops with it.
template <typename Numbers>
[[gnu::always_inline]] inline typename Numbers::value_type evaluate_forward(
    const Expression& e, Numbers& numbers, std::vector<typename Numbers::value_type>& stack) {
  stack.clear();
  for (const Node& n : e.nodes) {
    const int a = arity(n.op);
    if (stack.size() < static_cast<std::size_t>(a))
      throw Error("evaluate_forward: malformed expression");
    switch (a) {
      case 0: stack.push_back(numbers.leaf(n, stack.size())); break;
      case 1: numbers.unary(n, stack.back()); break;
      case 2:
        numbers.binary(n.op, stack[stack.size() - 2], stack.back());
        stack.pop_back();
        break;
      default:
        numbers.ternary(n.op, stack[stack.size() - 3], stack[stack.size() - 2], stack.back());
        stack.pop_back();
        stack.pop_back();
        break;
    }
  }
  if (stack.size() != 1) throw Error("evaluate_forward: malformed expression");
  return stack.back();
}

// Numbers of a scalar-like type T: every Var node reads `variables[index]`, every Param node
// `parameters[index]` (Error when missing), every Const its value.
template <typename T>
struct PointNumbers {
  using value_type = T;
  std::span<const T> variables;
  std::span<const double> parameters;

  T leaf(const Node& n, std::size_t /*depth*/) const {
    const auto i = static_cast<std::size_t>(n.index);
    if (n.op == Op::Var) {
      if (i >= variables.size()) throw Error("evaluate_forward: a variable has no value");
      return variables[i];
    }
    if (n.op == Op::Param) {
      if (i >= parameters.size()) throw Error("evaluate_forward: a parameter has no value");
      return T(parameters[i]);
    }
    return T(n.value);
  }
  void unary(const Node& n, T& a) const {
    a = apply_unary(n.op, a, n.index);
  }
  void binary(Op op, T& a, const T& b) const { a = apply_binary(op, a, b); }
  void ternary(Op op, T& a, const T& b, const T& c) const { a = apply_ternary(op, a, b, c); }
};

// e at one point, on numbers of type T (a Jet gives every derivative it carries).
template <typename T>
T evaluate_at(const Expression& e, std::span<const T> variables,
              std::span<const double> parameters) {
  PointNumbers<T> numbers{variables, parameters};
  std::vector<T> stack;
  stack.reserve(e.nodes.size());
  return evaluate_forward(e, numbers, stack);
}

// e at x where every variable takes the value x (formulas of one variable).
template <typename T>
T evaluate_at(const Expression& e, const T& x, std::span<const double> parameters) {
  const std::vector<T> variables(e.variables.empty() ? 1 : e.variables.size(), x);
  return evaluate_at<T>(e, std::span<const T>(variables), parameters);
}

}  // namespace shaderfit
