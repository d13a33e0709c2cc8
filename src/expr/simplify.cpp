// Bottom-up simplification. Each subtree is rebuilt from its simplified children through make(),
// which applies the local rules; rules only fire when the result equals the original wherever the
// original is finite (e.g. x - x = 0, x / x = 1). Rules that may turn a -0 into +0 (x + 0 = x,
// x * 0 = 0, ...) also skip subtrees whose sign of zero reaches the result: those that feed the
// second operand of a copysign through operators that pass a zero's sign on.
#include "shaderfit/expr/simplify.hpp"

#include <cmath>

namespace shaderfit {

namespace {

using Frag = std::vector<Node>;  // a postfix subtree

bool is_const(const Frag& f, double v) {
  return f.size() == 1 && f[0].op == Op::Const && f[0].value == v;
}
bool is_const(const Frag& f) { return f.size() == 1 && f[0].op == Op::Const; }
const Node& root(const Frag& f) { return f.back(); }

// The single child of a unary root (all nodes but the last).
Frag operand(const Frag& f) { return Frag(f.begin(), f.end() - 1); }

bool same(const Frag& a, const Frag& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!(a[i] == b[i])) return false;
  return true;
}

bool power_in_range(int k) { return k >= kMinIntegerPower && k <= kMaxIntegerPower; }

// Base and exponent of x^k (k = 1 when f is not an integer power).
std::pair<Frag, int> as_power(const Frag& f) {
  if (root(f).op == Op::IPow) return {operand(f), root(f).index};
  return {f, 1};
}

Frag constant(double v) { return Frag{Node::constant(v)}; }

Frag make(Op op, const std::vector<Frag>& kids, bool signed_zero);

// base^k, simplified for k = 0 and 1; caller checks the range.
Frag power(const Frag& base, int k) {
  if (k == 0) return constant(1.0);
  if (k == 1) return base;
  return make(Op::IPow, {base, Frag{Node::ipow(k)}}, false);
}

Frag assemble(Op op, const std::vector<Frag>& kids, int ipow_k = 0) {
  Frag out;
  for (const Frag& k : kids) out.insert(out.end(), k.begin(), k.end());
  out.push_back(op == Op::IPow ? Node::ipow(ipow_k) : Node::op_node(op));
  // Fix the root's length (children already have theirs).
  std::uint32_t len = 0;
  for (const Frag& k : kids) len += static_cast<std::uint32_t>(k.size());
  out.back().length = len;
  return out;
}

// For IPow, kids = {base, {ipow node}} so the exponent travels along.
// `signed_zero`: the sign of a zero result matters here (see the top of the file).
Frag make(Op op, const std::vector<Frag>& in, bool signed_zero) {
  int k = 0;
  std::vector<Frag> kids = in;
  if (op == Op::IPow) {
    k = in[1][0].index;
    kids.pop_back();
  }
  const int a = arity(op);

  // Constant folding (only to a finite result, which prints and re-parses exactly).
  bool all_const = true;
  for (const Frag& f : kids) all_const = all_const && is_const(f);
  if (all_const) {
    double v = 0;
    if (op == Op::IPow)
      v = apply_ipow(kids[0][0].value, k);
    else if (a == 3)
      v = apply_ternary(op, kids[0][0].value, kids[1][0].value, kids[2][0].value);
    else if (a == 2)
      v = apply_binary(op, kids[0][0].value, kids[1][0].value);
    else
      v = apply_unary(op, kids[0][0].value);
    if (std::isfinite(v)) return constant(v);
  }

  switch (op) {
    case Op::Add: {
      const Frag &x = kids[0], &y = kids[1];
      if (is_const(y, 0) && !signed_zero) return x;
      if (is_const(x, 0) && !signed_zero) return y;
      if (root(y).op == Op::Neg) return make(Op::Sub, {x, operand(y)}, signed_zero);
      if (root(x).op == Op::Neg) return make(Op::Sub, {y, operand(x)}, signed_zero);
      break;
    }
    case Op::Sub: {
      const Frag &x = kids[0], &y = kids[1];
      if (is_const(y, 0)) return x;
      if (is_const(x, 0) && !signed_zero) return make(Op::Neg, {y}, signed_zero);
      if (same(x, y)) return constant(0.0);
      if (root(y).op == Op::Neg) return make(Op::Add, {x, operand(y)}, signed_zero);
      break;
    }
    case Op::Mul: {
      const Frag &x = kids[0], &y = kids[1];
      if (is_const(x, 1)) return y;
      if (is_const(y, 1)) return x;
      if ((is_const(x, 0) || is_const(y, 0)) && !signed_zero) return constant(0.0);
      if (is_const(x, -1)) return make(Op::Neg, {y}, signed_zero);
      if (is_const(y, -1)) return make(Op::Neg, {x}, signed_zero);
      if (root(x).op == Op::Neg && root(y).op == Op::Neg)
        return make(Op::Mul, {operand(x), operand(y)}, signed_zero);
      auto [bx, kx] = as_power(x);
      auto [by, ky] = as_power(y);
      if (same(bx, by) && power_in_range(kx + ky)) return power(bx, kx + ky);
      break;
    }
    case Op::Div: {
      const Frag &x = kids[0], &y = kids[1];
      if (is_const(y, 1)) return x;
      if (is_const(y, -1)) return make(Op::Neg, {x}, signed_zero);
      if (is_const(x, 0) && !signed_zero) return constant(0.0);
      if (same(x, y)) return constant(1.0);
      auto [bx, kx] = as_power(x);
      auto [by, ky] = as_power(y);
      if (same(bx, by) && power_in_range(kx - ky)) return power(bx, kx - ky);
      if (is_const(x, 1)) return make(Op::Rcp, {y}, signed_zero);
      break;
    }
    case Op::Neg:
      if (root(kids[0]).op == Op::Neg) return operand(kids[0]);
      break;
    case Op::IPow: {
      auto [b, inner] = as_power(kids[0]);
      if (inner != 1 && power_in_range(inner * k)) return power(b, inner * k);
      if (k % 2 == 0 && (root(kids[0]).op == Op::Neg || root(kids[0]).op == Op::Abs))
        return power(operand(kids[0]), k);
      break;
    }
    case Op::Abs: {
      const Op r = root(kids[0]).op;
      if (r == Op::Abs || r == Op::Neg) return make(Op::Abs, {operand(kids[0])}, signed_zero);
      if (r == Op::IPow && root(kids[0]).index % 2 == 0) return kids[0];
      break;
    }
    case Op::Saturate:
      if (root(kids[0]).op == Op::Saturate) return kids[0];
      break;
    case Op::Sign:
      if (root(kids[0]).op == Op::Sign) return kids[0];
      break;
    case Op::Select: {
      // A constant condition picks its branch (a NaN one: c); equal branches need no condition.
      const Frag &x = kids[0], &y = kids[1], &z = kids[2];
      if (is_const(x)) return apply_select(x[0].value, 1.0, 0.0) != 0.0 ? y : z;
      if (same(y, z)) return y;
      break;
    }
    case Op::Min:
    case Op::Max:
      if (same(kids[0], kids[1])) return kids[0];
      break;
    case Op::Fma: {
      const Frag &x = kids[0], &y = kids[1], &z = kids[2];
      if (is_const(z, 0) && !signed_zero) return make(Op::Mul, {x, y}, signed_zero);
      if (is_const(x, 1)) return make(Op::Add, {y, z}, signed_zero);
      if (is_const(y, 1)) return make(Op::Add, {x, z}, signed_zero);
      if ((is_const(x, 0) || is_const(y, 0)) && !signed_zero) return z;
      break;
    }
    default: break;
  }
  return assemble(op, kids, k);
}

}  // namespace

Expression simplify(const Expression& e) {
  Expression out;
  out.variables = e.variables;
  out.parameters = e.parameters;
  out.parameter_values = e.parameter_values;
  if (e.nodes.empty()) return out;
  // Top-down: whether each node's sign of zero reaches the result through a copysign.
  std::vector<char> signed_zero(e.nodes.size(), 0);
  std::size_t kids_at[3];
  for (std::size_t i = e.nodes.size(); i-- > 0;) {
    const Node& n = e.nodes[i];
    if (n.arity == 0) continue;
    e.child_indices(i, std::span<std::size_t>(kids_at, n.arity));
    for (int k = 0; k < n.arity; ++k) {
      // |x|, even powers, copysign's magnitude and select's condition drop a zero's sign.
      const bool drops = n.op == Op::Abs || (n.op == Op::IPow && n.index % 2 == 0) ||
                         (n.op == Op::CopySign && k == 0) || (n.op == Op::Select && k == 0);
      signed_zero[kids_at[k]] = (n.op == Op::CopySign && k == 1) || (signed_zero[i] && !drops);
    }
  }
  // Replay the postfix order with a stack of simplified fragments.
  std::vector<Frag> stack;
  for (std::size_t i = 0; i < e.nodes.size(); ++i) {
    const Node& n = e.nodes[i];
    if (n.arity == 0) {
      Node leaf = n;
      leaf.length = 0;
      stack.push_back(Frag{leaf});
      continue;
    }
    std::vector<Frag> kids(n.arity);
    for (int k = n.arity - 1; k >= 0; --k) {
      kids[static_cast<std::size_t>(k)] = std::move(stack.back());
      stack.pop_back();
    }
    if (n.op == Op::IPow) kids.push_back(Frag{Node::ipow(n.index)});
    stack.push_back(make(n.op, kids, signed_zero[i] != 0));
  }
  out.nodes = std::move(stack.back());
  out.update_lengths();
  return out;
}

}  // namespace shaderfit
