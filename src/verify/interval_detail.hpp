// The helpers that verify/interval*.cpp share to build result cells: slots and flags, the chain
// rule, the tightening of an operand's box enclosure, and the raw interval operations with the
// reals' edge cases.
#pragma once

#include <mpfi.h>

#include "verify/interval.hpp"

namespace shaderfit::verify_detail {

using namespace shaderfit::verify;  // the area's public names

inline mpfr_ptr lo(mpfi_ptr x) { return &x->left; }
inline mpfr_ptr hi(mpfi_ptr x) { return &x->right; }
inline mpfr_srcptr lo(mpfi_srcptr x) { return &x->left; }
inline mpfr_srcptr hi(mpfi_srcptr x) { return &x->right; }

// The slots a cell uses: the box alone when constant, else the box and the arena's points.
int slots(const Cell* c);
// Slot s of a cell (a constant cell's value in every slot).
inline mpfi_srcptr slot(const Cell* c, int s) {
  return (s == 0 || c->constant) ? &c->v : &c->p[s - 1];
}
inline mpfi_ptr out(Cell* c, int s) { return s == 0 ? &c->v : &c->p[s - 1]; }
// Whether slot s of c may be NaN.
inline bool nan_in(const Cell* c, int s) {
  return c->constant ? (c->nan & 1u) != 0 : ((c->nan >> s) & 1u) != 0;
}

// A fresh cell whose flags are the operands': NaN where either may be, constant, smooth and
// taylor where both are.
Cell* result(const Cell* a);
Cell* result(const Cell* a, const Cell* b);
// Flags the slots whose value came out NaN (and the box with any point).
void settle(Cell* r);
void flag_nan(Cell* r, int s);  // slot s may be NaN (and so the box)
// Whether r's gradient (and second order) is to be computed: derivatives on, r not constant,
// smooth (taylor) and defined.
bool wants_gradient(const Cell* r);
bool wants_taylor(const Cell* r);
// A cell's derivatives, 0 for a constant: over the box (d), at the midpoint (g), the Hessian (h).
mpfi_srcptr D(const Cell* c, int i);
mpfi_srcptr G(const Cell* c, int i);
mpfi_srcptr H(const Cell* c, int k);
// r = f(a): f1 encloses f' over a's box interval, f2 f'' there, f1m f' at a's midpoint value
// (null f2 or f1m: first order only). Clears r->smooth (r->taylor) where f1 (f2, f1m) is
// unbounded.
void chain(Cell* r, const Cell* a, mpfi_srcptr f1, mpfi_srcptr f2 = nullptr,
           mpfi_srcptr f1m = nullptr);
// r = ca a + cb b for constants ca, cb (null: 1), every order.
void chain_linear(Cell* r, const Cell* a, mpfi_srcptr ca, const Cell* b, mpfi_srcptr cb);
// r = f(a, b) to first order only: r's gradient = fa * a's + fb * b's (fa, fb: f's partials over
// the box); clears r->taylor.
void chain2(Cell* r, const Cell* a, mpfi_srcptr fa, const Cell* b, mpfi_srcptr fb);
// The hull of both cells' gradients, component by component, into r (the Clarke gradient of a
// continuous choice between them: min, max, saturate). A constant cell's gradient is 0. Clears
// r->taylor: the gradient jumps.
void gradient_hull(Cell* r, const Cell* a, const Cell* b);

// Tightens a's box enclosure where a is smooth: by its mean-value form from the midpoint, and,
// where its gradient has one sign in every variable and the corners are carried, by the hull of
// its values at the two extreme corners (exact ends for a monotone operand). Returns whether it
// changed anything.
bool tighten(Cell* a);

enum class Truth { False, True, Maybe };
inline Truth flip(Truth t) {
  return t == Truth::Maybe ? t : (t == Truth::True ? Truth::False : Truth::True);
}

// r's slot s: a's where which(s) is True, b's where False, their hull where Maybe (NaN where the
// part taken may be). Not smooth: a jump between them.
template <typename Which>
Dual blend(const Dual& a, const Dual& b, Which which) {
  Cell* r = Arena::current().fresh();
  r->constant = false;
  r->smooth = r->taylor = false;
  for (int s = 0, n = slots(r); s < n; ++s) {
    const Truth t = which(s);
    if (t == Truth::True) {
      mpfi_set(out(r, s), slot(a.get(), s));
    } else if (t == Truth::False) {
      mpfi_set(out(r, s), slot(b.get(), s));
    } else {
      mpfi_union(out(r, s), slot(a.get(), s), slot(b.get(), s));
    }
    if ((t != Truth::False && nan_in(a.get(), s)) || (t != Truth::True && nan_in(b.get(), s))) {
      flag_nan(r, s);
    }
  }
  return Dual(r);
}

void set_entire(mpfi_ptr r);  // (-inf, +inf)
void set_nan(mpfi_ptr r);
// r = n / d over the reals, outward. A d holding 0 gives an unbounded or half-bounded r (x / 0 is
// infinite); returns true when the quotient may be undefined (0 / 0 or a NaN operand).
bool divide(mpfi_ptr r, mpfi_srcptr n, mpfi_srcptr d);
// r = a^k for k >= 1, the exact real power, outward.
void power(mpfi_ptr r, mpfi_srcptr a, long k);
// out = a's interval cut to [min, max]; false when nothing of it is inside.
bool clip(mpfi_ptr out, mpfi_srcptr a, double min, double max);
// Whether a reaches outside [min, max].
bool leaves(mpfi_srcptr a, double min, double max);

}  // namespace shaderfit::verify_detail
