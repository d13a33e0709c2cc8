// Random expressions and a scalar reference evaluator for the expression property tests.
#pragma once

#include <cmath>
#include <vector>

#include "shaderfit/core/random.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit::testing {

// A random well-formed expression over `vars` (and parameter "a" if with_param), depth <= depth.
inline void grow(Rng& rng, Expression& e, int depth, bool with_param) {
  const bool leaf = depth <= 0 || bernoulli(rng, 0.25);
  if (leaf) {
    const double u = uniform01(rng);
    if (u < 0.45) {
      e.nodes.push_back(Node::variable(static_cast<int>(uniform_index(rng, e.variables.size()))));
    } else if (with_param && u < 0.55) {
      e.nodes.push_back(Node::parameter(0));
    } else {
      static constexpr double kConsts[] = {0.0, 1.0, 2.0, 0.5, -1.0, -2.5, 3.0, 1e-5, 123456.75, -0.0};
      double v = uniform01(rng) < 0.5 ? kConsts[uniform_index(rng, std::size(kConsts))]
                                      : uniform(rng, -10.0, 10.0);
      e.nodes.push_back(Node::constant(v));
    }
    return;
  }
  Op op = static_cast<Op>(3 + uniform_index(rng, kOpCount - 3));
  const int a = arity(op);
  for (int k = 0; k < a; ++k) grow(rng, e, depth - 1, with_param);
  if (op == Op::IPow) {
    int k = static_cast<int>(uniform_index(rng, 31)) - 15;  // -15..15
    if (k == 0 || k == 1) k = 2;
    e.nodes.push_back(Node::ipow(k));
  } else {
    e.nodes.push_back(Node::op_node(op));
  }
}

inline Expression random_expression(Rng& rng, const std::vector<std::string>& vars, int depth,
                                    bool with_param = false) {
  Expression e;
  e.variables = vars;
  if (with_param) {
    e.parameters = {"a"};
    e.parameter_values = {0.75};
  }
  grow(rng, e, depth, with_param);
  e.update_lengths();
  return e;
}

// Reference evaluation with a plain stack, in any floating type.
// `all_finite`, when given, is cleared if any intermediate value is NaN or infinite.
template <typename T>
T eval_reference(const Expression& e, const std::vector<T>& vars, bool* all_finite = nullptr) {
  std::vector<T> st;
  auto check = [&] {
    if (all_finite && !std::isfinite(st.back())) *all_finite = false;
  };
  for (const Node& n : e.nodes) {
    switch (n.op) {
      case Op::Const: st.push_back(static_cast<T>(n.value)); continue;
      case Op::Var: st.push_back(vars[static_cast<std::size_t>(n.index)]); continue;
      case Op::Param:
        st.push_back(static_cast<T>(e.parameter_values[static_cast<std::size_t>(n.index)]));
        continue;
      default: break;
    }
    if (n.arity == 1) {
      T x = st.back();
      st.back() = n.op == Op::IPow ? apply_ipow(x, n.index) : apply_unary(n.op, x);
      check();
    } else if (n.arity == 2) {
      T y = st.back();
      st.pop_back();
      st.back() = apply_binary(n.op, st.back(), y);
      check();
    } else {
      T z = st.back();
      st.pop_back();
      T y = st.back();
      st.pop_back();
      st.back() = apply_ternary(n.op, st.back(), y, z);
      check();
    }
  }
  return st.back();
}

}  // namespace shaderfit::testing
