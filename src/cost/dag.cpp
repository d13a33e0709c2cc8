#include "cost/dag.hpp"

#include <bit>
#include <cmath>
#include <unordered_map>
#include <utility>

#include "cost/float_text.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/precision.hpp"

namespace shaderfit::cost_detail {

namespace {

// The structure of a node, for hash-consing: equal keys are the same value.
struct Key {
  std::uint8_t op;
  bool log_scale;
  int a, b, c;  // operand id * 2 + neg, or -1
  int index;
  std::uint32_t bits;  // Const: float bits
  std::uint64_t exact_bits;  // Const: the stated value's bits

  friend bool operator==(const Key&, const Key&) = default;
};

struct KeyHash {
  std::size_t operator()(const Key& k) const noexcept {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL * (k.op + 1u) ^ (k.log_scale ? 0x51ULL : 0);
    for (std::uint64_t v :
         {static_cast<std::uint64_t>(k.a + 2), static_cast<std::uint64_t>(k.b + 2),
          static_cast<std::uint64_t>(k.c + 2), static_cast<std::uint64_t>(k.index + 1000),
          std::uint64_t{k.bits}, k.exact_bits}) {
      h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    }
    return static_cast<std::size_t>(h);
  }
};

int code(DagRef r) { return r.id < 0 ? -1 : r.id * 2 + (r.neg ? 1 : 0); }
DagRef negate(DagRef r) { return {r.id, !r.neg}; }
bool ref_less(DagRef x, DagRef y) { return code(x) < code(y); }

class Builder {
 public:
  explicit Builder(Dag& dag) : dag_(dag), half_(dag.half), fast_(dag.fast_math) {}

  [[nodiscard]] bool half() const { return half_; }
  // log(x) = log2(x) * ln2, the product marked log_scale; with fast math log(exp(x)) = x, and
  // a log2 that folds (log2(exp2(x)) = x) leaves a plain product.
  DagRef log(DagRef a) {
    if (fast_ && !a.neg && dag_.node(a.id).op == Op::Exp) return dag_.node(a.id).a;
    // (LLVM folds log2(exp2(x)) but not log(exp2(x)): the log2 here does not fold.)
    const DagRef l = unary(Op::Log2, a, false);
    return mul(l, constant(kLn2), !l.neg && dag_.node(l.id).op == Op::Log2);
  }

  // A literal of the expression: its float32 value, or in a half DAG its binary16 value.
  DagRef literal(double v) {
    return constant(static_cast<float>(half_ ? round_to_half(v) : v), v);
  }

  DagRef constant(float v) { return constant(v, v); }
  DagRef constant(float v, double stated) {
    const bool neg = std::signbit(v);
    DagNode n;
    n.op = Op::Const;
    n.value = neg ? -v : v;
    n.exact = neg ? -stated : stated;
    return {intern(n), neg};
  }
  DagRef leaf(Op op, int index) {
    DagNode n;
    n.op = op;
    n.index = index;
    return {intern(n), false};
  }

  DagRef add(DagRef a, DagRef b) {
    if (is_const(a) && is_const(b))
      return fold([&](auto t) { return as(t, value(a)) + as(t, value(b)); });
    if (is_minus_zero(b)) return a;  // x + -0 == x for every x
    if (is_minus_zero(a)) return b;
    if (fast_) {  // x + 0 = x, x - x = 0
      if (is_zero(b)) return a;
      if (is_zero(a)) return b;
      if (a.id == b.id && a.neg != b.neg) return constant(0.0f);
    }
    // Keep the first operand positive: -a + b = b - a, and -a - b = -(a + b).
    if (a.neg) std::swap(a, b);
    const bool flip = a.neg;
    if (flip) {
      a = negate(a);
      b = negate(b);
    }
    return {binary(Op::Add, a, b), flip};
  }

  DagRef mul(DagRef a, DagRef b, bool log_scale = false) {
    if (is_const(a) && is_const(b))
      return fold([&](auto t) { return as(t, value(a)) * as(t, value(b)); });
    // x * 1 and x * -1 are x and -x exactly.
    if (is_const(a) && !log_scale && std::fabs(exact(a)) == 1.0)
      return {b.id, b.neg != (value(a) < 0)};
    if (is_const(b) && !log_scale && std::fabs(exact(b)) == 1.0)
      return {a.id, a.neg != (value(b) < 0)};
    if (fast_) {  // x * 0 = 0, x * (1 / x) = 1
      if (is_zero(a) || is_zero(b)) return constant(0.0f);
      for (const auto& [x, r] : {std::pair{a, b}, std::pair{b, a}}) {
        const DagNode& rn = dag_.node(r.id);
        if (rn.op == Op::Rcp && rn.a.id == x.id)
          return constant((x.neg != r.neg) != rn.a.neg ? -1.0f : 1.0f);
      }
    }
    const bool neg = a.neg != b.neg;
    a.neg = b.neg = false;
    DagNode n;
    n.op = Op::Mul;
    n.a = a;
    n.b = b;
    n.log_scale = log_scale;
    return {intern(n), neg};
  }

  // `inverse_folds`: with fast math, f(g(x)) = x for a g that inverts f (below).
  DagRef unary(Op op, DagRef a, bool inverse_folds = true) {
    if (is_const(a)) {
      return fold([&](auto t) {
        const auto x = as(t, value(a));
        return op == Op::Rcp ? as(t, 1.0f) / x : apply_unary(op, x);
      });
    }
    if (!half_ && op == Op::Rcp && !a.neg && dag_.node(a.id).op == Op::Sqrt) {
      return unary(Op::Rsqrt, dag_.node(a.id).a);  // 1 / sqrt(x) is rsqrt(x), as nvcc makes it
    }
    if (fast_ && inverse_folds) {  // 1 / (1 / x) = x, 1 / rsqrt(x) = sqrt(x), log2(exp2(x)) = x
      const DagNode& in = dag_.node(a.id);
      if (op == Op::Rcp && in.op == Op::Rcp) return {in.a.id, in.a.neg != a.neg};
      if (op == Op::Rcp && in.op == Op::Rsqrt && !a.neg) return unary(Op::Sqrt, in.a);
      if (op == Op::Log2 && in.op == Op::Exp2 && !a.neg) return in.a;
    }
    bool out_neg = false;
    if (op_info(op).parity == OpParity::Odd) {  // the sign moves to the result
      out_neg = a.neg;
      a.neg = false;
    } else if (op_info(op).parity == OpParity::Even) {  // the sign vanishes
      a.neg = false;
    }
    return {binary(op, a, {}), out_neg};
  }

  DagRef minmax(Op op, DagRef a, DagRef b) {
    if (is_const(a) && is_const(b))
      return fold([&](auto t) { return apply_binary(op, as(t, value(a)), as(t, value(b))); });
    // min(a, a) = a; max(max(a, b), a) = max(a, b): folds that LLVM makes too.
    if (a == b) return a;
    for (const auto& [inner, other] : {std::pair{a, b}, std::pair{b, a}}) {
      const DagNode& n = dag_.node(inner.id);
      if (!inner.neg && n.op == op && (n.a == other || n.b == other)) return inner;
    }
    // min(K1, max(K2, x)) = K1 when K1 <= K2, and max(K1, min(K2, x)) = K1 when K1 >= K2.
    for (const auto& [k, inner] : {std::pair{a, b}, std::pair{b, a}}) {
      const DagNode& n = dag_.node(inner.id);
      if (!is_const(k) || inner.neg || (n.op != Op::Min && n.op != Op::Max) || n.op == op) continue;
      for (const DagRef& k2 : {n.a, n.b}) {
        if (!is_const(k2)) continue;
        if ((op == Op::Min && exact(k) <= exact(k2)) || (op == Op::Max && exact(k) >= exact(k2)))
          return k;
      }
    }
    bool flip = false;
    if (a.neg && b.neg) {  // min(-a, -b) = -max(a, b)
      a = negate(a);
      b = negate(b);
      op = op == Op::Min ? Op::Max : Op::Min;
      flip = true;
    }
    return {binary(op, a, b), flip};
  }

  // sign(-x) = -sign(x); values of sign, copysign and select fold in float32 like the others.
  DagRef sign(DagRef a) {
    if (is_const(a)) return constant(apply_unary(Op::Sign, value(a)));
    return {binary(Op::Sign, {a.id, false}, {}), a.neg};
  }

  // atan2(-a, b) = -atan2(a, b): a's sign moves to the result; b keeps its sign.
  DagRef atan2(DagRef a, DagRef b) {
    if (is_const(a) && is_const(b))
      return fold(
          [&](auto t) { return apply_binary(Op::Atan2, as(t, value(a)), as(t, value(b))); });
    return {binary(Op::Atan2, {a.id, false}, b), a.neg};
  }

  // copysign(a, b) drops a's sign, copysign(a, -b) = -copysign(a, b), copysign(a, K) = +-|a|.
  DagRef copysign(DagRef a, DagRef b) {
    if (is_const(a) && is_const(b)) return constant(apply_binary(Op::CopySign, value(a), value(b)));
    if (is_const(b)) {  // copysign(a, K) = |a| or -|a|
      const DagRef r = unary(Op::Abs, a);
      return std::signbit(value(b)) ? negate(r) : r;
    }
    return {binary(Op::CopySign, {a.id, false}, {b.id, false}), b.neg};
  }

  // select(a, b, c) keeps a's sign on the reference (a comparison takes it for free); a literal
  // condition picks its branch; select(a, b, b) = b; select(a, -b, -c) = -select(a, b, c).
  DagRef select(DagRef a, DagRef b, DagRef c) {
    if (is_const(a)) return apply_select(value(a), 1.0f, 0.0f) != 0.0f ? b : c;
    if (b == c) return b;
    const bool flip = b.neg && c.neg;
    if (flip) {
      b = negate(b);
      c = negate(c);
    }
    DagNode n;
    n.op = Op::Select;
    n.a = a;
    n.b = b;
    n.c = c;
    return {intern(n), flip};
  }

  // x^k by the squaring chain of apply_ipow, so x^2, x^4, x^5 share their intermediates (in a half
  // DAG a literal x folds along the same chain, each product rounded).
  DagRef ipow(DagRef x, int k) {
    if (is_const(x) && !half_) return constant(apply_ipow(value(x), k));
    unsigned n = static_cast<unsigned>(k < 0 ? -k : k);
    DagRef result{}, base = x;
    bool first = true;
    while (n != 0) {
      if (n & 1u) {
        result = first ? base : mul(result, base);
        first = false;
      }
      n >>= 1u;
      if (n != 0) base = mul(base, base);
    }
    return k < 0 ? unary(Op::Rcp, result) : result;
  }

  // Half DAG: a / b rounded once. 1 / b is Rcp; a / K is a * (1/K) where 1/K is a power of two
  // that binary16 holds (the same value, rounded once); otherwise one Div node.
  DagRef div(DagRef a, DagRef b) {
    if (is_const(a) && is_const(b))
      return fold([&](auto t) { return as(t, value(a)) / as(t, value(b)); });
    if (is_const(a) && std::fabs(exact(a)) == 1.0) {
      const DagRef r = unary(Op::Rcp, b);
      return value(a) < 0 ? negate(r) : r;
    }
    if (is_const(b)) {
      int exponent = 0;
      const double inverse = 1.0 / static_cast<double>(value(b));
      if (std::fabs(std::frexp(inverse, &exponent)) == 0.5 && round_to_half(inverse) == inverse)
        return mul(a, constant(static_cast<float>(inverse)));
    }
    const bool neg = a.neg != b.neg;
    a.neg = b.neg = false;
    return {binary(Op::Div, a, b), neg};
  }

  // Half DAG: fma(a, b, c) rounded once, with a and b positive: fma(-a, b, c) = -fma(a, b, -c).
  // fma(+-1, b, c) is the sum and fma(a, b, +-0) the product: the same values, rounded once.
  DagRef fma(DagRef a, DagRef b, DagRef c) {
    if (is_const(a) && is_const(b) && is_const(c)) {
      return fold([&](auto t) {
        using T = decltype(t);
        return static_cast<T>(std::fma(as(t, value(a)), as(t, value(b)), as(t, value(c))));
      });
    }
    for (const auto& [k, other] : {std::pair{a, b}, std::pair{b, a}})
      if (is_const(k) && std::fabs(exact(k)) == 1.0)
        return add(value(k) < 0 ? negate(other) : other, c);
    if (is_const(c) && exact(c) == 0.0) return mul(a, b);
    const bool neg = a.neg != b.neg;
    a.neg = b.neg = false;
    if (neg) c = negate(c);
    DagNode n;
    n.op = Op::Fma;
    n.a = a;
    n.b = b;
    n.c = c;
    return {intern(n), neg};
  }

 private:
  [[nodiscard]] bool is_const(DagRef r) const { return dag_.is_const(r.id); }
  [[nodiscard]] float value(DagRef r) const {
    const float v = dag_.node(r.id).value;
    return r.neg ? -v : v;
  }
  // A literal's value in the folding type (float, or double in a half DAG).
  template <class T>
  static T as(T /*type*/, float v) {
    return static_cast<T>(v);
  }
  // A fold of literals: f computed in float32, or in a half DAG in double and rounded to
  // binary16 once, as evaluate_half (eval/evaluate_in.hpp) computes each operator.
  template <class F>
  DagRef fold(F f) {
    if (half_) return constant(static_cast<float>(round_to_half(f(0.0))));
    return constant(f(0.0f));
  }
  // The stated value, signed.
  [[nodiscard]] double exact(DagRef r) const {
    const double v = dag_.node(r.id).exact;
    return r.neg ? -v : v;
  }
  [[nodiscard]] bool is_zero(DagRef r) const { return is_const(r) && exact(r) == 0.0; }
  [[nodiscard]] bool is_minus_zero(DagRef r) const {
    return is_const(r) && exact(r) == 0.0 && std::signbit(exact(r));
  }
  int binary(Op op, DagRef a, DagRef b) {
    DagNode n;
    n.op = op;
    n.a = a;
    n.b = b;
    return intern(n);
  }
  // The node keeps the operand order it was first written in; the key of a commutative
  // operator sorts them, so b + a finds a + b.
  int intern(const DagNode& n) {
    const bool sort = op_info(n.op).commutative && ref_less(n.b, n.a);
    const Key key{static_cast<std::uint8_t>(n.op),
                  n.log_scale,
                  code(sort ? n.b : n.a),
                  code(sort ? n.a : n.b),
                  code(n.c),
                  n.index,
                  std::bit_cast<std::uint32_t>(n.value),
                  std::bit_cast<std::uint64_t>(n.exact)};
    auto [it, inserted] = ids_.try_emplace(key, static_cast<int>(dag_.nodes.size()));
    if (inserted) dag_.nodes.push_back(n);
    return it->second;
  }

  Dag& dag_;
  bool half_, fast_;
  std::unordered_map<Key, int, KeyHash> ids_;
};

DagRef lower_node(const Node& n, const DagRef* args, Builder& b) {
  switch (n.op) {
    case Op::Const: return b.literal(n.value);
    case Op::Var:
    case Op::Param: return b.leaf(n.op, n.index);
    case Op::Add: return b.add(args[0], args[1]);
    case Op::Sub: return b.add(args[0], negate(args[1]));
    case Op::Mul: return b.mul(args[0], args[1]);
    case Op::Div:
      return b.half() ? b.div(args[0], args[1]) : b.mul(args[0], b.unary(Op::Rcp, args[1]));
    case Op::Min:
    case Op::Max: return b.minmax(n.op, args[0], args[1]);
    case Op::Pow: return b.unary(Op::Exp2, b.mul(args[1], b.unary(Op::Log2, args[0])));
    case Op::Neg: return negate(args[0]);
    case Op::IPow: return b.ipow(args[0], n.index);
    case Op::Log:
      if (b.half()) return b.unary(Op::Log, args[0]);
      return b.log(args[0]);
    case Op::Fma:
      if (b.half()) return b.fma(args[0], args[1], args[2]);
      return b.add(b.mul(args[0], args[1]), args[2]);
    case Op::Sign: return b.sign(args[0]);
    case Op::CopySign: return b.copysign(args[0], args[1]);
    case Op::Select: return b.select(args[0], args[1], args[2]);
    case Op::Atan2: return b.atan2(args[0], args[1]);
    default:
      if (arity(n.op) == 1) return b.unary(n.op, args[0]);  // the other unary functions
      break;
  }
  throw Error("malformed expression: operator '" + std::string(op_info(n.op).name) +
              "' cannot be costed");
}

void count_uses(Dag& dag) {
  dag.uses.assign(dag.nodes.size(), 0);
  for (const DagRef& r : dag.roots) ++dag.uses[static_cast<std::size_t>(r.id)];
  for (std::size_t i = dag.nodes.size(); i-- > 0;) {
    if (dag.uses[i] == 0) continue;
    for (const DagRef& c : {dag.nodes[i].a, dag.nodes[i].b, dag.nodes[i].c})
      if (c.id >= 0) ++dag.uses[static_cast<std::size_t>(c.id)];
  }
}

}  // namespace

Dag lower_expression(const Expression& e, bool half, bool fast_math) {
  return lower_expressions({&e, 1}, half, fast_math);
}

Dag lower_expressions(std::span<const Expression> values, bool half, bool fast_math) {
  if (values.empty()) throw Error("empty expression");
  Dag dag;
  dag.half = half;
  dag.fast_math = fast_math && !half;
  dag.variables = values.front().variables;
  dag.parameters = values.front().parameters;
  Builder builder(dag);
  std::vector<DagRef> stack;
  for (const Expression& e : values) {
    if (e.nodes.empty()) throw Error("empty expression");
    stack.clear();
    stack.reserve(e.nodes.size());
    for (const Node& n : e.nodes) {
      const int a = arity(n.op);
      if (static_cast<int>(stack.size()) < a)
        throw Error("malformed expression: an operator lacks operands");
      if ((n.op == Op::Var &&
           (n.index < 0 || static_cast<std::size_t>(n.index) >= dag.variables.size())) ||
          (n.op == Op::Param &&
           (n.index < 0 || static_cast<std::size_t>(n.index) >= dag.parameters.size()))) {
        throw Error("malformed expression: a variable or parameter index is out of range");
      }
      DagRef args[3];
      for (int k = a - 1; k >= 0; --k) {
        args[k] = stack.back();
        stack.pop_back();
      }
      stack.push_back(lower_node(n, args, builder));
    }
    if (stack.size() != 1) throw Error("malformed expression: not a single tree");
    dag.roots.push_back(stack.back());
  }
  count_uses(dag);
  return dag;
}

namespace {

void infix(const Dag& dag, DagRef r, std::string& out, std::size_t max_chars, int parent_level) {
  if (out.size() > max_chars) return;
  const DagNode& n = dag.node(r.id);
  auto text = [&](const std::string& s) { out += s; };
  if (n.op == Op::Const) {
    text(float_text(r.neg ? -n.value : n.value));
    return;
  }
  const int level = n.log_scale ? 4 : precedence(n.op);  // a log scale prints as log(x)
  const bool neg_wrap = r.neg;
  const bool paren = neg_wrap ? parent_level >= 2 && level < 3 : level < parent_level;
  if (neg_wrap) text("-");
  if (paren || (neg_wrap && level < 3)) text("(");
  switch (n.op) {
    case Op::Var: text(dag.variables[static_cast<std::size_t>(n.index)]); break;
    case Op::Param: text(dag.parameters[static_cast<std::size_t>(n.index)]); break;
    case Op::Add:
      infix(dag, n.a, out, max_chars, 1);
      if (n.b.neg) {
        text(" - ");
        infix(dag, {n.b.id, false}, out, max_chars, 2);
      } else {
        text(" + ");
        infix(dag, n.b, out, max_chars, 2);
      }
      break;
    case Op::Mul:
      if (n.log_scale) {
        text("log(");
        infix(dag, dag.node(n.a.id).a, out, max_chars, 0);
        text(")");
        break;
      }
      infix(dag, n.a, out, max_chars, 2);
      text(" * ");
      infix(dag, n.b, out, max_chars, 3);
      break;
    case Op::Div:
      infix(dag, n.a, out, max_chars, 2);
      text(" / ");
      infix(dag, n.b, out, max_chars, 3);
      break;
    default:
      text(n.op == Op::Rcp ? "rcp(" : std::string(op_info(n.op).name) + "(");
      infix(dag, n.a, out, max_chars, 0);
      if (n.b.id >= 0) {
        text(n.op == Op::Select ? " >= 0, " : ", ");
        infix(dag, n.b, out, max_chars, 0);
      }
      if (n.c.id >= 0) {
        text(", ");
        infix(dag, n.c, out, max_chars, 0);
      }
      text(")");
      break;
  }
  if (paren || (neg_wrap && level < 3)) text(")");
}

}  // namespace

std::string dag_infix(const Dag& dag, DagRef r, std::size_t max_chars) {
  std::string out;
  infix(dag, r, out, max_chars, 0);
  if (out.size() > max_chars) out = out.substr(0, max_chars - 3) + "...";
  return out;
}

}  // namespace shaderfit::cost_detail
