#include "cost/step_text.hpp"

#include "cost/float_text.hpp"

namespace shaderfit::lowering {

namespace {

bool same(const Operand& a, const Operand& b) {
  return a.kind == b.kind && a.index == b.index && (a.kind != Operand::Kind::Const || a.value == b.value);
}

// Precedence: 1 sums, 2 products, 3 unary minus, 4 atoms and calls.
int level(StepOp op) {
  switch (op) {
    case StepOp::Add:
    case StepOp::Sub: return 1;
    case StepOp::Mul:
    case StepOp::Div: return 2;
    case StepOp::Neg: return 3;
    default: return 4;
  }
}

const char* call_name(StepOp op) {
  switch (op) {
    case StepOp::Fma: return "fma";
    case StepOp::Abs: return "abs";
    case StepOp::Sqrt: return "sqrt";
    case StepOp::Rsqrt: return "rsqrt";
    case StepOp::Exp2: return "exp2";
    case StepOp::Log2: return "log2";
    case StepOp::Exp: return "exp";
    case StepOp::Log: return "log";
    case StepOp::Sin: return "sin";
    case StepOp::Cos: return "cos";
    case StepOp::Sat: return "saturate";
    case StepOp::Min: return "min";
    case StepOp::Max: return "max";
    default: return "?";
  }
}

}  // namespace

StepText::StepText(const Dag& dag, const Program& program) : dag_(dag), p_(program) {
  powers_.resize(p_.steps.size());
  for (std::size_t i = 0; i < p_.steps.size(); ++i) {
    const Step& st = p_.steps[i];
    powers_[i] = {Operand{Operand::Kind::Step, static_cast<int>(i), 0.0f}, 1};
    if (st.op != StepOp::Mul) continue;
    auto pw = [&](const Operand& o) {
      return o.kind == Operand::Kind::Step ? powers_[static_cast<std::size_t>(o.index)] : Power{o, 1};
    };
    const Power a = pw(st.args[0]), b = pw(st.args[1]);
    if (same(a.base, b.base) && a.base.kind != Operand::Kind::Const) powers_[i] = {a.base, a.k + b.k};
  }
}

std::string StepText::operand(const Operand& o, int min_level) const {
  switch (o.kind) {
    case Operand::Kind::Const: {
      const std::string t = float_text(o.value);
      return o.value < 0 && min_level > 1 ? "(" + t + ")" : t;
    }
    case Operand::Kind::Var: return dag_.variables[static_cast<std::size_t>(o.index)];
    case Operand::Kind::Param: return dag_.parameters[static_cast<std::size_t>(o.index)];
    case Operand::Kind::Step: return step(o.index, min_level);
    default: return "?";
  }
}

std::string StepText::step(int i, int min_level) const {
  const Step& st = p_.steps[static_cast<std::size_t>(i)];
  const Power& pw = powers_[static_cast<std::size_t>(i)];
  std::string t;
  int lv = level(st.op);
  if (pw.k > 1) {
    t = operand(pw.base, 4) + "^" + std::to_string(pw.k);
    lv = 4;
  } else {
    switch (st.op) {
      case StepOp::Add: t = operand(st.args[0], 1) + " + " + operand(st.args[1], 2); break;
      case StepOp::Sub: t = operand(st.args[0], 1) + " - " + operand(st.args[1], 2); break;
      case StepOp::Mul: t = operand(st.args[0], 2) + " * " + operand(st.args[1], 3); break;
      case StepOp::Div: t = operand(st.args[0], 2) + " / " + operand(st.args[1], 3); break;
      case StepOp::Neg: t = "-" + operand(st.args[0], 4); break;
      default:
        t = std::string(call_name(st.op)) + "(";
        if (st.neg_arg) t += "-" + operand(st.args[0], 4);
        for (int k = st.neg_arg ? 1 : 0; k < st.arity; ++k) t += (k ? ", " : "") + operand(st.args[k], 0);
        t += ")";
        break;
    }
  }
  return lv < min_level ? "(" + t + ")" : t;
}

std::string StepText::of(int i, std::size_t max_chars) const {
  std::string t = step(i, 0);
  if (t.size() > max_chars) t = t.substr(0, max_chars - 3) + "...";
  return t;
}

}  // namespace shaderfit::lowering
