// The elementary functions of verify/interval.hpp: each value on the part of the operand inside
// the function's domain (MPFI, or MPFR at the ends of a monotone function), undefined where the
// operand leaves it, and the derivative's enclosure over the operand for the chain rule.
#include <mpfr.h>

#include "verify/interval.hpp"
#include "verify/interval_detail.hpp"

namespace shaderfit::verify {

using namespace verify_detail;

namespace {

constexpr double kInf = __builtin_inf();

// f(a) for a function defined on [min, max] (C's value at the ends: log(0) = -inf), slot by
// slot, NaN flagged where the operand leaves the domain (after tightening its box enclosure), with
// the derivatives `df(f1, x, y)` (f1 = an enclosure of f' for x = a's interval, y = f's) and
// `d2f(f2, x, y, f1)` (f2 = an enclosure of f'' over the box).
template <typename Value, typename Derivative, typename Second>
Dual elementary(const Dual& a, double min, double max, Value value, Derivative df, Second d2f) {
  Arena& arena = Arena::current();
  if (leaves(&a->v, min, max)) tighten(a.get());
  Cell* r = result(a.get());
  mpfi_ptr in = arena.scratch(0);
  for (int s = 0, n = slots(r); s < n; ++s) {
    mpfi_srcptr x = slot(a.get(), s);
    if (leaves(x, min, max)) flag_nan(r, s);
    if (!clip(in, x, min, max)) {
      set_nan(out(r, s));
      continue;
    }
    value(out(r, s), in);
  }
  settle(r);
  if (wants_gradient(r)) {
    mpfi_ptr f1 = arena.scratch(1), f2 = arena.scratch(4), f1m = arena.scratch(5);
    df(f1, &a->v, &r->v);
    if (wants_taylor(r)) {
      df(f1m, slot(a.get(), 1), slot(r, 1));
      d2f(f2, &a->v, &r->v, f1);
      chain(r, a.get(), f1, f2, f1m);
    } else {
      chain(r, a.get(), f1);
    }
  }
  return Dual(r);
}

// A function that MPFI does not have, increasing (or decreasing) on its whole domain: MPFR at the
// ends, rounded outward.
template <int (*F)(mpfr_ptr, mpfr_srcptr, mpfr_rnd_t), bool kIncreasing>
void monotone(mpfi_ptr r, mpfi_srcptr x) {
  if (kIncreasing) {
    F(lo(r), lo(x), MPFR_RNDD);
    F(hi(r), hi(x), MPFR_RNDU);
  } else {
    F(lo(r), hi(x), MPFR_RNDD);
    F(hi(r), lo(x), MPFR_RNDU);
  }
}

// Scratch for the derivatives' own temporaries (0 holds the clipped operand, 1 the factor).
mpfi_ptr tmp(int i) { return Arena::current().scratch(2 + i); }

// f = 1 / sqrt(s * (1 - x^2)) style helpers.
void one_minus_square(mpfi_ptr out, mpfi_srcptr x) {
  mpfi_sqr(out, x);
  mpfi_ui_sub(out, 1, out);
}

// f = c / sqrt(g) (unbounded where g reaches 0), with g >= 0 assumed (clipped to [0, inf)).
void inverse_sqrt(mpfi_ptr f, mpfi_srcptr g, long c) {
  mpfi_ptr t = tmp(1);
  mpfi_set(t, g);
  if (mpfr_sgn(lo(t)) < 0) mpfr_set_ui(lo(t), 0, MPFR_RNDD);
  mpfi_sqrt(t, t);
  mpfi_inv(f, t);
  mpfi_mul_si(f, f, c);
}

// Second derivatives in terms of x, y = f(x) and f1 = f'(x).
void minus_y(mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y, mpfi_srcptr) { mpfi_neg(f, y); }
void minus_square_of_f1(mpfi_ptr f, mpfi_srcptr, mpfi_srcptr, mpfi_srcptr f1) {
  mpfi_sqr(f, f1);
  mpfi_neg(f, f);
}
template <long C>
void x_times_f1(mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr, mpfi_srcptr f1) {  // C x f'
  mpfi_mul(f, x, f1);
  mpfi_mul_si(f, f, C);
}
template <long C>
void x_times_f1_squared(mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr, mpfi_srcptr f1) {  // C x f'^2
  mpfi_sqr(f, f1);
  mpfi_mul(f, f, x);
  mpfi_mul_si(f, f, C);
}
template <long C>
void x_times_f1_cubed(mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr, mpfi_srcptr f1) {  // C x f'^3
  mpfi_sqr(f, f1);
  mpfi_mul(f, f, f1);
  mpfi_mul(f, f, x);
  mpfi_mul_si(f, f, C);
}

}  // namespace

Dual sqrt(const Dual& a) {
  return elementary(
      a, 0, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_sqrt(r, x); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y) {  // 1 / (2 y)
        mpfi_mul_ui(f, y, 2);
        mpfi_inv(f, f);
      },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y, mpfi_srcptr) {  // -1 / (4 y^3)
        mpfi_sqr(f, y);
        mpfi_mul(f, f, y);
        mpfi_mul_si(f, f, -4);
        mpfi_inv(f, f);
      });
}

Dual cbrt(const Dual& a) {
  return elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_cbrt(r, x); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y) {  // 1 / (3 y^2)
        mpfi_sqr(f, y);
        mpfi_mul_ui(f, f, 3);
        mpfi_inv(f, f);
      },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y, mpfi_srcptr) {  // -2 / (9 y^5)
        mpfi_sqr(f, y);
        mpfi_sqr(f, f);
        mpfi_mul(f, f, y);
        mpfi_mul_si(f, f, -9);
        mpfi_inv(f, f);
        mpfi_mul_ui(f, f, 2);
      });
}

Dual exp(const Dual& a) {
  return elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_exp(r, x); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y) { mpfi_set(f, y); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y, mpfi_srcptr) { mpfi_set(f, y); });
}

Dual exp2(const Dual& a) {
  return elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_exp2(r, x); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y) {  // ln 2 y
        mpfi_const_log2(f);
        mpfi_mul(f, f, y);
      },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr, mpfi_srcptr f1) {  // ln 2 f'
        mpfi_const_log2(f);
        mpfi_mul(f, f, f1);
      });
}

Dual expm1(const Dual& a) {
  return elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_expm1(r, x); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y) { mpfi_add_ui(f, y, 1); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr, mpfi_srcptr f1) { mpfi_set(f, f1); });
}

Dual log(const Dual& a) {
  return elementary(
      a, 0, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_log(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) { mpfi_inv(f, x); }, minus_square_of_f1);
}

Dual log2(const Dual& a) {
  return elementary(
      a, 0, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_log2(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) {  // 1 / (x ln 2)
        mpfi_const_log2(f);
        mpfi_mul(f, f, x);
        mpfi_inv(f, f);
      },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr, mpfi_srcptr f1) {  // -ln 2 f'^2
        mpfi_const_log2(f);
        mpfi_sqr(tmp(0), f1);
        mpfi_mul(f, f, tmp(0));
        mpfi_neg(f, f);
      });
}

Dual log10(const Dual& a) {
  return elementary(
      a, 0, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_log10(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) {  // 1 / (x ln 10)
        mpfi_set_ui(f, 10);
        mpfi_log(f, f);
        mpfi_mul(f, f, x);
        mpfi_inv(f, f);
      },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr, mpfi_srcptr f1) {  // -ln 10 f'^2
        mpfi_set_ui(f, 10);
        mpfi_log(f, f);
        mpfi_sqr(tmp(0), f1);
        mpfi_mul(f, f, tmp(0));
        mpfi_neg(f, f);
      });
}

Dual log1p(const Dual& a) {
  return elementary(
      a, -1, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_log1p(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) {
        mpfi_add_ui(f, x, 1);
        mpfi_inv(f, f);
      },
      minus_square_of_f1);
}

Dual sin(const Dual& a) {
  return elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_sin(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) { mpfi_cos(f, x); }, minus_y);
}

Dual cos(const Dual& a) {
  return elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_cos(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) {
        mpfi_sin(f, x);
        mpfi_neg(f, f);
      },
      minus_y);
}

Dual tan(const Dual& a) {
  Dual t = elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_tan(r, x); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y) {  // 1 + y^2
        mpfi_sqr(f, y);
        mpfi_add_ui(f, f, 1);
      },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y, mpfi_srcptr f1) {  // 2 y f'
        mpfi_mul(f, y, f1);
        mpfi_mul_ui(f, f, 2);
      });
  if (!mpfi_bounded_p(&t->v)) t->smooth = false;  // a pole inside: a jump from +inf to -inf
  return t;
}

Dual asin(const Dual& a) {
  return elementary(
      a, -1, 1, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_asin(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) {
        one_minus_square(tmp(0), x);
        inverse_sqrt(f, tmp(0), 1);
      },
      x_times_f1_cubed<1>);
}

Dual acos(const Dual& a) {
  return elementary(
      a, -1, 1, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_acos(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) {
        one_minus_square(tmp(0), x);
        inverse_sqrt(f, tmp(0), -1);
      },
      x_times_f1_cubed<1>);
}

Dual atan(const Dual& a) {
  return elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_atan(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) {
        mpfi_sqr(f, x);
        mpfi_add_ui(f, f, 1);
        mpfi_inv(f, f);
      },
      x_times_f1_squared<-2>);
}

Dual sinh(const Dual& a) {
  return elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_sinh(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) { mpfi_cosh(f, x); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y, mpfi_srcptr) { mpfi_set(f, y); });
}

Dual cosh(const Dual& a) {
  return elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_cosh(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) { mpfi_sinh(f, x); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y, mpfi_srcptr) { mpfi_set(f, y); });
}

Dual tanh(const Dual& a) {
  return elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_tanh(r, x); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y) { one_minus_square(f, y); },
      [](mpfi_ptr f, mpfi_srcptr, mpfi_srcptr y, mpfi_srcptr f1) {  // -2 y f'
        mpfi_mul(f, y, f1);
        mpfi_mul_si(f, f, -2);
      });
}

Dual asinh(const Dual& a) {
  return elementary(
      a, -kInf, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_asinh(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) {
        mpfi_sqr(tmp(0), x);
        mpfi_add_ui(tmp(0), tmp(0), 1);
        inverse_sqrt(f, tmp(0), 1);
      },
      x_times_f1_cubed<-1>);
}

Dual acosh(const Dual& a) {
  return elementary(
      a, 1, kInf, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_acosh(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) {
        mpfi_sqr(tmp(0), x);
        mpfi_sub_ui(tmp(0), tmp(0), 1);
        inverse_sqrt(f, tmp(0), 1);
      },
      x_times_f1_cubed<-1>);
}

Dual atanh(const Dual& a) {
  return elementary(
      a, -1, 1, [](mpfi_ptr r, mpfi_srcptr x) { mpfi_atanh(r, x); },
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) {
        one_minus_square(f, x);
        mpfi_inv(f, f);
      },
      x_times_f1_squared<2>);
}

namespace {

// 2 / sqrt(pi) exp(-x^2), times `sign`.
void erf_derivative(mpfi_ptr f, mpfi_srcptr x, long sign) {
  mpfi_sqr(f, x);
  mpfi_neg(f, f);
  mpfi_exp(f, f);
  mpfi_ptr c = tmp(0);
  mpfi_const_pi(c);
  mpfi_sqrt(c, c);
  mpfi_div(f, f, c);
  mpfi_mul_si(f, f, 2 * sign);
}

}  // namespace

Dual erf(const Dual& a) {
  return elementary(
      a, -kInf, kInf, monotone<mpfr_erf, true>,
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) { erf_derivative(f, x, 1); }, x_times_f1<-2>);
}

Dual erfc(const Dual& a) {
  return elementary(
      a, -kInf, kInf, monotone<mpfr_erfc, false>,
      [](mpfi_ptr f, mpfi_srcptr x, mpfi_srcptr) { erf_derivative(f, x, -1); }, x_times_f1<-2>);
}

namespace {

// A step function (floor, ceil, trunc, round: non-decreasing, integer-valued): constant where
// both ends of the operand give the same integer, else a jump (not smooth).
template <int (*F)(mpfr_ptr, mpfr_srcptr, mpfr_rnd_t)>
Dual step(const Dual& a) {
  Cell* r = result(a.get());
  auto value = [&](int s) {
    F(lo(out(r, s)), lo(slot(a.get(), s)), MPFR_RNDD);
    F(hi(out(r, s)), hi(slot(a.get(), s)), MPFR_RNDU);
  };
  value(0);
  if (!mpfr_equal_p(lo(&r->v), hi(&r->v)) && tighten(a.get())) value(0);
  if (mpfr_equal_p(lo(&r->v), hi(&r->v)) && !a->undefined()) {
    r->constant = true;  // one integer over the box: the derivative is 0
    r->smooth = r->taylor = true;
    r->nan = 0;
    return Dual(r);
  }
  for (int s = 1, n = slots(r); s < n; ++s) value(s);
  settle(r);
  r->smooth = false;
  return Dual(r);
}

}  // namespace

Dual floor(const Dual& a) { return step<mpfr_rint_floor>(a); }
Dual ceil(const Dual& a) { return step<mpfr_rint_ceil>(a); }
Dual trunc(const Dual& a) { return step<mpfr_rint_trunc>(a); }
Dual round(const Dual& a) { return step<mpfr_rint_round>(a); }

namespace {

// a^b = exp(b log a) (or exp2(b log2 a)): composed of those where a > 0 on the box (every
// derivative follows); else slot by slot on the part of a >= 0, NaN flagged where a < 0 and, with
// `zero_power_nan`, where a = 0 and b = 0 may meet (exp2(0 * -inf)); else 0^b there is the C
// value (0, 1 or +inf); not smooth (the slope in a is unbounded at 0 where b < 1).
Dual real_power(const Dual& a, const Dual& b, bool base2, bool zero_power_nan) {
  Arena& arena = Arena::current();
  if (mpfr_sgn(lo(&a->v)) <= 0) tighten(a.get());
  if (mpfr_sgn(lo(&a->v)) > 0) return base2 ? exp2(b * log2(a)) : exp(b * log(a));
  Cell* r = result(a.get(), b.get());
  mpfi_ptr in = arena.scratch(0), t = arena.scratch(1);
  for (int s = 0, n = slots(r); s < n; ++s) {
    mpfi_srcptr x = slot(a.get(), s), y = slot(b.get(), s);
    if (mpfr_sgn(lo(x)) < 0) flag_nan(r, s);
    if (!clip(in, x, 0, kInf)) {
      set_nan(out(r, s));
      continue;
    }
    const bool zero_base = mpfr_sgn(lo(in)) == 0;
    if (zero_base && mpfi_has_zero(y)) {
      if (zero_power_nan) flag_nan(r, s);
      mpfr_set_ui(lo(out(r, s)), 0, MPFR_RNDD);  // 0^b: 0, 1 or +inf
      mpfr_set_inf(hi(out(r, s)), 1);
      continue;
    }
    if (base2) {
      mpfi_log2(t, in);
      mpfi_mul(t, t, y);
      mpfi_exp2(out(r, s), t);
    } else {
      mpfi_log(t, in);
      mpfi_mul(t, t, y);
      mpfi_exp(out(r, s), t);
    }
  }
  settle(r);
  r->smooth = r->taylor = false;
  return Dual(r);
}

}  // namespace

Dual gpu_pow(const Dual& a, const Dual& b) { return real_power(a, b, true, true); }

Dual pow(const Dual& a, const Dual& b) {
  // std::pow: an integer constant exponent takes any base (1 / a^-n where negative).
  if (is_point(*b) && mpfr_integer_p(lo(&b->v)) && mpfr_cmpabs_ui(lo(&b->v), 1u << 30) < 0) {
    const long n = mpfr_get_si(lo(&b->v), MPFR_RNDN);
    if (n == 0) return Dual(1.0);  // pow(x, 0) = 1 for every x, NaN included
    return ipow(a, static_cast<int>(n));
  }
  return real_power(a, b, false, false);
}

namespace {

// Whether atan2 is continuous on the box y x x: inside one branch (the right half-plane, the
// upper half-plane with the negative x-axis, where atan2(+0, x) = pi, or the open lower one) and
// away from the origin.
bool atan2_continuous(mpfi_srcptr y, mpfi_srcptr x) {
  const bool origin = mpfi_has_zero(x) && mpfi_has_zero(y);
  return !origin && (mpfr_sgn(lo(x)) > 0 || mpfr_sgn(lo(y)) >= 0 || mpfr_sgn(hi(y)) < 0);
}

// atan2 on a box: where continuous, its extremes are at corners; else [-pi, pi].
void atan2_value(mpfi_ptr r, mpfi_srcptr y, mpfi_srcptr x) {
  if (!atan2_continuous(y, x)) {
    mpfi_const_pi(r);
    mpfr_neg(lo(r), hi(r), MPFR_RNDD);
    return;
  }
  Arena& arena = Arena::current();
  mpfr_ptr t = lo(arena.scratch(0));
  mpfr_ptr plus_zero = hi(arena.scratch(0));  // a zero's sign is +: atan2(0, -1) = pi
  mpfr_set_ui(plus_zero, 0, MPFR_RNDN);
  mpfr_set_inf(lo(r), 1);
  mpfr_set_inf(hi(r), -1);
  for (int k = 0; k < 4; ++k) {
    mpfr_srcptr yc = (k & 1) ? hi(y) : lo(y);
    mpfr_srcptr xc = (k & 2) ? hi(x) : lo(x);
    if (mpfr_zero_p(yc)) yc = plus_zero;
    mpfr_atan2(t, yc, xc, MPFR_RNDD);
    mpfr_min(lo(r), lo(r), t, MPFR_RNDD);
    mpfr_atan2(t, yc, xc, MPFR_RNDU);
    mpfr_max(hi(r), hi(r), t, MPFR_RNDU);
  }
}

}  // namespace

Dual atan2(const Dual& y, const Dual& x) {
  if (!atan2_continuous(&y->v, &x->v)) {
    tighten(y.get());
    tighten(x.get());
  }
  Cell* r = result(y.get(), x.get());
  for (int s = 0, n = slots(r); s < n; ++s)
    atan2_value(out(r, s), slot(y.get(), s), slot(x.get(), s));
  settle(r);
  if (!atan2_continuous(&y->v, &x->v)) r->smooth = false;  // the cut, or the origin
  if (wants_gradient(r)) {  // d/dy = x / (x^2 + y^2), d/dx = -y / (x^2 + y^2)
    Arena& arena = Arena::current();
    mpfi_ptr n = arena.scratch(0), fy = arena.scratch(1), fx = arena.scratch(2);
    mpfi_sqr(n, &x->v);
    mpfi_sqr(fx, &y->v);
    mpfi_add(n, n, fx);
    mpfi_inv(n, n);
    mpfi_mul(fy, &x->v, n);
    mpfi_mul(fx, &y->v, n);
    mpfi_neg(fx, fx);
    chain2(r, y.get(), fy, x.get(), fx);
  }
  return Dual(r);
}

Dual hypot(const Dual& a, const Dual& b) {
  return sqrt(a * a + b * b);  // each operand once, squared: as tight as mpfi_hypot
}

namespace {

// fmod(a, b) = a - trunc(a / b) b exactly, for b without 0: that where the quotient's integer
// part is one number (returned in q), else the bounds |fmod| < |b|, |fmod| <= |a|, sign of a.
bool fmod_value(mpfi_ptr r, mpfi_srcptr a, mpfi_srcptr b, mpfi_ptr q) {
  mpfi_div(q, a, b);
  mpfr_rint_trunc(lo(q), lo(q), MPFR_RNDD);
  mpfr_rint_trunc(hi(q), hi(q), MPFR_RNDU);
  if (mpfr_equal_p(lo(q), hi(q))) {
    mpfi_ptr nb = Arena::current().scratch(2);
    mpfi_mul(nb, q, b);
    mpfi_sub(r, a, nb);
    return true;
  }
  mpfi_ptr m = Arena::current().scratch(2);
  mpfi_abs(m, b);
  mpfr_neg(lo(m), hi(m), MPFR_RNDD);  // m = [-max |b|, max |b|]
  mpfi_set(r, a);
  if (mpfr_sgn(lo(r)) > 0) mpfr_set_ui(lo(r), 0, MPFR_RNDD);
  if (mpfr_sgn(hi(r)) < 0) mpfr_set_ui(hi(r), 0, MPFR_RNDU);
  mpfi_intersect(r, r, m);
  return false;
}

}  // namespace

Dual fmod(const Dual& a, const Dual& b) {
  if (mpfi_has_zero(&b->v)) tighten(b.get());
  Cell* r = result(a.get(), b.get());
  Arena& arena = Arena::current();
  mpfi_ptr q = arena.scratch(0);
  bool one_quotient = false;
  for (int s = 0, n = slots(r); s < n; ++s) {
    mpfi_srcptr x = slot(a.get(), s), y = slot(b.get(), s);
    if (mpfi_has_zero(y) || mpfi_nan_p(y)) {  // fmod(x, 0) is NaN
      set_nan(out(r, s));
      flag_nan(r, s);
      continue;
    }
    const bool one = fmod_value(out(r, s), x, y, q);
    if (s == 0) one_quotient = one;
    if (s == 0 && one && wants_gradient(r)) {  // a - n b
      mpfi_ptr fb = arena.scratch(1);
      mpfi_neg(fb, q);
      chain_linear(r, a.get(), nullptr, b.get(), fb);
    }
  }
  settle(r);
  if (!one_quotient) r->smooth = false;
  return Dual(r);
}

}  // namespace shaderfit::verify
