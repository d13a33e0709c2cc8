#include "rational/jet_eval.hpp"

#include <vector>

#include "shaderfit/core/error.hpp"

namespace shaderfit::rational::detail {

namespace {

Jet integer_power(const Jet& a, int k) {
  const bool inverse = k < 0;
  int m = inverse ? -k : k;
  Jet r(1.0), base = a;
  while (m != 0) {
    if (m & 1) r = r * base;
    m >>= 1;
    if (m != 0) base = base * base;
  }
  return inverse ? Jet(1.0) / r : r;
}

Jet unary(Op op, const Jet& a) {
  switch (op) {
    case Op::Neg: return -a;
    case Op::Sqrt: return sqrt(a);
    case Op::Rsqrt: return Jet(1.0) / sqrt(a);
    case Op::Rcp: return Jet(1.0) / a;
    case Op::Exp2: return exp2(a);
    case Op::Log2: return log2(a);
    case Op::Exp: return exp(a);
    case Op::Log: return log(a);
    case Op::Abs: return abs(a);
    case Op::Saturate: return a.value() < 0 ? Jet(0.0) : (a.value() > 1 ? Jet(1.0) : a);
    case Op::Sin: return sin(a);
    case Op::Cos: return cos(a);
    default: throw Error("jet evaluation: not a unary operator");
  }
}

Jet binary(Op op, const Jet& a, const Jet& b) {
  switch (op) {
    case Op::Add: return a + b;
    case Op::Sub: return a - b;
    case Op::Mul: return a * b;
    case Op::Div: return a / b;
    case Op::Min: return b.value() < a.value() ? b : a;
    case Op::Max: return b.value() > a.value() ? b : a;
    case Op::Pow: return exp2(b * log2(a));
    default: throw Error("jet evaluation: not a binary operator");
  }
}

}  // namespace

Jet evaluate_jet(const Expression& e, const Jet& x, std::span<const double> params) {
  std::vector<Jet> stack;
  stack.reserve(e.nodes.size());
  for (const Node& n : e.nodes) {
    switch (arity(n.op)) {
      case 0:
        if (n.op == Op::Var) {
          stack.push_back(x);
        } else if (n.op == Op::Param) {
          const auto i = static_cast<std::size_t>(n.index);
          if (i >= params.size()) throw Error("jet evaluation: a parameter has no value");
          stack.push_back(Jet(params[i]));
        } else {
          stack.push_back(Jet(n.value));
        }
        break;
      case 1:
        stack.back() =
            n.op == Op::IPow ? integer_power(stack.back(), n.index) : unary(n.op, stack.back());
        break;
      case 2: {
        const Jet b = stack.back();
        stack.pop_back();
        stack.back() = binary(n.op, stack.back(), b);
        break;
      }
      default: {
        const Jet c = stack.back();
        stack.pop_back();
        const Jet b = stack.back();
        stack.pop_back();
        stack.back() = stack.back() * b + c;
        break;
      }
    }
  }
  if (stack.size() != 1) throw Error("jet evaluation: malformed expression");
  return stack.back();
}

}  // namespace shaderfit::rational::detail
