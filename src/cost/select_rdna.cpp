// RDNA selection: the VALU instructions LLVM's AMDGPU back end makes of the generated code
// (clang -O3 -cl-fast-relaxed-math, gfx1030 for RDNA 2, gfx1100 for RDNA 3), counted as
// operations. Rules, each checked against clang's output (docs/cost-model.md, "RDNA"):
//  - + - * fma min max are one VALU instruction each (v_add_f32, v_sub_f32, v_mul_f32,
//    v_fma_f32 / v_fmac_f32, v_min_f32, v_max_f32); literals are free operands (an inline
//    constant or the one 32-bit literal of the instruction; moves of constants are not counted);
//  - every float instruction (the transcendentals and v_cndmask's VOP3 form too) reads -x and |x|
//    as source modifiers: a negation or |x| read only by those is free; a negation of the result
//    of +, -, *, fma, min, max, a reciprocal or a sine, read only there, moves into that
//    instruction's operands (-(a * b) = -a * b, -rcp(x) = rcp(-x)); any other negation is
//    v_xor_b32 with the sign bit, any other |x| v_and_b32;
//  - saturate is the clamp bit of the instruction that computes its operand when that operand
//    is read only there and is not a bit operation (v_bfi, v_cndmask, v_xor, v_and) nor a * b + K
//    with a literal K (v_fmaak_f32, which has no clamp bit); otherwise v_max_f32 x, x clamp;
//  - min(min(a, b), c) and max(max(a, b), c), the inner one read only there, are one v_min3_f32 or
//    v_max3_f32; on RDNA 3 also min(max(a, b), c) and max(min(a, b), c), one v_maxmin_f32 or
//    v_minmax_f32 (RDNA 2 has v_med3_f32 for min(max(x, K0), K1), which LLVM forms only with IEEE
//    mode off, as in pixel shaders, not in the compute kernels of the check: counted as two);
//  - |x| of a value that is never negative (exp2, exp, sqrt, saturate, x * x) is x;
//  - a product with a factor x + 1, x - 1, 1 - x or -1 - x is one v_fma_f32 ((x + 1) y = x y + y),
//    so such a sum read only by products is not computed (LLVM's distributive FMA fold);
//  - sqrt(a) * sqrt(b), both roots read only there, is sqrt(a * b): one product, one root;
//  - the DAG is lowered with fast math's folds (dag.hpp: x - x, x / x, 1 / (1 / x), ...), as
//    LLVM rewrites the algebra under -cl-fast-relaxed-math;
//  - a / b is v_rcp_f32 and v_mul_f32 (the reciprocal of one divisor computed once); 1 / exp2(x)
//    and 1 / exp(x), the exponential read only there, is v_exp_f32 of -x;
//  - sqrt, rsqrt, exp2, log2 are v_sqrt_f32, v_rsq_f32, v_exp_f32, v_log_f32 (quarter rate);
//    exp(x) scales by log2(e) first, log(x) by ln(2) after, sin and cos by 1 / (2 pi) first (once
//    per distinct argument); a scale merges into a product with a literal that is read only there
//    (exp(2 * x) is v_mul_f32 by 2 log2(e) and v_exp_f32; log(x) * 3 is v_log_f32 and v_mul_f32);
//  - select(a, b, c) is v_cmp_ge_f32 (one per distinct condition and sign) and v_cndmask_b32;
//    copysign is v_bfi_b32; sign(x) is v_bfi_b32 (copysign(1, x)), v_cmp_lg_f32 and
//    v_cndmask_b32;
//  - asin, acos, atan, atan2, tanh and erf are the instructions of ROCm's OCML functions as
//    measured (cost/op_instructions.hpp, with the transcendentals' instructions).
// RDNA 2 and RDNA 3 count the same but for v_maxmin_f32 and v_minmax_f32; RDNA 3 may also issue
// two independent operations as one VOPD instruction (v_dual_*), which the count does not model
// (the check counts a pair as its two operations).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
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

// A float the instructions encode as an inline constant (no 32-bit literal): 0, 0.5, 1, 2, 4, their
// negations and 1 / (2 pi).
bool inline_constant(float v) {
  const float a = std::fabs(v);
  return a == 0.0f || a == 0.5f || a == 1.0f || a == 2.0f || a == 4.0f || v == kInv2Pi;
}

// Operators whose instructions take -x and |x| operands for free.
bool reads_modifiers(Op op) {
  switch (op) {
    case Op::CopySign:
    case Op::Sign:
    case Op::Neg:
    case Op::Abs: return false;
    default: return true;
  }
}

// Operators whose result's negation moves into their own operands: the arithmetic, and the odd
// transcendentals (sine: -sin(x) = sin(-x)).
bool absorbs_negation(Op op) {
  switch (op) {
    case Op::Add:
    case Op::Sub:
    case Op::Mul:
    case Op::Fma:
    case Op::Min:
    case Op::Max: return true;
    default: {
      const OpInstructions* f = op_instructions(op);
      return f != nullptr && !f->library() && !f->rdna.empty() &&
             op_info(op).parity == OpParity::Odd;
    }
  }
}

class RdnaSelector : SelectorState {
 public:
  RdnaSelector(const Dag& dag, const Program& p, bool text, bool rdna3)
      : SelectorState(dag, p, text), rdna3_(rdna3) {
    pair_min_max();
    find_root_products();
    find_distributed();
  }

  std::vector<TargetInstruction> run() {
    for (std::size_t i = 0; i < p_.steps.size(); ++i) select(static_cast<int>(i));
    return std::move(out_);
  }

 private:
  const Step& step(int s) const { return p_.steps[static_cast<std::size_t>(s)]; }
  const Step* step_of(const Operand& o) const {
    return o.kind == Operand::Kind::Step ? &step(o.index) : nullptr;
  }

  // Every reader of step s takes modifiers (and s is not a result).
  bool all_modifier_readers(int s) const {
    if (readers_.is_result(s)) return false;
    for (int r : readers_.of(s))
      if (!reads_modifiers(step(r).op)) return false;
    return true;
  }
  // Step s (a Neg) is free: read only as a modifier, or moved into the step it negates.
  bool free_negation(int s) const {
    if (all_modifier_readers(s)) return true;
    return moves_into(step(s).args[0]);
  }
  bool moves_into(const Operand& o) const {
    const Step* x = step_of(o);
    if (x == nullptr) return false;
    if (absorbs_negation(x->op) || is_reciprocal(*x)) return readers_.only_reader(o.index) >= 0;
    return false;
  }
  // |x| of a value that is never negative: x itself.
  bool never_negative(const Operand& o) const {
    const Step* x = step_of(o);
    if (x == nullptr) return false;
    switch (x->op) {
      case Op::Exp2:
      case Op::Exp:
      case Op::Sqrt:
      case Op::Saturate: return true;
      case Op::Mul:
        return x->args[0].kind == x->args[1].kind && x->args[0].index == x->args[1].index &&
               x->args[0].kind != Operand::Kind::Const;
      default: return false;
    }
  }
  // The instruction of step s can carry the clamp bit of a saturate that reads it.
  bool clamps(int s) const {
    const Step& st = step(s);
    switch (st.op) {
      case Op::Fma:  // a * b + K with a literal K is v_fmaak_f32, a VOP2 form with no clamp bit
        return !(st.args[2].kind == Operand::Kind::Const && !inline_constant(st.args[2].value) &&
                 st.args[0].kind != Operand::Kind::Const &&
                 st.args[1].kind != Operand::Kind::Const);
      case Op::Select:
      case Op::CopySign:
      case Op::Sign: return false;
      case Op::Neg:
        return free_negation(s) && step_of(step(s).args[0]) != nullptr &&
               clamps(step(s).args[0].index);
      case Op::Abs: return false;
      default: return library_call(step(s).op) == nullptr;
    }
  }
  // A single-use product with a literal factor, whose literal a following scale merges into.
  bool literal_product(const Operand& o) const {
    const Step* x = step_of(o);
    return x && x->op == Op::Mul && readers_.only_reader(o.index) >= 0 &&
           (x->args[0].kind == Operand::Kind::Const || x->args[1].kind == Operand::Kind::Const);
  }
  bool read_by_saturate(int s) const {
    const int r = readers_.only_reader(s);
    return r >= 0 && step(r).op == Op::Saturate && clamps(s);
  }

  static std::string text(const Val& v) { return register_value_text(v, "v"); }
  static Val literal(float v) { return Val{-1, false, false, true, v}; }
  static Val token(const char* t) { return Val{-1, false, false, true, 0.0f, t}; }

  // One instruction; `clamp` appends the clamp bit. A comparison writes vcc_lo.
  Val emit(InstructionUnit unit, const std::string& op, std::initializer_list<Val> args,
           const std::string& comment, bool clamp = false) {
    const Val d = op.starts_with("v_cmp_") ? token("vcc_lo") : Val{next_reg_++};
    TargetInstruction ins;
    ins.unit = unit;
    if (text_) {
      ins.text = op + " " + text(d);
      for (const Val& a : args) ins.text += ", " + text(a);
      if (clamp) ins.text += " clamp";
      ins.comment = comment;
    }
    out_.push_back(std::move(ins));
    return d;
  }
  // A float instruction computing step s, with the clamp bit when a saturate reads it alone.
  Val emit_step(int s, InstructionUnit unit, const std::string& op, std::initializer_list<Val> args,
                const std::string& comment) {
    const bool sat = read_by_saturate(s);
    const int r = readers_.only_reader(s);
    return emit(unit, op, args, sat && text_ ? names_text_.of(r) : comment, sat);
  }

  Val library(const OpInstructions& call, Val a, Val b, int arity, const std::string& c) {
    return emit_library_call(
        call.rdna, call.ocml, a, b, arity, c, text_,
        [&](InstructionUnit u, const std::string& op, std::initializer_list<Val> args,
            const std::string& what) { return emit(u, op, args, what); });
  }

  // A scale by `k` before a transcendental (exp, sin, cos): merged into a single-use product
  // with a literal factor.
  Val scaled(const Operand& o, float k, const std::string& comment) {
    if (literal_product(o)) {
      const Step& m = *step_of(o);
      const bool first = m.args[0].kind == Operand::Kind::Const;
      const Operand& other = first ? m.args[1] : m.args[0];
      const float c = (first ? m.args[0] : m.args[1]).value * k;
      return emit(InstructionUnit::Fp32, "v_mul_f32", {literal(c), val(other)}, comment);
    }
    return emit(InstructionUnit::Fp32, "v_mul_f32", {literal(k), val(o)}, comment);
  }
  // A single-use product with a literal factor whose only reader scales it (exp, sin, cos) or
  // whose only reader is a log's scale: computed by that reader.
  bool merged_product(int s) const {
    if (!literal_product(Operand{Operand::Kind::Step, s})) return false;
    const Op r = step(readers_.only_reader(s)).op;
    return r == Op::Exp || in_turns(r);
  }

  void select(int s) {
    const Step& st = step(s);
    if (st.compared) return;                                // its selects compare its operands
    if (distributed_[static_cast<std::size_t>(s)]) return;  // its products distribute over it
    const std::string c = text_ ? names_text_.of(s) : std::string();
    const Val a = st.arity > 0 ? val(st.args[0]) : Val{};
    const Val b = st.arity > 1 ? val(st.args[1]) : Val{};
    Val& out = vals_[static_cast<std::size_t>(s)];
    using U = InstructionUnit;
    switch (st.op) {
      case Op::Add: out = emit_step(s, U::Fp32, "v_add_f32", {a, b}, c); break;
      case Op::Sub: out = emit_step(s, U::Fp32, "v_sub_f32", {a, b}, c); break;
      case Op::Mul: {
        if (merged_product(s)) {
          out = Val{};  // computed by its reader's scale
          break;
        }
        const bool roots = root_product_[static_cast<std::size_t>(s)];
        const auto [f0, f1] = factors(st, s);
        const Operand fs[2] = {f0, f1};
        for (int k = 0; k < 2; ++k) {
          const Operand& f = fs[k];
          if (f.kind != Operand::Kind::Step || !distributed_[static_cast<std::size_t>(f.index)])
            continue;
          // (x + 1) y = fma(x, y, y), and the like.
          const auto [x, x_neg, one] = unit_sum(step(f.index));
          const Val y = val(fs[1 - k]);
          const Val p =
              roots ? emit(U::Fp32, "v_fma_f32",
                           {x_neg ? negated(val(x)) : val(x), y, one < 0 ? negated(y) : y},
                           "the product of the radicands")
                    : emit_step(s, U::Fp32, "v_fma_f32",
                                {x_neg ? negated(val(x)) : val(x), y, one < 0 ? negated(y) : y}, c);
          out = roots ? emit_step(s, U::Mufu, "v_sqrt_f32", {p}, c) : p;
          return;
        }
        if (roots) {  // sqrt(a) * sqrt(b) = sqrt(a * b)
          const Val p =
              emit(U::Fp32, "v_mul_f32", {val(f0), val(f1)}, "the product of the radicands");
          out = emit_step(s, U::Mufu, "v_sqrt_f32", {p}, c);
          return;
        }
        // log(x) * K: the ln(2) scale of the log merges into this product.
        for (int k = 0; k < 2; ++k) {
          const Step* x = step_of(st.args[k]);
          if (x && x->op == Op::Log && st.args[1 - k].kind == Operand::Kind::Const) {
            out = emit_step(s, U::Fp32, "v_mul_f32",
                            {literal(st.args[1 - k].value * kLn2), k ? b : a}, c);
            return;
          }
        }
        out = emit_step(s, U::Fp32, "v_mul_f32", {a, b}, c);
        break;
      }
      case Op::Fma: out = emit_step(s, U::Fp32, "v_fma_f32", {a, b, val(st.args[2])}, c); break;
      case Op::Min:
      case Op::Max: {
        if (inner_[static_cast<std::size_t>(s)]) {
          out = Val{};  // computed by the three-operand instruction that reads it
          break;
        }
        const int k = outer_[static_cast<std::size_t>(s)];
        if (k >= 0) {
          const Step& in = step(st.args[k].index);
          const char* op = in.op == st.op ? (st.op == Op::Min ? "v_min3_f32" : "v_max3_f32")
                                          : (st.op == Op::Min ? "v_maxmin_f32" : "v_minmax_f32");
          out = emit_step(s, U::MinMax, op, {val(in.args[0]), val(in.args[1]), val(st.args[1 - k])},
                          c);
          break;
        }
        out = emit_step(s, U::MinMax, st.op == Op::Min ? "v_min_f32" : "v_max_f32", {a, b}, c);
        break;
      }
      case Op::Neg:
        if (all_modifier_readers(s))
          out = negated(a);
        else if (moves_into(st.args[0]))
          out = negated(a);  // the producer computed it negated
        else
          out = emit(U::MinMax, "v_xor_b32", {token("0x80000000"), a}, c);
        break;
      case Op::Abs:
        if (never_negative(st.args[0]))
          out = a;
        else if (all_modifier_readers(s))
          out = Val{a.reg, false, true};
        else
          out = emit(U::MinMax, "v_and_b32", {token("0x7fffffff"), a}, c);
        break;
      case Op::Div: {
        const bool rcp = is_reciprocal(st);
        const Step* den = step_of(st.args[1]);
        if (rcp && den && exponential(den->op) && den->uses == 1) {
          out = b;  // the exponential of -x
          break;
        }
        if (rcp) {
          const Val r = emit_step(s, U::Mufu, "v_rcp_f32", {a.value < 0 ? negated(b) : b}, c);
          out = r;
          break;
        }
        const Val r = emit(U::Mufu, "v_rcp_f32", {b}, "reciprocal of the divisor");
        out = emit_step(s, U::Fp32, "v_mul_f32", {a, r}, c);
        break;
      }
      case Op::Sqrt:
        if (merged_root_[static_cast<std::size_t>(s)]) break;  // its product takes the radicand
        out = emit_step(s, U::Mufu, "v_sqrt_f32", {a}, c);
        break;
      case Op::Exp: {
        const float k = (st.neg_arg != inverted(s)) ? -kLog2E : kLog2E;
        const Val t = scaled(st.args[0], k, "log2(e) * ...");
        out = emit_step(s, U::Mufu, "v_exp_f32", {t}, c);
        break;
      }
      case Op::Log: {
        const int r = readers_.only_reader(s);
        const Step* rd = r >= 0 ? &step(r) : nullptr;
        const bool merged =
            rd && rd->op == Op::Mul &&
            (rd->args[0].kind == Operand::Kind::Const || rd->args[1].kind == Operand::Kind::Const);
        if (merged) {
          out = emit(U::Mufu, "v_log_f32", {a}, "log2 of ...");  // the reader scales by K ln(2)
        } else {
          const Val t = emit(U::Mufu, "v_log_f32", {a}, "log2 of ...");
          out = emit_step(s, U::Fp32, "v_mul_f32", {literal(kLn2), t}, c);
        }
        break;
      }
      case Op::Saturate: {
        const Step* x = step_of(st.args[0]);
        if (x && readers_.only_reader(st.args[0].index) == s && clamps(st.args[0].index))
          out = a;
        else
          out = emit(U::MinMax, "v_max_f32", {a, a}, c, true);
        break;
      }
      case Op::Sign: {
        const Val one = emit(U::MinMax, "v_bfi_b32", {token("0x7fffffff"), literal(1.0f), a},
                             "copysign(1, ...)");
        const Val vcc = emit(U::MinMax, "v_cmp_lg_f32", {literal(0.0f), a}, "test of " + c);
        (void)vcc;
        out = emit(U::MinMax, "v_cndmask_b32", {a, one, token("vcc_lo")}, c);
        break;
      }
      case Op::CopySign: out = emit(U::MinMax, "v_bfi_b32", {token("0x7fffffff"), a, b}, c); break;
      case Op::Select: {
        const auto key = std::make_tuple(static_cast<int>(st.args[0].kind), st.args[0].index,
                                         st.neg_arg ? 1 : 0);
        if (conditions_.insert(key).second) {
          const Comparison cmp = select_comparison(p_, st);
          emit(U::MinMax, st.neg_arg ? "v_cmp_le_f32" : "v_cmp_ge_f32",
               {val(cmp.lhs), val(cmp.rhs)}, "condition of " + c);
        }
        out = emit(U::MinMax, "v_cndmask_b32", {val(st.args[2]), b, token("vcc_lo")}, c);
        break;
      }
      default: {
        const OpInstructions* f = op_instructions(st.op);
        if (f == nullptr || f->rdna.empty())
          throw Error("internal: no RDNA form for '" + std::string(op_info(st.op).name) + "'");
        if (f->library()) {
          out = library(*f, a, b, st.arity, c);
          break;
        }
        // A transcendental: its argument in turns first where it takes one (once per distinct
        // argument), negated where only a reciprocal reads an exponential.
        Val x = a;
        if (f->turns) {
          const auto key = std::make_tuple(static_cast<int>(st.args[0].kind), st.args[0].index);
          auto it = scaled_.find(key);
          if (it == scaled_.end())
            it = scaled_.emplace(key, scaled(st.args[0], kInv2Pi, "argument / (2 pi)")).first;
          x = it->second;
        }
        if (f->exponential && inverted(s)) x = negated(x);
        out = emit_step(s, mnemonic_unit(f->rdna), std::string(f->rdna), {x}, c);
        break;
      }
    }
  }

  // Step s (an exponential) is read only by a reciprocal: it computes exp2(-x) instead.
  bool inverted(int s) const {
    const int r = readers_.only_reader(s);
    return r >= 0 && is_reciprocal(step(r));
  }
  // A sum x + 1, x - 1, 1 - x or -1 - x as (x, x negated, the literal); `one` 0 for other steps.
  struct UnitSum {
    Operand x;
    bool x_neg = false;
    float one = 0.0f;
  };
  static UnitSum unit_sum(const Step& st) {
    if (st.op != Op::Add && st.op != Op::Sub) return {};
    for (int k = 0; k < 2; ++k) {
      const Operand& lit = st.args[k];
      if (lit.kind != Operand::Kind::Const || std::fabs(lit.value) != 1.0f ||
          st.args[1 - k].kind == Operand::Kind::Const)
        continue;
      if (st.op == Op::Add) return {st.args[1 - k], false, lit.value};
      return k == 0 ? UnitSum{st.args[1], true, lit.value} : UnitSum{st.args[0], false, -lit.value};
    }
    return {};
  }
  // The unit sums every reader of which is a product that takes it as one factor.
  // sqrt(a) * sqrt(b) = sqrt(a * b) where both roots are read only by the product.
  void find_root_products() {
    root_product_.assign(p_.steps.size(), false);
    merged_root_.assign(p_.steps.size(), false);
    for (std::size_t m = 0; m < p_.steps.size(); ++m) {
      const Step& st = p_.steps[m];
      if (st.op != Op::Mul) continue;
      const Step *x = step_of(st.args[0]), *y = step_of(st.args[1]);
      if (!x || !y || x->op != Op::Sqrt || y->op != Op::Sqrt ||
          st.args[0].index == st.args[1].index ||
          readers_.only_reader(st.args[0].index) != static_cast<int>(m) ||
          readers_.only_reader(st.args[1].index) != static_cast<int>(m))
        continue;
      root_product_[m] = true;
      merged_root_[static_cast<std::size_t>(st.args[0].index)] = true;
      merged_root_[static_cast<std::size_t>(st.args[1].index)] = true;
    }
  }
  // The factors a product multiplies: its operands, or for a product of merged roots their
  // radicands.
  std::pair<Operand, Operand> factors(const Step& product, int index) const {
    if (!root_product_[static_cast<std::size_t>(index)]) return {product.args[0], product.args[1]};
    return {step(product.args[0].index).args[0], step(product.args[1].index).args[0]};
  }

  void find_distributed() {
    distributed_.assign(p_.steps.size(), false);
    for (std::size_t i = 0; i < p_.steps.size(); ++i) {
      const Step& st = p_.steps[i];
      if (unit_sum(st).one == 0.0f || st.compared || readers_.is_result(static_cast<int>(i)) ||
          readers_.of(static_cast<int>(i)).empty())
        continue;
      bool all = true;
      for (int r : readers_.of(static_cast<int>(i))) {
        // A merged root reads it for the product of radicands that reads the root.
        const int p = merged_root_[static_cast<std::size_t>(r)] ? readers_.only_reader(r) : r;
        const Step& rd = step(p);
        const auto [f0, f1] = factors(rd, p);
        const bool first = f0.kind == Operand::Kind::Step && f0.index == static_cast<int>(i);
        const bool second = f1.kind == Operand::Kind::Step && f1.index == static_cast<int>(i);
        all = all && rd.op == Op::Mul && first != second;
      }
      distributed_[i] = all;
    }
  }

  // The min and max steps that merge into one three-operand instruction: a min or max read only
  // by a min or max (a different one only on RDNA 3) that takes it as an operand, and that did
  // not take an inner one itself.
  void pair_min_max() {
    inner_.assign(p_.steps.size(), false);
    outer_.assign(p_.steps.size(), -1);
    for (std::size_t r = 0; r < p_.steps.size(); ++r) {
      const Step& st = p_.steps[r];
      if (st.op != Op::Min && st.op != Op::Max) continue;
      for (int k = 0; k < 2; ++k) {
        const Step* in = step_of(st.args[k]);
        if (in == nullptr || (in->op != Op::Min && in->op != Op::Max) ||
            (in->op != st.op && !rdna3_))
          continue;
        const auto i = static_cast<std::size_t>(st.args[k].index);
        if (outer_[i] >= 0 || readers_.only_reader(st.args[k].index) != static_cast<int>(r))
          continue;
        inner_[i] = true;
        outer_[r] = k;
        break;
      }
    }
  }

  bool rdna3_;
  std::vector<bool> inner_;  // a min or max computed by the three-operand instruction reading it
  std::vector<int> outer_;   // the operand (0, 1) of a min or max that is its inner one, or -1
  std::vector<bool> distributed_;                 // unit sums the products reading them take apart
  std::vector<bool> root_product_, merged_root_;  // sqrt(a) * sqrt(b) and its two roots
  std::map<std::tuple<int, int>, Val> scaled_;
  std::set<std::tuple<int, int, int>> conditions_;  // Select: one v_cmp per condition and sign
};

}  // namespace

std::vector<TargetInstruction> select_rdna(const Dag& dag, const Program& program, bool with_text,
                                           bool rdna3) {
  return RdnaSelector(dag, program, with_text, rdna3).run();
}

}  // namespace shaderfit::cost_detail
