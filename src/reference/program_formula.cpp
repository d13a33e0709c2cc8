#include "shaderfit/reference/program_formula.hpp"

#include <cctype>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "shaderfit/core/error.hpp"

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

// Writes register r's value as postfix nodes, operands first; false (with `why`) where the
// operators cannot write it.
class FormulaWriter {
 public:
  FormulaWriter(const Program& p, std::vector<int> var_of_input)
      : p_(p), var_of_input_(std::move(var_of_input)) {}

  bool write(std::uint32_t r) {
    if (nodes.size() > kMaxProgramFormulaNodes) {
      why = "written out as a formula it has more than " + std::to_string(kMaxProgramFormulaNodes) +
            " nodes";
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
      default: break;
    }
    // The arithmetic, min, max, pow and sign: the operator of the same name and meaning.
    if (const Op same = same_operator(in.op); same != Op::Count_) return op(same, arity(same));
    const std::string name(program_op_name(in.op));
    why = std::isalpha(static_cast<unsigned char>(name[0]))
              ? "it calls " + name + ", which the search's operators cannot write"
              : "it reads '" + name + "' as a number, which the search's operators cannot write";
    return false;
  }

  std::vector<Node> nodes;
  std::string why;

 private:
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
  using Writer = std::function<bool()>;
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
      case ProgramOp::NotEqual:
        why = "it branches on '" + std::string(program_op_name(c.op)) +
              "', which the search's operators cannot write";
        return false;
      default: why = "it branches on a number, not on a comparison"; return false;
    }
    const std::uint32_t x = operand(flip ? 1 : 0), y = operand(flip ? 0 : 1);
    const auto zero = [&](std::uint32_t r) {
      return p_.code[r].op == ProgramOp::Const && p_.code[r].value == 0;
    };
    if (zero(y)) {
      if (!write(x)) return false;
    } else if (zero(x)) {
      if (!write(y)) return false;
      nodes.push_back(Node::op_node(Op::Neg));
    } else {
      if (!write(x) || !write(y)) return false;
      nodes.push_back(Node::op_node(Op::Sub));
    }
    if (!(swap ? b() : a()) || !(swap ? a() : b())) return false;
    nodes.push_back(Node::op_node(Op::Select));
    return true;
  }

  const Program& p_;
  std::vector<int> var_of_input_;
};

}  // namespace

ProgramFormula program_formula(const Program& program, std::span<const std::string> variables) {
  if (program.outputs.empty()) throw Error("the reference has no outputs", {program.description});
  std::vector<int> var_of_input(program.inputs.size(), -1);
  for (std::size_t i = 0; i < program.inputs.size(); ++i)
    for (std::size_t v = 0; v < variables.size(); ++v)
      if (variables[v] == program.inputs[i]) var_of_input[i] = static_cast<int>(v);
  FormulaWriter w(program, std::move(var_of_input));
  ProgramFormula out;
  if (!w.write(program.outputs.back())) {
    out.why = std::move(w.why);
    return out;
  }
  Expression e;
  e.nodes = std::move(w.nodes);
  e.variables.assign(variables.begin(), variables.end());
  e.update_lengths();
  out.formula = std::move(e);
  return out;
}

}  // namespace shaderfit::reference
