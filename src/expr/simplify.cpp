// Bottom-up simplification. Each subtree is rebuilt from its simplified children through make(),
// which applies the local rules; rules only fire when the result equals the original wherever the
// original is finite (e.g. x - x = 0, x / x = 1). Rules that may turn a -0 into +0 (x + 0 = x,
// x * 0 = 0, ...) also skip subtrees whose sign of zero reaches the result: those that feed the
// second operand of a copysign, or either operand of an atan2, through operators that pass a
// zero's sign on.
//
// With SimplifyOptions::regroup_constants, further rules move constants through sums and
// products (they hold in real arithmetic and round differently): scaled() and shifted() push a
// factor or an offset into a subtree's own constant, never adding a node; and a term added and
// taken away again cancels ((a + b) - b = a).
#include "shaderfit/expr/simplify.hpp"

#include <cmath>
#include <optional>

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

std::optional<Frag> finite_constant(double v) {
  if (!std::isfinite(v)) return std::nullopt;
  return constant(v);
}

// The children of f's root, first operand first.
std::vector<Frag> children(const Frag& f) {
  std::vector<Frag> kids(static_cast<std::size_t>(root(f).arity));
  auto end = f.end() - 1;
  for (std::size_t k = kids.size(); k-- > 0;) {
    const auto begin = end - 1 - static_cast<std::ptrdiff_t>((end - 1)->length);
    kids[k] = Frag(begin, end);
    end = begin;
  }
  return kids;
}

// A term as a multiple k x of a non-constant x: c * x or x * c (k = c), -x (k = -1), x (k = 1).
std::optional<std::pair<double, Frag>> as_multiple(const Frag& f) {
  if (is_const(f)) return std::nullopt;
  if (root(f).op == Op::Neg) return std::make_pair(-1.0, operand(f));
  if (root(f).op == Op::Mul) {
    std::vector<Frag> kids = children(f);
    for (int side = 0; side < 2; ++side) {
      const Frag &c = kids[static_cast<std::size_t>(side)],
                 &x = kids[static_cast<std::size_t>(1 - side)];
      if (is_const(c) && !is_const(x)) return std::make_pair(c[0].value, x);
    }
  }
  return std::make_pair(1.0, f);
}

// The rules, with the options and the tables that cost callbacks need.
class Rules {
 public:
  Rules(const SimplifyOptions& options, const Expression& source)
      : options_(options), source_(source) {}

  // base^k, simplified for k = 0 and 1; caller checks the range.
  Frag power(const Frag& base, int k) const {
    if (k == 0) return constant(1.0);
    if (k == 1) return base;
    return make(Op::IPow, {base, Frag{Node::ipow(k)}}, false);
  }

  static Frag assemble(Op op, const std::vector<Frag>& kids, int ipow_k = 0) {
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
  Frag make(Op op, const std::vector<Frag>& in, bool signed_zero) const {
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
      if (a == 3)
        v = apply_ternary(op, kids[0][0].value, kids[1][0].value, kids[2][0].value);
      else if (a == 2)
        v = apply_binary(op, kids[0][0].value, kids[1][0].value);
      else
        v = apply_unary(op, kids[0][0].value, k);
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
    if (options_.merge_calls && !signed_zero)
      if (std::optional<Frag> r = merged(op, kids)) return *std::move(r);
    if (options_.regroup_constants && !signed_zero)
      if (std::optional<Frag> r = regrouped(op, kids)) return *std::move(r);
    return assemble(op, kids, k);
  }

 private:
  std::optional<Frag> merged(Op op, const std::vector<Frag>& kids) const;
  std::optional<Frag> merged_pair(Op op, const Frag& x, const Frag& y) const;
  std::optional<Frag> regrouped(Op op, const std::vector<Frag>& kids) const;
  std::optional<Frag> like_terms(Op op, const Frag& x, const Frag& y) const;
  std::optional<Frag> scaled(const Frag& f, double k) const;
  std::optional<Frag> shifted(const Frag& f, double d) const;
  Frag power_of_power(const Frag& a, const Frag& y, const Frag& z) const;

  const SimplifyOptions& options_;
  const Expression& source_;
};

// f * k in at most f's nodes, when f has constants that can take the factor: a constant, a
// product or quotient with such a factor, a sum or difference of two such terms, -f, fma.
std::optional<Frag> Rules::scaled(const Frag& f, double k) const {
  if (is_const(f)) return finite_constant(f[0].value * k);
  const Op op = root(f).op;
  if (op == Op::Neg) return scaled(operand(f), -k);
  if (op != Op::Mul && op != Op::Div && op != Op::Add && op != Op::Sub && op != Op::Fma)
    return std::nullopt;
  std::vector<Frag> kids = children(f);
  if (op == Op::Mul || op == Op::Div) {
    if (std::optional<Frag> a = scaled(kids[0], k)) return make(op, {*a, kids[1]}, false);
    if (op == Op::Mul) {
      if (std::optional<Frag> b = scaled(kids[1], k)) return make(op, {kids[0], *b}, false);
    } else if (is_const(kids[1])) {
      if (std::optional<Frag> b = finite_constant(kids[1][0].value / k))
        return make(op, {kids[0], *b}, false);
    }
    return std::nullopt;
  }
  if (op == Op::Fma) {  // a * b + c
    std::optional<Frag> c = scaled(kids[2], k);
    if (!c) return std::nullopt;
    if (std::optional<Frag> a = scaled(kids[0], k)) return make(op, {*a, kids[1], *c}, false);
    if (std::optional<Frag> b = scaled(kids[1], k)) return make(op, {kids[0], *b, *c}, false);
    return std::nullopt;
  }
  std::optional<Frag> a = scaled(kids[0], k);
  if (!a) return std::nullopt;
  std::optional<Frag> b = scaled(kids[1], k);
  if (!b) return std::nullopt;
  return make(op, {*a, *b}, false);
}

// f + d in at most f's nodes, when f has a constant term that can take the offset (through
// sums, differences, -f, fma's addend, and products and quotients by a constant).
std::optional<Frag> Rules::shifted(const Frag& f, double d) const {
  if (is_const(f)) return finite_constant(f[0].value + d);
  const Op op = root(f).op;
  if (op == Op::Neg) {
    if (std::optional<Frag> a = shifted(operand(f), -d)) return make(Op::Neg, {*a}, false);
    return std::nullopt;
  }
  if (op != Op::Add && op != Op::Sub && op != Op::Fma && op != Op::Mul && op != Op::Div)
    return std::nullopt;
  std::vector<Frag> kids = children(f);
  switch (op) {
    case Op::Add:
    case Op::Sub:
      if (std::optional<Frag> a = shifted(kids[0], d)) return make(op, {*a, kids[1]}, false);
      if (std::optional<Frag> b = shifted(kids[1], op == Op::Add ? d : -d))
        return make(op, {kids[0], *b}, false);
      return std::nullopt;
    case Op::Fma:
      if (std::optional<Frag> c = shifted(kids[2], d))
        return make(op, {kids[0], kids[1], *c}, false);
      return std::nullopt;
    case Op::Mul:
      if (is_const(kids[0]) && kids[0][0].value != 0)
        if (std::optional<Frag> b = shifted(kids[1], d / kids[0][0].value))
          return make(op, {kids[0], *b}, false);
      if (is_const(kids[1]) && kids[1][0].value != 0)
        if (std::optional<Frag> a = shifted(kids[0], d / kids[1][0].value))
          return make(op, {*a, kids[1]}, false);
      return std::nullopt;
    default:  // Div
      if (is_const(kids[1]))
        if (std::optional<Frag> a = shifted(kids[0], d * kids[1][0].value))
          return make(op, {*a, kids[1]}, false);
      return std::nullopt;
  }
}

// pow(pow(a, y), z) = pow(a, y * z): both are exp2(z * y * log2(a)) (for a < 0 both are NaN,
// for a = 0 both are 0 or infinite alike). For a constant a > 0 and a cost callback, the
// cheaper of that and exp2(log2(a) * y * z) (pow as the op defines it); on a tie, pow.
Frag Rules::power_of_power(const Frag& a, const Frag& y, const Frag& z) const {
  const Frag e = make(Op::Mul, {y, z}, false);
  Frag pow_form = make(Op::Pow, {a, e}, false);
  if (!options_.cost || !is_const(a) || !(a[0].value > 0)) return pow_form;
  const std::optional<Frag> c = finite_constant(std::log2(a[0].value));
  if (!c) return pow_form;
  Frag exp2_form = make(Op::Exp2, {make(Op::Mul, {*c, e}, false)}, false);
  const auto cost = [&](const Frag& f) {
    Expression x;
    x.variables = source_.variables;
    x.parameters = source_.parameters;
    x.parameter_values = source_.parameter_values;
    x.nodes = f;
    x.update_lengths();
    return options_.cost(x);
  };
  return cost(exp2_form) < cost(pow_form) ? exp2_form : pow_form;
}

// x op y as one call (kCallMerges, and pow(a, p) * pow(b, p) = pow(a b, p)), or a quotient's
// divisors as one product: (u / a) / b = u / (a b), rcp(a) / b = rcp(a b), u / rcp(a) = u a,
// (u / a) * rcp(b) = u / (a b); nullopt when none applies. Never adds a node.
std::optional<Frag> Rules::merged_pair(Op op, const Frag& x, const Frag& y) const {
  const Op rx = root(x).op, ry = root(y).op;
  for (const CallMerge& m : kCallMerges)
    if (op == m.outer && rx == m.call && ry == m.call)
      return make(m.call, {make(m.inner, {operand(x), operand(y)}, false)}, false);
  if (op == Op::Mul && rx == Op::Pow && ry == Op::Pow) {
    const std::vector<Frag> a = children(x), b = children(y);
    if (same(a[1], b[1])) return make(Op::Pow, {make(Op::Mul, {a[0], b[0]}, false), a[1]}, false);
  }
  if (op == Op::Div) {
    if (rx == Op::Div) {
      const std::vector<Frag> ua = children(x);
      return make(Op::Div, {ua[0], make(Op::Mul, {ua[1], y}, false)}, false);
    }
    if (rx == Op::Rcp) return make(Op::Rcp, {make(Op::Mul, {operand(x), y}, false)}, false);
    if (ry == Op::Rcp) return make(Op::Mul, {x, operand(y)}, false);
  }
  if (op == Op::Mul)
    for (int side = 0; side < 2; ++side) {
      const Frag &q = side == 0 ? x : y, &r = side == 0 ? y : x;
      if (root(q).op == Op::Div && root(r).op == Op::Rcp) {
        const std::vector<Frag> ua = children(q);
        return make(Op::Div, {ua[0], make(Op::Mul, {ua[1], operand(r)}, false)}, false);
      }
    }
  return std::nullopt;
}

// merge_calls: a pair of the kids merged, or, for a product or sum with a product or sum of the
// same kind beside it, one of its operands merged with the other kid ((u * rcp(a)) * rcp(b) =
// u * rcp(a b)). For a result whose sign of zero does not matter.
std::optional<Frag> Rules::merged(Op op, const std::vector<Frag>& kids) const {
  if (op != Op::Mul && op != Op::Div && op != Op::Add) return std::nullopt;
  if (std::optional<Frag> r = merged_pair(op, kids[0], kids[1])) return r;
  if (op == Op::Div) return std::nullopt;
  for (int side = 0; side < 2; ++side) {
    const Frag &group = kids[static_cast<std::size_t>(side)],
               &other = kids[static_cast<std::size_t>(1 - side)];
    if (root(group).op != op) continue;
    const std::vector<Frag> parts = children(group);
    for (int k = 0; k < 2; ++k)
      if (std::optional<Frag> m = merged_pair(op, parts[static_cast<std::size_t>(k)], other))
        return make(op, {parts[static_cast<std::size_t>(1 - k)], *m}, false);
  }
  return std::nullopt;
}

// x op y (op + or -) with like terms collected: a x + b x = (a + b) x, a x - b x = (a - b) x,
// also where x (y) is a sum whose one term is like y (x): (u + a x) + b x = u + (a + b) x;
// nullopt where no two terms are alike (or both are x itself: x + x stays). Never adds a node.
std::optional<Frag> Rules::like_terms(Op op, const Frag& x, const Frag& y) const {
  const auto my = as_multiple(y);
  // a is like y: the same term, and not both written bare.
  auto alike = [&](const std::optional<std::pair<double, Frag>>& ma) {
    return ma && my && same(ma->second, my->second) && (ma->first != 1 || my->first != 1);
  };
  if (const auto mx = as_multiple(x); alike(mx)) {
    const double k = op == Op::Add ? mx->first + my->first : mx->first - my->first;
    if (!std::isfinite(k)) return std::nullopt;
    return make(Op::Mul, {constant(k), mx->second}, false);
  }
  // One level into a sum or difference on the left: (u +- v) op y.
  const Op inner = root(x).op;
  if (inner != Op::Add && inner != Op::Sub) return std::nullopt;
  const std::vector<Frag> uv = children(x);
  if (alike(as_multiple(uv[0]))) return make(inner, {make(op, {uv[0], y}, false), uv[1]}, false);
  if (alike(as_multiple(uv[1]))) {
    // u + v op y = u + (v op y); u - v op y = u - (v -op y).
    const Op back = inner == Op::Add ? op : (op == Op::Add ? Op::Sub : Op::Add);
    return make(inner, {uv[0], make(back, {uv[1], y}, false)}, false);
  }
  return std::nullopt;
}

// The rules of regroup_constants, for a result whose sign of zero does not matter; nullopt when
// none applies. `kids` are simplified.
std::optional<Frag> Rules::regrouped(Op op, const std::vector<Frag>& kids) const {
  const auto value = [](const Frag& f) { return f[0].value; };
  switch (op) {
    case Op::Mul:
      // c * x: the factor into x's own constant; c * -x = -c * x.
      for (int side = 0; side < 2; ++side) {
        const Frag &c = kids[static_cast<std::size_t>(side)],
                   &x = kids[static_cast<std::size_t>(1 - side)];
        if (!is_const(c) || is_const(x)) continue;
        if (std::optional<Frag> s = scaled(x, value(c))) return s;
        if (root(x).op == Op::Neg) {
          const Frag negated = constant(-value(c));
          return side == 0 ? make(Op::Mul, {negated, operand(x)}, false)
                           : make(Op::Mul, {operand(x), negated}, false);
        }
      }
      return std::nullopt;
    case Op::Div:  // (c1 * x) / c2 = (c1 / c2) * x
      if (is_const(kids[1]) && !is_const(kids[0]) && value(kids[1]) != 0)
        return scaled(kids[0], 1 / value(kids[1]));
      return std::nullopt;
    case Op::Add:
      if (std::optional<Frag> r = like_terms(op, kids[0], kids[1])) return r;
      // (a - b) + b = a, either side.
      for (int side = 0; side < 2; ++side) {
        const Frag &x = kids[static_cast<std::size_t>(side)],
                   &y = kids[static_cast<std::size_t>(1 - side)];
        if (root(x).op == Op::Sub)
          if (std::vector<Frag> ab = children(x); same(ab[1], y)) return ab[0];
      }
      if (is_const(kids[1]) && !is_const(kids[0])) return shifted(kids[0], value(kids[1]));
      if (is_const(kids[0]) && !is_const(kids[1])) return shifted(kids[1], value(kids[0]));
      return std::nullopt;
    case Op::Sub:
      if (std::optional<Frag> r = like_terms(op, kids[0], kids[1])) return r;
      // (a + b) - b = a and (a + b) - a = b.
      if (root(kids[0]).op == Op::Add) {
        std::vector<Frag> ab = children(kids[0]);
        if (same(ab[1], kids[1])) return ab[0];
        if (same(ab[0], kids[1])) return ab[1];
      }
      if (is_const(kids[1]) && !is_const(kids[0])) return shifted(kids[0], -value(kids[1]));
      if (is_const(kids[0]) && !is_const(kids[1])) {
        // c - x = -(x - c); written b - a when x - c is a - b.
        std::optional<Frag> s = shifted(kids[1], -value(kids[0]));
        if (!s) return std::nullopt;
        if (root(*s).op == Op::Sub) {
          std::vector<Frag> ab = children(*s);
          return make(Op::Sub, {ab[1], ab[0]}, false);
        }
        return make(Op::Neg, {*s}, false);
      }
      return std::nullopt;
    case Op::Pow:
      if (root(kids[0]).op == Op::Pow) {
        std::vector<Frag> inner = children(kids[0]);
        return power_of_power(inner[0], inner[1], kids[1]);
      }
      return std::nullopt;
    default: return std::nullopt;
  }
}

}  // namespace

Expression simplify(const Expression& e, const SimplifyOptions& options) {
  const Rules rules(options, e);
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
      // |x|, even powers, copysign's magnitude and select's condition drop a zero's sign;
      // atan2 reads the signs of both its zeros (atan2(+-0, -1) = +-pi, atan2(0, -0) = pi).
      const bool drops = n.op == Op::Abs || (n.op == Op::IPow && n.index % 2 == 0) ||
                         (n.op == Op::CopySign && k == 0) || (n.op == Op::Select && k == 0);
      signed_zero[kids_at[k]] =
          (n.op == Op::CopySign && k == 1) || n.op == Op::Atan2 || (signed_zero[i] && !drops);
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
    stack.push_back(rules.make(n.op, kids, signed_zero[i] != 0));
  }
  out.nodes = std::move(stack.back());
  out.update_lengths();
  return out;
}

}  // namespace shaderfit
