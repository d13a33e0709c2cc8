#include "shaderfit/reference/program_formula.hpp"

#include <array>
#include <cctype>
#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit::reference {

namespace {

// The operator that means what `op` means and has its name ("+", "neg", "min", "pow", ...), or
// Op::Count_.
Op same_operator(ProgramOp op) {
  for (int i = 0; i < kOpCount; ++i) {
    const Op o = static_cast<Op>(i);
    if (!is_leaf(o) && op_info(o).name == program_op_name(op) && arity(o) == program_op_arity(op))
      return o;
  }
  return Op::Count_;
}

// The C functions the operators lack but write exactly in real arithmetic, as formulas of their
// operands x and y.
constexpr std::pair<ProgramOp, std::string_view> kIdentities[] = {
    {ProgramOp::Tan, "sin(x) / cos(x)"},
    {ProgramOp::Cbrt, "copysign(pow(abs(x), 0.333333333333333333), x)"},
    {ProgramOp::Log10, "log2(x) * 0.301029995663981195"},
    {ProgramOp::Log1p, "log(1 + x)"},
    {ProgramOp::Expm1, "exp(x) - 1"},
    {ProgramOp::Sinh, "(exp(x) - exp(-x)) * 0.5"},
    {ProgramOp::Cosh, "(exp(x) + exp(-x)) * 0.5"},
    {ProgramOp::Asinh, "log(x + sqrt(x^2 + 1))"},
    {ProgramOp::Acosh, "log(x + sqrt(x^2 - 1))"},
    {ProgramOp::Atanh, "log((1 + x) / (1 - x)) * 0.5"},
    {ProgramOp::Erfc, "1 - erf(x)"},
    {ProgramOp::Hypot, "sqrt(x^2 + y^2)"},
};

// Writes register r's value as postfix nodes, operands first; false (with `why`) where the
// operators cannot write it.
class FormulaWriter {
 public:
  FormulaWriter(const Program& p, std::vector<int> var_of_input, std::size_t max_nodes)
      : p_(p), var_of_input_(std::move(var_of_input)), max_nodes_(max_nodes) {}

  bool write(std::uint32_t r) {
    if (nodes.size() > max_nodes_) {
      why = "written out as a formula it has more than " + std::to_string(max_nodes_) + " nodes";
      return false;
    }
    const Instruction& in = p_.code[r];
    const auto operand = [&](int k) { return in.operands[static_cast<std::size_t>(k)]; };
    const auto op = [&](Op o, int n) {
      for (int k = 0; k < n; ++k)
        if (!write(operand(k))) return false;
      nodes.push_back(Node::op_node(o));
      return true;
    };
    switch (in.op) {
      case ProgramOp::Const: nodes.push_back(Node::constant(in.value)); return true;
      case ProgramOp::Input: {
        const int v = var_of_input_[static_cast<std::size_t>(in.index)];
        if (v < 0) {
          why = "its input '" + p_.inputs[static_cast<std::size_t>(in.index)] +
                "' is not a variable of the formula";
          return false;
        }
        nodes.push_back(Node::variable(v));
        return true;
      }
      case ProgramOp::Min:
        if (const auto x = clamped(in)) {  // clamp(x, 0, 1), saturate(x)
          if (!write(*x)) return false;
          nodes.push_back(Node::op_node(Op::Saturate));
          return true;
        }
        break;
      case ProgramOp::Operator:
        return op(static_cast<Op>(in.index), arity(static_cast<Op>(in.index)));
      case ProgramOp::IPow: return power(operand(0), in.index);
      case ProgramOp::Select: return select(in);
      case ProgramOp::Builtin: why = "it calls a built-in reference"; return false;
      default:
        if (const std::optional<bool> done = identity(in)) return *done;
        break;
    }
    // The arithmetic, min, max, pow and sign: the operator of the same name and meaning.
    if (const Op same = same_operator(in.op); same != Op::Count_) return op(same, arity(same));
    const std::string name(program_op_name(in.op));
    // Shader code truncates by conversion too: int(x), (int)x, an int variable given a float.
    // And the built-ins written with floor: fract, mod and fmod.
    const std::string also = in.op == ProgramOp::Trunc   ? " (or converts a float to int)"
                             : in.op == ProgramOp::Floor ? " (or fract, frac or mod)"
                                                         : "";
    why = std::isalpha(static_cast<unsigned char>(name[0]))
              ? "it calls " + name + also + ", which the search's operators cannot write"
              : "it reads '" + name + "' as a number, which the search's operators cannot write";
    return false;
  }

  std::vector<Node> nodes;
  std::string why;

 private:
  // The C functions the operators lack but write exactly in real arithmetic, in them; nullopt
  // for any other op, else whether the operands could be written.
  std::optional<bool> identity(const Instruction& in) {
    for (const auto& [op, text] : kIdentities)
      if (op == in.op)
        return formula(text, [&] { return write(in.operands[0]); },
                       [&] { return write(in.operands[1]); });
    return std::nullopt;
  }

  // Writes `text`, a formula of x and y, with x and y written by the writers given.
  using Writer = std::function<bool()>;
  bool formula(std::string_view text, const Writer& x, const Writer& y = {}) {
    ParseOptions o;
    o.variables = {"x", "y"};
    const Expression e = parse_formula(std::string(text), o);
    for (Node n : e.nodes) {
      if (n.op == Op::Var) {
        if (!(n.index == 0 ? x() : y())) return false;
        continue;
      }
      n.length = 0;
      nodes.push_back(n);
    }
    return true;
  }

  // x^k: the operators' integer power within +-16, pow beyond it.
  bool power(std::uint32_t x, int k) {
    if (k == 0) {
      nodes.push_back(Node::constant(1.0));
      return true;
    }
    if (!write(x)) return false;
    if (k == 1) return true;
    if (k >= kMinIntegerPower && k <= kMaxIntegerPower) {
      nodes.push_back(Node::ipow(k));
    } else {
      nodes.push_back(Node::constant(k));
      nodes.push_back(Node::op_node(Op::Pow));
    }
    return true;
  }

  // x where `in` is min(max(x, 0), 1) (clamp and saturate), else nullopt.
  std::optional<std::uint32_t> clamped(const Instruction& in) const {
    const auto constant = [&](std::uint32_t r, double v) {
      return p_.code[r].op == ProgramOp::Const && p_.code[r].value == v;
    };
    for (int k : {0, 1}) {
      const std::uint32_t inner = in.operands[static_cast<std::size_t>(k)];
      const Instruction& m = p_.code[inner];
      if (!constant(in.operands[static_cast<std::size_t>(1 - k)], 1.0) || m.op != ProgramOp::Max)
        continue;
      for (int j : {0, 1})
        if (constant(m.operands[static_cast<std::size_t>(1 - j)], 0.0))
          return m.operands[static_cast<std::size_t>(j)];
    }
    return std::nullopt;
  }

  bool select(const Instruction& in) {
    return choose(
        in.operands[0], [&] { return write(in.operands[1]); },
        [&] { return write(in.operands[2]); });
  }

  // Writes `truth` ? a : b, where `truth` holds a truth value (ProgramLogic's: nonzero is true)
  // made of comparisons, constants, logic and selects of truth values (an early `return` leaves
  // such a select). A comparison of x and y is a select(s, ., .) (s >= 0 picks the first):
  // x >= y is x - y >= 0, x <= y is y - x >= 0, x < y and x > y their negations. The others
  // are written as selects of these, each branch written where it is taken.
  bool choose(std::uint32_t truth, const Writer& a, const Writer& b) {
    const Instruction& c = p_.code[truth];
    const auto operand = [&](int k) { return c.operands[static_cast<std::size_t>(k)]; };
    bool swap = false, flip = false;
    switch (c.op) {
      case ProgramOp::Const: return c.value < 0 || c.value > 0 ? a() : b();
      case ProgramOp::Not: return choose(operand(0), b, a);
      case ProgramOp::And:
        return choose(
            operand(0), [&] { return choose(operand(1), a, b); }, b);
      case ProgramOp::Or: return choose(operand(0), a, [&] { return choose(operand(1), a, b); });
      case ProgramOp::Select:
        return choose(
            operand(0), [&] { return choose(operand(1), a, b); },
            [&] { return choose(operand(2), a, b); });
      case ProgramOp::GreaterEqual: break;
      case ProgramOp::LessEqual: flip = true; break;
      case ProgramOp::Less: swap = true; break;
      case ProgramOp::Greater: flip = swap = true; break;
      case ProgramOp::Equal:
      case ProgramOp::NotEqual: {
        // x == y is -|x - y| >= 0 (NaN takes the second branch, as x == NaN is false).
        const bool eq = c.op == ProgramOp::Equal;
        if (!formula("-abs(x)", [&] { return difference(operand(0), operand(1)); })) return false;
        if (!(eq ? a() : b()) || !(eq ? b() : a())) return false;
        nodes.push_back(Node::op_node(Op::Select));
        return true;
      }
      default: why = "it branches on a number, not on a comparison"; return false;
    }
    if (!difference(operand(flip ? 1 : 0), operand(flip ? 0 : 1))) return false;
    if (!(swap ? b() : a()) || !(swap ? a() : b())) return false;
    nodes.push_back(Node::op_node(Op::Select));
    return true;
  }

  // Writes x - y (x alone for y = 0, -y for x = 0).
  bool difference(std::uint32_t x, std::uint32_t y) {
    const auto zero = [&](std::uint32_t r) {
      return p_.code[r].op == ProgramOp::Const && p_.code[r].value == 0;
    };
    if (zero(y)) return write(x);
    if (zero(x)) {
      if (!write(y)) return false;
      nodes.push_back(Node::op_node(Op::Neg));
      return true;
    }
    if (!write(x) || !write(y)) return false;
    nodes.push_back(Node::op_node(Op::Sub));
    return true;
  }

  const Program& p_;
  std::vector<int> var_of_input_;
  std::size_t max_nodes_;
};

// e's nodes with each select whose branch is a select on the same condition (as nodes) replaced
// by the branch that one picks there: an early return leaves select(c, select(c, a, u), b), u
// the value not yet returned.
std::vector<Node> without_repeated_conditions(const Expression& e) {
  std::vector<Node> out;
  const auto same = [&](std::size_t i, std::size_t j) {
    if (e.nodes[i].length != e.nodes[j].length) return false;
    for (std::size_t k = 0; k <= e.nodes[i].length; ++k)
      if (!(e.nodes[i - k] == e.nodes[j - k])) return false;
    return true;
  };
  const auto emit = [&](const auto& self, std::size_t i) -> void {
    const Node& n = e.nodes[i];
    std::array<std::size_t, 3> kids{};
    e.child_indices(i, std::span<std::size_t>(kids.data(), n.arity));
    if (n.op == Op::Select)
      for (std::size_t k = 1; k <= 2; ++k)
        while (e.nodes[kids[k]].op == Op::Select) {
          std::array<std::size_t, 3> inner{};
          e.child_indices(kids[k], std::span<std::size_t>(inner.data(), 3));
          if (!same(inner[0], kids[0])) break;
          kids[k] = inner[k];
        }
    for (std::size_t k = 0; k < n.arity; ++k) self(self, kids[k]);
    out.push_back(n);
  };
  emit(emit, e.nodes.size() - 1);
  return out;
}

}  // namespace

ProgramFormula program_formula(const Program& program, std::span<const std::string> variables,
                               std::size_t max_nodes) {
  if (program.outputs.empty()) throw Error("the reference has no outputs", {program.description});
  std::vector<int> var_of_input(program.inputs.size(), -1);
  for (std::size_t i = 0; i < program.inputs.size(); ++i)
    for (std::size_t v = 0; v < variables.size(); ++v)
      if (variables[v] == program.inputs[i]) var_of_input[i] = static_cast<int>(v);
  FormulaWriter w(program, std::move(var_of_input), max_nodes);
  ProgramFormula out;
  if (!w.write(program.outputs.back())) {
    out.why = std::move(w.why);
    return out;
  }
  Expression e;
  e.nodes = std::move(w.nodes);
  e.variables.assign(variables.begin(), variables.end());
  e.update_lengths();
  e.nodes = without_repeated_conditions(e);
  e.update_lengths();
  out.formula = std::move(e);
  return out;
}

}  // namespace shaderfit::reference
