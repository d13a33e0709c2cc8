// Internal: a few shading formulas built node by node (postfix), shared by the evaluator's tests
// and benchmark so that neither depends on the parser.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit::eval_detail {

// Appends nodes in postfix order: PostfixBuilder({"x"}).var(0).ipow(4).done().
class PostfixBuilder {
 public:
  explicit PostfixBuilder(std::vector<std::string> variables) {
    e_.variables = std::move(variables);
  }
  PostfixBuilder& var(int i) { return push(Node::variable(i)); }
  PostfixBuilder& c(double v) { return push(Node::constant(v)); }
  PostfixBuilder& ipow(int k) { return push(Node::ipow(k)); }
  PostfixBuilder& op(Op o) { return push(Node::op_node(o)); }
  Expression done() {
    e_.update_lengths();
    return e_;
  }

 private:
  PostfixBuilder& push(Node n) {
    e_.nodes.push_back(n);
    return *this;
  }
  Expression e_;
};

struct SampleFormula {
  std::string name;
  Expression expression;
};

// The formulas of the benchmark; every variable is meant to lie in (0, 1].
inline std::vector<SampleFormula> sample_formulas() {
  std::vector<SampleFormula> out;
  // One line per subexpression:
  // clang-format off
  // The seed Fresnel fit, 8 nodes: r0 + (x - r0) * x^4.
  out.push_back({"fresnel", PostfixBuilder({"r0", "x"})
      .var(0)
      .var(1).var(0).op(Op::Sub)
      .var(1).ipow(4)
      .op(Op::Mul).op(Op::Add).done()});
  // Schlick, 10 nodes: r0 + (1 - r0) * (1 - c)^5.
  out.push_back({"schlick", PostfixBuilder({"r0", "c"})
      .var(0)
      .c(1).var(0).op(Op::Sub)
      .c(1).var(1).op(Op::Sub).ipow(5)
      .op(Op::Mul).op(Op::Add).done()});
  // 29 nodes: exp2(log2(c) * a) / (1 + sqrt(a*a*(1 - c*c) + c*c)) + r0 * exp2(-5.5 * c).
  out.push_back({"mixed29", PostfixBuilder({"r0", "c", "a"})
      .var(1).op(Op::Log2).var(2).op(Op::Mul).op(Op::Exp2)
      .c(1)
      .var(2).var(2).op(Op::Mul)
      .c(1).var(1).var(1).op(Op::Mul).op(Op::Sub)
      .op(Op::Mul)
      .var(1).var(1).op(Op::Mul)
      .op(Op::Add).op(Op::Sqrt).op(Op::Add)
      .op(Op::Div)
      .var(0).c(-5.5).var(1).op(Op::Mul).op(Op::Exp2).op(Op::Mul)
      .op(Op::Add).done()});
  // 16 nodes: sin(x * 2 pi) * cos(y * pi) + 0.5 * cos(x + y).
  out.push_back({"trig", PostfixBuilder({"x", "y"})
      .var(0).c(6.283185307179586).op(Op::Mul).op(Op::Sin)
      .var(1).c(3.141592653589793).op(Op::Mul).op(Op::Cos)
      .op(Op::Mul)
      .c(0.5).var(0).var(1).op(Op::Add).op(Op::Cos).op(Op::Mul)
      .op(Op::Add).done()});
  // clang-format on
  return out;
}

}  // namespace shaderfit::eval_detail
