// What chooses in verify/interval.hpp: kinks (abs, saturate, min, max: continuous, their gradient
// the hull of the one-sided ones), jumps (sign, copysign, select: where the box does not decide
// them, each point decides for itself and the box takes the hull, not smooth), the reference
// programs' comparisons and logic, and the formula operators by Op. An undecided box first
// tightens the operand that decides (interval_detail.hpp, tighten).
#include <mpfr.h>

#include "shaderfit/core/error.hpp"
#include "shaderfit/reference/builtin_evaluate.hpp"
#include "verify/interval.hpp"
#include "verify/interval_detail.hpp"

namespace shaderfit::verify {

using namespace verify_detail;

namespace {

// a >= 0 in slot s of a cell (NaN: false).
Truth nonnegative(const Cell* a, int s) {
  mpfi_srcptr v = slot(a, s);
  Truth t = Truth::Maybe;
  if (mpfr_sgn(lo(v)) >= 0) t = Truth::True;
  if (mpfr_sgn(hi(v)) < 0) t = Truth::False;
  if (nan_in(a, s) && t == Truth::True) t = Truth::Maybe;
  return t;
}

}  // namespace

Dual abs(const Dual& a) {
  if (mpfr_sgn(lo(&a->v)) < 0 && mpfr_sgn(hi(&a->v)) > 0) tighten(a.get());
  if (mpfr_sgn(lo(&a->v)) >= 0) return a;
  if (mpfr_sgn(hi(&a->v)) <= 0) return -a;
  Cell* r = result(a.get());
  for (int s = 0, n = slots(r); s < n; ++s) mpfi_abs(out(r, s), slot(a.get(), s));
  if (wants_gradient(r)) {  // the slopes -1 and 1 both occur: [-1, 1] times a's gradient
    mpfi_ptr f = Arena::current().scratch(1);
    mpfi_interv_si(f, -1, 1);
    chain(r, a.get(), f);
  }
  return Dual(r);
}

Dual saturate(const Dual& a) {
  auto inside = [&] { return mpfr_sgn(lo(&a->v)) >= 0 && mpfr_cmp_ui(hi(&a->v), 1) <= 0; };
  auto flat = [&] { return mpfr_sgn(hi(&a->v)) <= 0 || mpfr_cmp_ui(lo(&a->v), 1) >= 0; };
  if (!inside() && !flat()) tighten(a.get());
  if (inside()) return a;
  if (flat()) {
    Cell* r = Arena::current().fresh();
    r->nan = a->undefined() ? 1 : 0;
    mpfi_set_ui(&r->v, mpfr_sgn(hi(&a->v)) <= 0 ? 0 : 1);
    return Dual(r);
  }
  Cell* r = result(a.get());
  for (int s = 0, n = slots(r); s < n; ++s) {
    mpfi_ptr o = out(r, s);
    mpfi_set(o, slot(a.get(), s));
    for (mpfr_ptr e : {lo(o), hi(o)}) {
      if (mpfr_sgn(e) < 0) mpfr_set_ui(e, 0, MPFR_RNDN);
      if (mpfr_cmp_ui(e, 1) > 0) mpfr_set_ui(e, 1, MPFR_RNDN);
    }
  }
  settle(r);
  if (wants_gradient(r)) {
    Cell flat_part;  // the clamped parts: gradient 0
    gradient_hull(r, a.get(), &flat_part);
  }
  return Dual(r);
}

namespace {

// min (or max) of a and b: the operand that is the smaller (larger) on the whole box, else the
// endpoints' min (max) slot by slot, with the hull of both gradients. A NaN operand flags the
// result (C's fmin would take the other operand: the bound only gets looser).
Dual extreme(const Dual& a, const Dual& b, bool max) {
  auto decided = [&]() -> const Dual* {
    if (a->undefined() || b->undefined()) return nullptr;
    if (mpfr_cmp(hi(&a->v), lo(&b->v)) <= 0) return max ? &b : &a;
    if (mpfr_cmp(hi(&b->v), lo(&a->v)) <= 0) return max ? &a : &b;
    return nullptr;
  };
  if (decided() == nullptr) {
    tighten(a.get());
    tighten(b.get());
  }
  if (const Dual* d = decided()) return *d;
  Cell* r = result(a.get(), b.get());
  for (int s = 0, n = slots(r); s < n; ++s) {
    mpfi_srcptr x = slot(a.get(), s), y = slot(b.get(), s);
    if (max) {
      mpfr_max(lo(out(r, s)), lo(x), lo(y), MPFR_RNDD);
      mpfr_max(hi(out(r, s)), hi(x), hi(y), MPFR_RNDU);
    } else {
      mpfr_min(lo(out(r, s)), lo(x), lo(y), MPFR_RNDD);
      mpfr_min(hi(out(r, s)), hi(x), hi(y), MPFR_RNDU);
    }
  }
  settle(r);
  gradient_hull(r, a.get(), b.get());
  return Dual(r);
}

}  // namespace

Dual fmin(const Dual& a, const Dual& b) { return extreme(a, b, false); }
Dual fmax(const Dual& a, const Dual& b) { return extreme(a, b, true); }

Dual copysign(const Dual& a, const Dual& b) {
  // A zero's sign is +: copysign(a, 0) = |a|. A NaN b gives |a| with some sign: either.
  if (nonnegative(b.get(), 0) == Truth::Maybe) tighten(b.get());
  const Truth t = nonnegative(b.get(), 0);
  if (t == Truth::True) return abs(a);
  if (t == Truth::False) return -abs(a);
  const Dual m = abs(a);
  return blend(m, -m, [&](int s) { return nonnegative(b.get(), s); });
}

Dual sign(const Dual& a) {
  auto decided = [&] {
    const int l = mpfr_sgn(lo(&a->v)), h = mpfr_sgn(hi(&a->v));
    return l == h || (l > 0 && h > 0) || (l < 0 && h < 0);
  };
  if (!decided()) tighten(a.get());
  const bool constant = decided();
  Cell* r = Arena::current().fresh();
  r->constant = constant || a->constant;
  r->smooth = r->taylor = r->constant;
  for (int s = 0, n = slots(r); s < n; ++s) {
    mpfi_srcptr x = slot(a.get(), s);
    const int l = mpfr_sgn(lo(x)), h = mpfr_sgn(hi(x));
    mpfi_interv_si(out(r, s), l > 0 ? 1 : (l < 0 ? -1 : 0), h > 0 ? 1 : (h < 0 ? -1 : 0));
    if (nan_in(a.get(), s)) flag_nan(r, s);
  }
  settle(r);
  return Dual(r);
}

Dual select(const Dual& a, const Dual& b, const Dual& c) {
  if (nonnegative(a.get(), 0) == Truth::Maybe) tighten(a.get());
  const Truth t = nonnegative(a.get(), 0);
  if (t == Truth::True) return b;  // -0.0 and 0 take b
  if (t == Truth::False) return c;
  return blend(b, c, [&](int s) { return nonnegative(a.get(), s); });  // NaN takes c
}

Dual apply_op(Op op, int index, std::span<const Dual> o) {
  // op.hpp's forms, but for the operators whose forms compare (saturate, sign, select) or whose
  // interval has a tighter form here (pow as the GPU computes it, ipow).
  return visit_op(op, [&]<Op O>() -> Dual {
    if constexpr (O == Op::Pow)
      return gpu_pow(o[0], o[1]);
    else if constexpr (O == Op::IPow)
      return ipow(o[0], index);
    else if constexpr (O == Op::Saturate)
      return saturate(o[0]);
    else if constexpr (O == Op::Sign)
      return sign(o[0]);
    else if constexpr (O == Op::Select)
      return select(o[0], o[1], o[2]);
    else if constexpr (O == Op::Fma)
      return apply_fma(o[0], o[1], o[2]);
    else if constexpr (O != Op::Count_ && arity(O) == 1)
      return unary_value<O>(o[0]);
    else if constexpr (O != Op::Count_ && arity(O) == 2)
      return binary_value<O>(o[0], o[1]);
    else
      throw Error("certify: operator '" + std::string(op_info(op).name) + "' is not an operation");
  });
}

}  // namespace shaderfit::verify

namespace shaderfit::reference {

namespace {

using verify::Cell;
using verify::Dual;
using verify_detail::flip;
using verify_detail::hi;
using verify_detail::lo;
using verify_detail::nan_in;
using verify_detail::out;
using verify_detail::slot;
using verify_detail::slots;
using verify_detail::Truth;

// Whether slot s of a cell is nonzero (true); a NaN counts as false (0 < NaN and NaN < 0 are
// both false).
Truth truth_of(const Cell* c, int s) {
  mpfi_srcptr v = slot(c, s);
  Truth t = Truth::Maybe;
  if (mpfr_sgn(lo(v)) > 0 || mpfr_sgn(hi(v)) < 0) t = Truth::True;
  if (mpfr_zero_p(lo(v)) && mpfr_zero_p(hi(v))) t = Truth::False;
  if (nan_in(c, s) && t == Truth::True) t = Truth::Maybe;
  return t;
}

void set_truth(mpfi_ptr v, Truth t) {
  if (t == Truth::Maybe) {
    mpfi_interv_si(v, 0, 1);
  } else {
    mpfi_set_si(v, t == Truth::True ? 1 : 0);
  }
}

// A truth value: constant where the box decides, else decided (or not) point by point.
template <typename Of>
Dual truth_value(Of truth) {
  Cell* r = verify::Arena::current().fresh();
  const Truth box = truth(0);
  r->constant = box != Truth::Maybe;
  r->smooth = r->taylor = r->constant;
  for (int s = 0, n = slots(r); s < n; ++s) set_truth(out(r, s), s == 0 ? box : truth(s));
  return Dual(r);
}

// The same function on the box: one cell, or two constants of one value.
bool same(const Cell* x, const Cell* y) {
  return x == y ||
         (verify::is_point(*x) && verify::is_point(*y) && mpfr_equal_p(lo(&x->v), lo(&y->v)));
}

Truth compare_slots(ProgramOp op, mpfi_srcptr a, mpfi_srcptr b) {
  auto less = [](mpfi_srcptr x, mpfi_srcptr y) {  // x < y
    if (mpfr_cmp(hi(x), lo(y)) < 0) return Truth::True;
    if (mpfr_cmp(lo(x), hi(y)) >= 0) return Truth::False;
    return Truth::Maybe;
  };
  auto less_equal = [](mpfi_srcptr x, mpfi_srcptr y) {  // x <= y
    if (mpfr_cmp(hi(x), lo(y)) <= 0) return Truth::True;
    if (mpfr_cmp(lo(x), hi(y)) > 0) return Truth::False;
    return Truth::Maybe;
  };
  auto equal = [](mpfi_srcptr x, mpfi_srcptr y) {
    if (mpfr_cmp(hi(x), lo(y)) < 0 || mpfr_cmp(hi(y), lo(x)) < 0) return Truth::False;
    if (mpfr_equal_p(lo(x), hi(x)) && mpfr_equal_p(lo(y), hi(y)) && mpfr_equal_p(lo(x), lo(y))) {
      return Truth::True;
    }
    return Truth::Maybe;
  };
  switch (op) {
    case ProgramOp::Less: return less(a, b);
    case ProgramOp::LessEqual: return less_equal(a, b);
    case ProgramOp::Greater: return less(b, a);
    case ProgramOp::GreaterEqual: return less_equal(b, a);
    case ProgramOp::Equal: return equal(a, b);
    default: return flip(equal(a, b));  // NotEqual
  }
}

}  // namespace

Dual ProgramLogic<Dual>::compare(ProgramOp op, const Dual& a, const Dual& b) {
  auto truth = [&](int s) {
    if (mpfi_nan_p(slot(a.get(), s)) || mpfi_nan_p(slot(b.get(), s))) return Truth::Maybe;
    Truth t = compare_slots(op, slot(a.get(), s), slot(b.get(), s));
    if ((nan_in(a.get(), s) || nan_in(b.get(), s)) && t == Truth::True) t = Truth::Maybe;
    return t;  // NaN compares false
  };
  if (truth(0) == Truth::Maybe) {
    verify_detail::tighten(a.get());
    verify_detail::tighten(b.get());
  }
  Dual r = truth_value(truth);
  if (!r->constant) {
    r->cmp_lhs = a.get();
    r->cmp_rhs = b.get();
    r->cmp_op = op;
  }
  return r;
}

Dual ProgramLogic<Dual>::logic(ProgramOp op, const Dual& a, const Dual& b) {
  return truth_value([&](int s) {
    const Truth ta = truth_of(a.get(), s);
    if (op == ProgramOp::Not) return flip(ta);
    const Truth tb = truth_of(b.get(), s);
    if (op == ProgramOp::And) {
      if (ta == Truth::False || tb == Truth::False) return Truth::False;
      return ta == Truth::True && tb == Truth::True ? Truth::True : Truth::Maybe;
    }
    if (ta == Truth::True || tb == Truth::True) return Truth::True;  // Or
    return ta == Truth::False && tb == Truth::False ? Truth::False : Truth::Maybe;
  });
}

Dual ProgramLogic<Dual>::select(const Dual& c, const Dual& a, const Dual& b) {
  const Truth t = truth_of(c.get(), 0);
  if (t == Truth::True) return a;
  if (t == Truth::False) return b;
  // `x > y ? x : y` and the like are a min or max of the compared values: continuous.
  const ProgramOp op = c->cmp_op;
  const bool greater = op == ProgramOp::Greater || op == ProgramOp::GreaterEqual;
  const bool less = op == ProgramOp::Less || op == ProgramOp::LessEqual;
  if (greater || less) {
    if (same(a.get(), c->cmp_lhs) && same(b.get(), c->cmp_rhs)) {
      return greater ? verify::fmax(a, b) : verify::fmin(a, b);
    }
    if (same(a.get(), c->cmp_rhs) && same(b.get(), c->cmp_lhs)) {
      return greater ? verify::fmin(a, b) : verify::fmax(a, b);
    }
  }
  return verify_detail::blend(a, b, [&](int s) { return truth_of(c.get(), s); });
}

Dual ProgramLogic<Dual>::builtin(BuiltinId id, std::span<const Dual> args) {
  return evaluate_builtin<Dual>(id, args);
}

}  // namespace shaderfit::reference

namespace shaderfit::verify {

using L = reference::ProgramLogic<Dual>;
Dual operator<(const Dual& a, const Dual& b) {
  return L::compare(reference::ProgramOp::Less, a, b);
}
Dual operator<=(const Dual& a, const Dual& b) {
  return L::compare(reference::ProgramOp::LessEqual, a, b);
}
Dual operator>(const Dual& a, const Dual& b) {
  return L::compare(reference::ProgramOp::Greater, a, b);
}
Dual operator>=(const Dual& a, const Dual& b) {
  return L::compare(reference::ProgramOp::GreaterEqual, a, b);
}
Dual choose(const Dual& condition, const Dual& a, const Dual& b) {
  return L::select(condition, a, b);
}

}  // namespace shaderfit::verify
