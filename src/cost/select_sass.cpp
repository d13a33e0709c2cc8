// SASS selection: what ptxas makes of the PTX of the generated CUDA (nvcc --use_fast_math,
// sm_90). Rules, each checked against cuobjdump output (docs/cost-model.md, "SASS"):
//  - a negation or |x| read by FADD/FMUL/FFMA/FMNMX is an operand modifier: free;
//  - a negation of a product read only there folds into the product (FMUL -a, b): free;
//  - any other negation (before a MUFU op, FADD.SAT, or of the result) is FADD d, -x, -RZ;
//    any other |x| is FADD d, |x|, -RZ;
//  - -1 / x is MUFU.RCP, negated like any other value;
//  - sin and cos scale their argument by 1/(2 pi) with FMUL.RZ, once per distinct argument;
//  - exp(x) is FMUL by log2(e) + MUFU.EX2 (that FMUL takes |x| and -x for free); log(x) is
//    MUFU.LG2 + FMUL by ln(2);
//  - saturate of a product read only there is FMUL.SAT (not so for FADD, FFMA, FMNMX results);
//  - 1 / exp2(x) and 1 / exp(x), the exponential read only there, is MUFU.EX2 of -x: no MUFU.RCP;
//  - |x * x| is x * x;
//  - log's ln(2) scale merges into FMUL.SAT when saturated, and into a product with a literal;
//  - select(a, b, c) is FSETP (one per distinct condition and sign: -a folds into the comparison)
//    and FSEL, except that a branch computed only for the select runs under the predicate
//    instead (no FSEL);
//  - copysign(a, b) is one LOP3 (a & 0x7fffffff | b & 0x80000000); sign(x), written
//    |x| > 0 ? copysign(1, x) : x, is FSETP on |x|, LOP3 and FSEL;
//  - sqrt, rsqrt, exp2, log2, sin and cos are their MUFU op (cost/op_instructions.hpp);
//  - asin, acos, atan, atan2, tanh and erf are the instructions of CUDA's asinf ... erff as
//    measured (cost/op_instructions.hpp); their operands are read as they are (a negated operand
//    costs its FADD; acos of a negated product is the product, its negation and acosf).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <tuple>

#include "cost/float_text.hpp"
#include "cost/op_instructions.hpp"
#include "cost/register_value.hpp"
#include "cost/select.hpp"
#include "cost/step_text.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit::cost_detail {

namespace {

using Val = RegisterValue;

class SassSelector : SelectorState {
 public:
  SassSelector(const Dag& dag, const Program& p, bool text) : SelectorState(dag, p, text) {}

  std::vector<TargetInstruction> run() {
    for (std::size_t i = 0; i < p_.steps.size(); ++i) select(static_cast<int>(i));
    return std::move(out_);
  }

 private:
  bool is_result(int s) const { return readers_.is_result(s); }
  bool all_alu(int s, bool neg_ok = false) const {
    if (is_result(s)) return false;
    for (int c : readers_.of(s)) {
      const Op op = p_.steps[static_cast<std::size_t>(c)].op;
      if (!takes_operand_modifiers(op) && !(neg_ok && op == Op::Neg && all_alu(c))) return false;
    }
    return true;
  }
  // A product whose only reader is a negation that is not free: ptxas computes it negated,
  // unless the negation is read by a library function (checked against ptxas: acosf(-(x * y))
  // is FMUL, FADD -p, -RZ, then acosf's instructions).
  bool negated_product(int s) const {
    const Step& st = p_.steps[static_cast<std::size_t>(s)];
    if (st.op != Op::Mul || st.uses != 1 || readers_.of(s).size() != 1) return false;
    const int c = readers_.of(s)[0];
    if (p_.steps[static_cast<std::size_t>(c)].op != Op::Neg || all_alu(c)) return false;
    for (int r : readers_.of(c))
      if (library_call(p_.steps[static_cast<std::size_t>(r)].op) != nullptr) return false;
    return true;
  }

  int only_reader(int s) const { return readers_.only_reader(s); }
  const Step* step_of(const Operand& o) const {
    return o.kind == Operand::Kind::Step ? &p_.steps[static_cast<std::size_t>(o.index)] : nullptr;
  }
  // Abs that costs nothing: read only as an operand modifier, or of a square.
  bool free_abs(int s) const {
    const Step& st = p_.steps[static_cast<std::size_t>(s)];
    const Step* x = step_of(st.args[0]);
    if (x && x->op == Op::Mul && x->args[0].kind == x->args[1].kind && x->args[0].index == x->args[1].index &&
        x->args[0].kind != Operand::Kind::Const)
      return true;
    if (is_result(s)) return false;
    for (int c : readers_.of(s)) {
      const Step& rd = p_.steps[static_cast<std::size_t>(c)];
      if (!takes_operand_modifiers(rd.op) && rd.op != Op::Exp && !(rd.op == Op::Neg && all_alu(c))) return false;
      // -|x| as the subtrahend of FADD is not folded (checked against ptxas).
      if (rd.op == Op::Sub && rd.args[1].kind == Operand::Kind::Step && rd.args[1].index == s) return false;
    }
    return true;
  }

  static std::string text(const Val& v) { return register_value_text(v, "R"); }
  static Val sign_mask() { return Val{-1, false, false, true, 0.0f, "0x80000000"}; }

  Val emit(InstructionUnit unit, const std::string& op, std::initializer_list<Val> args,
           const std::string& comment, bool predicate = false) {
    Val d{predicate ? -1 : next_reg_++};
    if (predicate) {  // P0, P1, ... (named by a token that lives as long as the selector)
      d.token =
          predicate_names_.emplace_back("P" + std::to_string(predicate_names_.size())).c_str();
    }
    TargetInstruction ins;
    ins.unit = unit;
    if (text_) {
      ins.text = op + " " + text(d);
      for (const Val& a : args) ins.text += ", " + text(a);
      ins.comment = comment;
    }
    out_.push_back(std::move(ins));
    return d;
  }

  // The measured instructions of a library function, the first reading the operands and the
  // last giving the result.
  Val library(const OpInstructions& call, Val a, Val b, int arity, const std::string& c) {
    return emit_library_call(call.sass, call.cuda, a, b, arity, c, text_,
                             [&](InstructionUnit u, const std::string& op, std::initializer_list<Val> args,
                                 const std::string& what) { return emit(u, op, args, what); });
  }

  // A function of the hardware (MUFU): its argument in turns first where it takes one (FMUL.RZ,
  // once per distinct argument), negated where only a reciprocal reads an exponential.
  Val function(int s, const OpInstructions& f, Val a, const std::string& c) {
    const Step& st = p_.steps[static_cast<std::size_t>(s)];
    if (f.turns) {
      const auto key = std::make_tuple(static_cast<int>(st.args[0].kind), st.args[0].index);
      auto it = scaled_.find(key);
      if (it == scaled_.end()) {
        const Val k{-1, false, false, true, kInv2Pi};
        it = scaled_
                 .emplace(key, emit(InstructionUnit::Fp32, "FMUL.RZ", {a, k}, "argument / (2 pi)"))
                 .first;
      }
      a = it->second;
    }
    const int r = only_reader(s);
    const bool inv =
        f.exponential && r >= 0 && is_reciprocal(p_.steps[static_cast<std::size_t>(r)]);
    return emit(mnemonic_unit(f.sass), std::string(f.sass), {inv ? negated(a) : a},
                inv ? "1 / " + c : c);
  }

  void select(int s) {
    const Step& st = p_.steps[static_cast<std::size_t>(s)];
    if (st.compared) return;  // its selects compare its operands
    const std::string c = text_ ? names_text_.of(s) : std::string();
    const Val a = st.arity > 0 ? val(st.args[0]) : Val{};
    const Val b = st.arity > 1 ? val(st.args[1]) : Val{};
    const Val rz{-1, true, false, true, 0.0f, "RZ"};
    Val& out = vals_[static_cast<std::size_t>(s)];
    using U = InstructionUnit;
    // Immediates go last, as ptxas writes them.
    auto ordered = [](Val x, Val y) { return x.imm && !y.imm ? std::make_pair(y, x) : std::make_pair(x, y); };
    switch (st.op) {
      case Op::Add:
      case Op::Sub: {
        const auto [x, y] = ordered(a, st.op == Op::Sub ? negated(b) : b);
        out = emit(U::Fp32, "FADD.FTZ", {x, y}, c);
        break;
      }
      case Op::Mul: {
        auto [x, y] = ordered(a, b);
        if (negated_product(s)) x = negated(x);
        const int r = only_reader(s);
        const bool sat = r >= 0 && p_.steps[static_cast<std::size_t>(r)].op == Op::Saturate;
        out = emit(U::Fp32, sat ? "FMUL.FTZ.SAT" : "FMUL.FTZ", {x, y}, sat ? names_text_.of(r) : c);
        break;
      }
      case Op::Fma: {
        const auto [x, y] = ordered(a, b);
        out = emit(U::Fp32, "FFMA.FTZ", {x, y, val(st.args[2])}, c);
        break;
      }
      case Op::Min:
      case Op::Max: {
        const auto [x, y] = ordered(a, b);
        out = emit(U::MinMax, "FMNMX.FTZ", {x, y, Val{-1, false, false, true, 0.0f, st.op == Op::Min ? "PT" : "!PT"}}, c);
        break;
      }
      case Op::Neg:
        if (all_alu(s)) out = negated(a);
        else if (st.args[0].kind == Operand::Kind::Step && negated_product(st.args[0].index)) out = a;
        else out = emit(U::Fp32, "FADD.FTZ", {negated(a), rz}, c);
        break;
      case Op::Abs: {
        const Step* x = step_of(st.args[0]);
        if (x && x->op == Op::Mul && free_abs(s)) out = a;  // a square is not negative
        else if (free_abs(s)) out = Val{a.reg, false, true};
        else out = emit(U::Fp32, "FADD.FTZ", {Val{a.reg, false, true}, rz}, c);
        break;
      }
      case Op::Div: {
        const bool rcp = is_reciprocal(st);
        const Step* den = step_of(st.args[1]);
        const bool folded = rcp && den && exponential(den->op) && den->uses == 1;
        const Val r = folded ? b : emit(U::Mufu, "MUFU.RCP", {b}, rcp ? c : std::string("reciprocal of the divisor"));
        if (!rcp) out = emit(U::Fp32, "FMUL.FTZ", {a, r}, c);
        else if (a.value > 0) out = r;
        else if (all_alu(s)) out = negated(r);
        else out = emit(U::Fp32, "FADD.FTZ", {negated(r), rz}, c);
        break;
      }
      case Op::Saturate: {
        const Step* x = step_of(st.args[0]);
        if (x && (x->op == Op::Mul || x->op == Op::Log) && only_reader(st.args[0].index) == s)
          out = a;  // FMUL.SAT
        else out = emit(U::Fp32, "FADD.FTZ.SAT", {a, rz}, c);
        break;
      }
      case Op::Exp: {
        const float scale = st.neg_arg ? -kLog2E : kLog2E;
        const Val t = emit(U::Fp32, "FMUL.FTZ", {a, Val{-1, false, false, true, scale}}, "log2(e) * ...");
        const int r = only_reader(s);
        const bool inv = r >= 0 && is_reciprocal(p_.steps[static_cast<std::size_t>(r)]);
        out = emit(U::Mufu, "MUFU.EX2", {inv ? negated(t) : t}, inv ? "1 / " + c : c);
        break;
      }
      case Op::Log: {
        const int r = only_reader(s);
        const Step* rd = r >= 0 ? &p_.steps[static_cast<std::size_t>(r)] : nullptr;
        // (x * 2 is x + x in PTX, which does not merge.)
        auto scale = [](const Operand& o) { return o.kind == Operand::Kind::Const && std::fabs(o.value) != 2.0f; };
        const bool merged = rd && rd->op == Op::Mul && (scale(rd->args[0]) || scale(rd->args[1]));
        const bool sat = rd && rd->op == Op::Saturate;
        const Val t = emit(U::Mufu, "MUFU.LG2", {a}, merged ? c : "log2 of ...");
        out = merged ? t : emit(U::Fp32, sat ? "FMUL.FTZ.SAT" : "FMUL.FTZ", {t, Val{-1, false, false, true, kLn2}}, c);
        break;
      }
      case Op::Sign: {
        const Val p = emit(U::MinMax, "FSETP.GT.FTZ.AND", {Val{a.reg, false, true}, rz},
                           "test of " + c, true);
        const Val one =
            emit(U::MinMax, "LOP3.LUT", {Val{-1, false, false, true, 1.0f}, sign_mask(), a},
                 "copysign(1, ...)");
        out = emit(U::MinMax, "FSEL", {one, a, p}, c);
        break;
      }
      case Op::CopySign: out = emit(U::MinMax, "LOP3.LUT", {a, sign_mask(), b}, c); break;
      case Op::Select: {
        const auto key = std::make_tuple(static_cast<int>(st.args[0].kind), st.args[0].index,
                                         st.neg_arg ? 1 : 0);
        auto it = predicates_.find(key);
        if (it == predicates_.end()) {
          const Comparison cmp = select_comparison(p_, st);
          const bool zero = cmp.rhs.kind == Operand::Kind::Const && cmp.rhs.value == 0.0f;
          const Val p = emit(U::MinMax, st.neg_arg ? "FSETP.LE.FTZ.AND" : "FSETP.GE.FTZ.AND",
                             {val(cmp.lhs), zero ? rz : val(cmp.rhs)}, "condition of " + c, true);
          it = predicates_.emplace(key, p).first;
        }
        // A branch that is computed for this select alone is computed under the predicate.
        for (int k : {1, 2}) {
          if (st.args[k].kind == Operand::Kind::Step && only_reader(st.args[k].index) == s) {
            out = val(st.args[k]);
            return;
          }
        }
        out = emit(U::MinMax, "FSEL", {b, val(st.args[2]), it->second}, c);
        break;
      }
      default: {
        const OpInstructions* f = op_instructions(st.op);
        if (f == nullptr || f->sass.empty())
          throw Error("internal: no SASS form for '" + std::string(op_info(st.op).name) + "'");
        if (!f->library()) {
          out = function(s, *f, a, c);
          break;
        }
        // A function that ptxas gives a negated product (read only there) as the product and its
        // negation, where other readers take FMUL -a, b (acosf).
        const Step* x = step_of(st.args[0]);
        Val arg = a;
        if (f->negates_product && x && x->op == Op::Mul && x->negated && x->uses == 1)
          arg = emit(U::Fp32, "FADD.FTZ", {a, rz}, "the product's negation");
        out = library(*f, arg, b, st.arity, c);
        break;
      }
    }
  }

  std::map<std::tuple<int, int>, Val> scaled_;
  std::map<std::tuple<int, int, int>, Val> predicates_;  // Select: FSETP per condition and sign
  std::deque<std::string> predicate_names_;
};

}  // namespace

std::vector<TargetInstruction> select_sass(const Dag& dag, const Program& program, bool with_text) {
  return SassSelector(dag, program, with_text).run();
}

}  // namespace shaderfit::cost_detail
