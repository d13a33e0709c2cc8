#include "shaderfit/cost/cost_model.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <tuple>
#include <vector>

namespace shaderfit {

namespace {

// An operand of a DAG node: a node id and whether it is negated (negation is free).
struct Ref {
  int id = -1;
  bool neg = false;
};

struct DagNode {
  Op op = Op::Const;  // Const, Var, Param, Add, Mul, Rcp, Min, Max, or a unary MUFU-like op
  Ref a, b;
  double value = 0.0;  // Const
  int index = 0;       // Var, Param
};

// Lowers an expression to a DAG with equal subexpressions shared (value numbering), constants
// folded, negation moved into operand flags, and every operator rewritten into the instruction
// set the model counts: Add (also subtract), Mul, Rcp, Min, Max, and one-instruction unary ops.
class Lowering {
 public:
  Ref constant(double v) {
    const bool neg = std::signbit(v) && v != 0.0;
    const double mag = neg ? -v : v;
    return {intern({Op::Const, {}, {}, mag, 0}), neg};
  }
  Ref leaf(Op op, int index) { return {intern({op, {}, {}, 0.0, index}), false}; }

  Ref add(Ref a, Ref b) {
    if (is_const(a) && is_const(b)) return constant(value(a) + value(b));
    if (is_const(a) && value(a) == 0.0) return b;
    if (is_const(b) && value(b) == 0.0) return a;
    if (std::tie(b.id, b.neg) < std::tie(a.id, a.neg)) std::swap(a, b);
    // -(a) + -(b) = -(a + b): keep the first operand positive.
    const bool flip = a.neg;
    if (flip) {
      a.neg = !a.neg;
      b.neg = !b.neg;
    }
    return {intern({Op::Add, a, b, 0.0, 0}), flip};
  }
  Ref mul(Ref a, Ref b) {
    if (is_const(a) && is_const(b)) return constant(value(a) * value(b));
    if (is_const(b)) std::swap(a, b);
    if (is_const(a) && (value(a) == 1.0 || value(a) == -1.0)) {  // 1 / b is just rcp(b)
      return {b.id, b.neg != (value(a) < 0)};
    }
    const bool neg = a.neg != b.neg;
    a.neg = b.neg = false;
    if (b.id < a.id) std::swap(a, b);
    return {intern({Op::Mul, a, b, 0.0, 0}), neg};
  }
  Ref rcp(Ref a) {
    if (is_const(a)) return constant(1.0 / value(a));
    return {intern({Op::Rcp, {a.id, false}, {}, 0.0, 0}), a.neg};
  }
  Ref unary(Op op, Ref a) {
    if (is_const(a)) return constant(apply_unary(op, value(a)));
    bool out_neg = false;
    if (a.neg) {
      if (op == Op::Sin) {
        a.neg = false;
        out_neg = true;  // odd
      } else if (op == Op::Cos || op == Op::Abs) {
        a.neg = false;  // even
      }
    }
    return {intern({op, a, {}, 0.0, 0}), out_neg};
  }
  Ref minmax(Op op, Ref a, Ref b) {
    if (is_const(a) && is_const(b)) return constant(apply_binary(op, value(a), value(b)));
    if (std::tie(b.id, b.neg) < std::tie(a.id, a.neg)) std::swap(a, b);
    return {intern({op, a, b, 0.0, 0}), false};
  }
  // x^k as the squaring chain of apply_ipow, so x^2, x^4 and x^5 share their intermediates.
  Ref ipow(Ref x, int k) {
    if (is_const(x)) return constant(apply_ipow(value(x), k));
    const bool inverse = k < 0;
    unsigned n = static_cast<unsigned>(inverse ? -k : k);
    Ref result{};
    Ref base = x;
    bool first = true;
    while (n != 0) {
      if (n & 1u) {
        result = first ? base : mul(result, base);
        first = false;
      }
      n >>= 1u;
      if (n != 0) base = mul(base, base);
    }
    return inverse ? rcp(result) : result;
  }

  [[nodiscard]] const std::vector<DagNode>& nodes() const { return nodes_; }

 private:
  [[nodiscard]] bool is_const(Ref r) const {
    return nodes_[static_cast<std::size_t>(r.id)].op == Op::Const;
  }
  [[nodiscard]] double value(Ref r) const {
    const double v = nodes_[static_cast<std::size_t>(r.id)].value;
    return r.neg ? -v : v;
  }
  int intern(const DagNode& n) {
    const auto key = std::make_tuple(static_cast<int>(n.op), n.a.id * 2 + (n.a.neg ? 1 : 0),
                                     n.b.id * 2 + (n.b.neg ? 1 : 0), n.index,
                                     std::bit_cast<std::uint64_t>(n.value));
    auto [it, inserted] = ids_.try_emplace(key, static_cast<int>(nodes_.size()));
    if (inserted) nodes_.push_back(n);
    return it->second;
  }

  std::vector<DagNode> nodes_;
  std::map<std::tuple<int, int, int, int, std::uint64_t>, int> ids_;
};

Ref lower(const Expression& e, Lowering& low) {
  std::vector<Ref> stack;
  stack.reserve(e.nodes.size());
  constexpr double kLog2E = 1.4426950408889634;
  constexpr double kLn2 = 0.6931471805599453;
  for (const Node& n : e.nodes) {
    const int a = arity(n.op);
    Ref args[3];
    for (int k = a - 1; k >= 0; --k) {
      args[k] = stack.back();
      stack.pop_back();
    }
    Ref r;
    switch (n.op) {
      case Op::Const: r = low.constant(n.value); break;
      case Op::Var:
      case Op::Param: r = low.leaf(n.op, n.index); break;
      case Op::Add: r = low.add(args[0], args[1]); break;
      case Op::Sub: r = low.add(args[0], {args[1].id, !args[1].neg}); break;
      case Op::Mul: r = low.mul(args[0], args[1]); break;
      case Op::Div: r = low.mul(args[0], low.rcp(args[1])); break;
      case Op::Min:
      case Op::Max: r = low.minmax(n.op, args[0], args[1]); break;
      case Op::Pow: r = low.unary(Op::Exp2, low.mul(args[1], low.unary(Op::Log2, args[0]))); break;
      case Op::Neg: r = {args[0].id, !args[0].neg}; break;
      case Op::IPow: r = low.ipow(args[0], n.index); break;
      case Op::Rcp: r = low.rcp(args[0]); break;
      case Op::Exp: r = low.unary(Op::Exp2, low.mul(args[0], low.constant(kLog2E))); break;
      case Op::Log: r = low.mul(low.unary(Op::Log2, args[0]), low.constant(kLn2)); break;
      case Op::Fma: r = low.add(low.mul(args[0], args[1]), args[2]); break;
      default: r = low.unary(n.op, args[0]); break;  // sqrt rsqrt exp2 log2 abs saturate sin cos
    }
    stack.push_back(r);
  }
  return stack.back();
}

double count_instructions(const Expression& e) {
  if (e.nodes.empty()) return 0.0;
  Lowering low;
  const Ref root = lower(e, low);
  const auto& nodes = low.nodes();
  const std::size_t count = nodes.size();

  // Reachable nodes and their number of uses; nodes are in topological order (children first).
  std::vector<int> uses(count, 0);
  std::vector<bool> live(count, false);
  live[static_cast<std::size_t>(root.id)] = true;
  uses[static_cast<std::size_t>(root.id)] = 1;  // the result is a use that never fuses
  for (std::size_t i = count; i-- > 0;) {
    if (!live[i]) continue;
    for (const Ref& c : {nodes[i].a, nodes[i].b}) {
      if (c.id < 0) continue;
      live[static_cast<std::size_t>(c.id)] = true;
      ++uses[static_cast<std::size_t>(c.id)];
    }
  }

  // Each add absorbs one product operand (an FMA), the one with the fewest other uses.
  std::vector<int> fused(count, 0);
  for (std::size_t i = 0; i < count; ++i) {
    if (!live[i] || nodes[i].op != Op::Add) continue;
    int best = -1;
    for (const Ref& c : {nodes[i].a, nodes[i].b}) {
      if (nodes[static_cast<std::size_t>(c.id)].op != Op::Mul) continue;
      if (best < 0 || uses[static_cast<std::size_t>(c.id)] < uses[static_cast<std::size_t>(best)])
        best = c.id;
    }
    if (best >= 0) ++fused[static_cast<std::size_t>(best)];
  }

  double total = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!live[i] || is_leaf(nodes[i].op)) continue;
    if (nodes[i].op == Op::Mul && fused[i] == uses[i]) continue;  // every use became an FMA
    total += 1.0;
  }
  return total;
}

}  // namespace

double expression_cost(const Expression& e, CostTarget target) {
  switch (target) {
    case CostTarget::Nodes: return static_cast<double>(e.nodes.size());
    case CostTarget::Instructions: return count_instructions(e);
  }
  return 0.0;
}

std::optional<CostTarget> cost_target_from_name(std::string_view name) {
  if (name == "nodes") return CostTarget::Nodes;
  if (name == "instructions") return CostTarget::Instructions;
  return std::nullopt;
}

std::string_view cost_target_name(CostTarget target) {
  return target == CostTarget::Nodes ? "nodes" : "instructions";
}

}  // namespace shaderfit
