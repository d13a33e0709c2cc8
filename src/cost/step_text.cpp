#include "cost/step_text.hpp"

#include <cstdint>

#include "cost/float_text.hpp"

namespace shaderfit::cost_detail {

namespace {

bool same(const Operand& a, const Operand& b) {
  return a.kind == b.kind && a.index == b.index &&
         (a.kind != Operand::Kind::Const || a.value == b.value);
}

}  // namespace

std::string_view step_call_name(Op op) { return op_info(op).name; }

StepText::StepText(const Dag& dag, const Program& program) : dag_(dag), p_(program) {
  powers_.resize(p_.steps.size());
  for (std::size_t i = 0; i < p_.steps.size(); ++i) {
    const Step& st = p_.steps[i];
    powers_[i] = {Operand{Operand::Kind::Step, static_cast<int>(i), 0.0f}, 1};
    if (st.op != Op::Mul) continue;
    auto pw = [&](const Operand& o) {
      return o.kind == Operand::Kind::Step ? powers_[static_cast<std::size_t>(o.index)]
                                           : Power{o, 1};
    };
    const Power a = pw(st.args[0]), b = pw(st.args[1]);
    // Nested powers multiply their exponents ((x^16)^16 ... is x^(16^n)), so the sum is taken
    // in 64 bits and a chain beyond 2^30 prints as the product it is.
    const std::int64_t k = std::int64_t{a.k} + b.k;
    if (same(a.base, b.base) && a.base.kind != Operand::Kind::Const && k <= (std::int64_t{1} << 30))
      powers_[i] = {a.base, static_cast<int>(k)};
  }
}

std::string StepText::operand(const Operand& o, int min_level, std::size_t limit) const {
  switch (o.kind) {
    case Operand::Kind::Const: {
      const std::string t = float_text(o.value);
      return o.value < 0 && min_level > 1 ? "(" + t + ")" : t;
    }
    case Operand::Kind::Var: return dag_.variables[static_cast<std::size_t>(o.index)];
    case Operand::Kind::Param: return dag_.parameters[static_cast<std::size_t>(o.index)];
    case Operand::Kind::Step: return step(o.index, min_level, limit);
    default: return "?";
  }
}

std::string StepText::pair(const Operand& a, int level_a, std::string_view op, const Operand& b,
                           int level_b, std::size_t limit) const {
  std::string t = operand(a, level_a, limit);
  if (t.size() > limit) return t;
  t += op;
  if (t.size() > limit) return t;
  return t + operand(b, level_b, limit - t.size());
}

std::string StepText::step(int i, int min_level, std::size_t limit) const {
  const Step& st = p_.steps[static_cast<std::size_t>(i)];
  const Power& pw = powers_[static_cast<std::size_t>(i)];
  std::string t;
  int lv = precedence(st.op);
  if (pw.k > 1) {
    t = operand(pw.base, 4, limit) + "^" + std::to_string(pw.k);
    lv = 4;
  } else if (op_info(st.op).infix) {
    const std::string symbol = " " + std::string(op_info(st.op).name) + " ";
    t = pair(st.args[0], lv, symbol, st.args[1], lv + 1, limit);
  } else {
    switch (st.op) {
      case Op::Neg: t = "-" + operand(st.args[0], 4, limit); break;
      case Op::Select:
        t = "select(" + std::string(st.neg_arg ? "-" : "") +
            operand(st.args[0], st.neg_arg ? 4 : 0, limit) + " >= 0, " +
            operand(st.args[1], 0, limit) + ", " + operand(st.args[2], 0, limit) + ")";
        break;
      default:
        t = std::string(step_call_name(st.op)) + "(";
        if (st.neg_arg) t += "-" + operand(st.args[0], 4, limit);
        for (int k = st.neg_arg ? 1 : 0; k < st.arity && t.size() <= limit; ++k) {
          if (k) t += ", ";
          t += operand(st.args[k], 0, t.size() < limit ? limit - t.size() : 0);
        }
        t += ")";
        break;
    }
  }
  return lv < min_level ? "(" + t + ")" : t;
}

std::string StepText::of(int i, std::size_t max_chars) const {
  std::string t = step(i, 0, max_chars);
  if (t.size() > max_chars) t = t.substr(0, max_chars - 3) + "...";
  return t;
}

}  // namespace shaderfit::cost_detail
