// The arena, the handles, the shared helpers and the arithmetic of verify/interval.hpp.
#include "verify/interval.hpp"

#include <mpfr.h>

#include "shaderfit/core/error.hpp"
#include "verify/interval_detail.hpp"

namespace shaderfit::verify {

namespace {
thread_local Arena* g_current = nullptr;
}  // namespace

Arena::Arena(int precision_bits, int dims)
    : precision_(precision_bits),
      dims_(dims),
      lo_(static_cast<std::size_t>(dims)),
      hi_(static_cast<std::size_t>(dims)),
      mid_(static_cast<std::size_t>(dims)) {
  for (auto& s : scratch_) mpfi_init2(&s, precision_);
  for (auto& s : offset_) mpfi_init2(&s, precision_);
  mpfi_init2(&zero_, precision_);
  mpfi_set_ui(&zero_, 0);
}

Arena::~Arena() {
  for (auto& chunk : chunks_) {
    for (std::size_t k = 0; k < kChunk; ++k) {
      Cell& c = chunk[k];
      mpfi_clear(&c.v);
      for (auto& p : c.p) mpfi_clear(&p);
      for (int i = 0; i < dims_; ++i) mpfi_clear(&c.d[i]);
      for (auto& g : c.g) mpfi_clear(&g);
      for (auto& h : c.h) mpfi_clear(&h);
    }
  }
  for (auto& s : scratch_) mpfi_clear(&s);
  for (auto& s : offset_) mpfi_clear(&s);
  mpfi_clear(&zero_);
}

void Arena::grow() {
  auto chunk = std::make_unique<Cell[]>(kChunk);
  for (std::size_t k = 0; k < kChunk; ++k) {
    Cell& c = chunk[k];
    mpfi_init2(&c.v, precision_);
    for (auto& p : c.p) mpfi_init2(&p, precision_);
    for (int i = 0; i < dims_; ++i) mpfi_init2(&c.d[i], precision_);
    for (auto& g : c.g) mpfi_init2(&g, precision_);
    for (auto& h : c.h) mpfi_init2(&h, precision_);
  }
  chunks_.push_back(std::move(chunk));
}

void Arena::begin(std::span<const double> lo, std::span<const double> hi, bool derivatives) {
  derivatives_ = derivatives;
  points_ = derivatives ? (dims_ <= kCornerDims ? 1 + (1 << dims_) : 1) : 0;
  next_ = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(dims_); ++i) {
    lo_[i] = lo[i];
    hi_[i] = hi[i];
    mid_[i] = lo[i] + 0.5 * (hi[i] - lo[i]);
    mpfi_interv_d(&offset_[i], lo[i], hi[i]);
    mpfi_sub_d(&offset_[i], &offset_[i], mid_[i]);
  }
}

Cell* Arena::fresh() {
  const std::size_t chunk = next_ / kChunk;
  if (chunk == chunks_.size()) grow();
  Cell* c = &chunks_[chunk][next_ % kChunk];
  ++next_;
  c->nan = 0;
  c->constant = true;
  c->smooth = true;
  c->taylor = true;
  c->cmp_lhs = c->cmp_rhs = nullptr;
  c->cmp_op = reference::ProgramOp::Count_;
  return c;
}

Arena& Arena::current() {
  if (g_current == nullptr) throw Error("interval evaluation outside an ArenaScope (internal)");
  return *g_current;
}

ArenaScope::ArenaScope(Arena& arena) : previous_(g_current) { g_current = &arena; }
ArenaScope::~ArenaScope() { g_current = previous_; }

Dual::Dual(double constant) : cell_(Arena::current().fresh()) {
  mpfi_set_d(&cell_->v, constant);
  if (constant != constant) cell_->nan = 1;
}

Dual Dual::variable(int axis) {
  Arena& arena = Arena::current();
  Cell* c = arena.fresh();
  const double lo = arena.lo(axis), hi = arena.hi(axis);
  mpfi_interv_d(&c->v, lo, hi);
  if (lo == hi) return Dual(c);  // one value on the box: constant along the others
  c->constant = false;
  c->smooth = arena.derivatives();
  c->taylor = arena.second_order();
  if (arena.derivatives()) {
    for (int i = 0; i < arena.dims(); ++i) mpfi_set_ui(&c->d[i], i == axis ? 1 : 0);
  }
  if (c->taylor) {
    for (int i = 0; i < arena.dims(); ++i) mpfi_set_ui(&c->g[i], i == axis ? 1 : 0);
    for (auto& h : c->h) mpfi_set_ui(&h, 0);
  }
  for (int k = 0; k < arena.points(); ++k) {
    // Point 0 is the midpoint, point 1 + j corner j.
    const double x = k == 0 ? arena.mid(axis) : (((k - 1) >> axis) & 1 ? hi : lo);
    mpfi_set_d(&c->p[k], x);
  }
  return Dual(c);
}

bool is_point(const Cell& c) {
  return c.constant && c.nan == 0 && mpfr_equal_p(&c.v.left, &c.v.right) != 0;
}

}  // namespace shaderfit::verify

namespace shaderfit::verify_detail {

using namespace shaderfit::verify;  // the area's public names

int slots(const Cell* c) { return c->constant ? 1 : 1 + Arena::current().points(); }

Cell* result(const Cell* a) {
  Cell* r = Arena::current().fresh();
  r->nan = a->nan;
  r->constant = a->constant;
  r->smooth = a->smooth;
  r->taylor = a->taylor;
  return r;
}

Cell* result(const Cell* a, const Cell* b) {
  Cell* r = Arena::current().fresh();
  r->constant = a->constant && b->constant;
  r->smooth = a->smooth && b->smooth;
  r->taylor = a->taylor && b->taylor;
  for (int s = 0, n = slots(r); s < n; ++s) {
    if (nan_in(a, s) || nan_in(b, s)) r->nan |= static_cast<std::uint16_t>(1u << s);
  }
  return r;
}

void flag_nan(Cell* r, int s) { r->nan |= static_cast<std::uint16_t>(1u | (1u << s)); }

void settle(Cell* r) {
  for (int s = 0, n = slots(r); s < n; ++s) {
    if (mpfi_nan_p(out(r, s))) flag_nan(r, s);
  }
  if (r->nan != 0) r->nan |= 1u;
}

bool wants_gradient(const Cell* r) {
  return Arena::current().derivatives() && !r->constant && r->smooth && !r->undefined();
}

bool wants_taylor(const Cell* r) {
  return wants_gradient(r) && r->taylor && Arena::current().second_order();
}

mpfi_srcptr D(const Cell* c, int i) { return c->constant ? Arena::current().zero() : &c->d[i]; }
mpfi_srcptr G(const Cell* c, int i) { return c->constant ? Arena::current().zero() : &c->g[i]; }
mpfi_srcptr H(const Cell* c, int k) { return c->constant ? Arena::current().zero() : &c->h[k]; }

void chain(Cell* r, const Cell* a, mpfi_srcptr f1, mpfi_srcptr f2, mpfi_srcptr f1m) {
  if (!wants_gradient(r)) return;
  if (!mpfi_bounded_p(f1)) {
    r->smooth = r->taylor = false;
    return;
  }
  Arena& arena = Arena::current();
  const int n = arena.dims();
  for (int i = 0; i < n; ++i) mpfi_mul(&r->d[i], f1, &a->d[i]);
  if (!wants_taylor(r)) return;
  if (f2 == nullptr || f1m == nullptr || !mpfi_bounded_p(f2) || !mpfi_bounded_p(f1m)) {
    r->taylor = false;
    return;
  }
  // h_ij = f'' a_i a_j + f' a_ij; g_i = f'(a(m)) a_i(m).
  mpfi_ptr t = arena.scratch(Arena::kScratch - 1);
  for (int i = 0; i < n; ++i) {
    for (int j = i; j < n; ++j) {
      const int k = hessian_index(i, j);
      if (i == j) {
        mpfi_sqr(t, &a->d[i]);
      } else {
        mpfi_mul(t, &a->d[i], &a->d[j]);
      }
      mpfi_mul(t, t, f2);
      mpfi_mul(&r->h[k], f1, &a->h[k]);
      mpfi_add(&r->h[k], &r->h[k], t);
    }
    mpfi_mul(&r->g[i], f1m, &a->g[i]);
  }
}

void chain_linear(Cell* r, const Cell* a, mpfi_srcptr ca, const Cell* b, mpfi_srcptr cb) {
  if (!wants_gradient(r)) return;
  Arena& arena = Arena::current();
  mpfi_ptr t = arena.scratch(Arena::kScratch - 1);
  // out = ca x + cb y, for one derivative of each operand.
  auto combine = [&](mpfi_ptr out, mpfi_srcptr x, mpfi_srcptr y) {
    if (ca == nullptr) {
      mpfi_set(out, x);
    } else {
      mpfi_mul(out, ca, x);
    }
    if (cb == nullptr) {
      mpfi_add(out, out, y);
    } else {
      mpfi_mul(t, cb, y);
      mpfi_add(out, out, t);
    }
  };
  for (int i = 0; i < arena.dims(); ++i) combine(&r->d[i], D(a, i), D(b, i));
  if (!wants_taylor(r)) return;
  for (int i = 0; i < arena.dims(); ++i) combine(&r->g[i], G(a, i), G(b, i));
  for (int i = 0; i < arena.dims(); ++i) {
    for (int j = i; j < arena.dims(); ++j) {
      const int k = hessian_index(i, j);
      combine(&r->h[k], H(a, k), H(b, k));
    }
  }
}

void chain2(Cell* r, const Cell* a, mpfi_srcptr fa, const Cell* b, mpfi_srcptr fb) {
  r->taylor = false;
  if (!wants_gradient(r)) return;
  if ((!a->constant && !mpfi_bounded_p(fa)) || (!b->constant && !mpfi_bounded_p(fb))) {
    r->smooth = false;
    return;
  }
  Arena& arena = Arena::current();
  mpfi_ptr t = arena.scratch(Arena::kScratch - 1);
  for (int i = 0; i < arena.dims(); ++i) {
    mpfi_mul(&r->d[i], fa, D(a, i));
    mpfi_mul(t, fb, D(b, i));
    mpfi_add(&r->d[i], &r->d[i], t);
  }
}

void gradient_hull(Cell* r, const Cell* a, const Cell* b) {
  r->taylor = false;
  if (!wants_gradient(r)) return;
  Arena& arena = Arena::current();
  for (int i = 0; i < arena.dims(); ++i) mpfi_union(&r->d[i], D(a, i), D(b, i));
}

bool tighten(Cell* a) {
  Arena& arena = Arena::current();
  if (!wants_gradient(a) || arena.points() == 0 || (a->nan & 2u) != 0) return false;
  mpfi_ptr t = arena.scratch(Arena::kScratch - 2), u = arena.scratch(Arena::kScratch - 1);
  // The mean-value form from the midpoint.
  mpfi_set(t, &a->p[0]);
  for (int i = 0; i < arena.dims(); ++i) {
    mpfi_mul(u, &a->d[i], arena.offset(i));
    mpfi_add(t, t, u);
  }
  bool changed = false;
  if (mpfi_bounded_p(t)) {
    mpfi_intersect(t, t, &a->v);
    if (!mpfi_is_empty(t) && !mpfi_nan_p(t)) {
      changed = mpfr_cmp(lo(t), lo(&a->v)) > 0 || mpfr_cmp(hi(t), hi(&a->v)) < 0;
      mpfi_set(&a->v, t);
    }
  }
  // Monotone in every variable: the values at the extreme corners are the ends.
  if (!arena.corners()) return changed;
  int low = 0, high = 0;
  for (int i = 0; i < arena.dims(); ++i) {
    const int sl = mpfr_sgn(lo(&a->d[i])), sh = mpfr_sgn(hi(&a->d[i]));
    if (arena.lo(i) == arena.hi(i)) continue;  // a flat axis: either end
    if (sl > 0) {
      high |= 1 << i;
    } else if (sh < 0) {
      low |= 1 << i;
    } else {
      return changed;
    }
  }
  if ((a->nan >> (2 + low) & 1u) || (a->nan >> (2 + high) & 1u)) return changed;
  mpfi_union(t, &a->p[1 + low], &a->p[1 + high]);
  mpfi_intersect(t, t, &a->v);
  if (mpfi_is_empty(t) || mpfi_nan_p(t)) return changed;
  changed = changed || mpfr_cmp(lo(t), lo(&a->v)) > 0 || mpfr_cmp(hi(t), hi(&a->v)) < 0;
  mpfi_set(&a->v, t);
  return changed;
}

void set_entire(mpfi_ptr r) {
  mpfr_set_inf(lo(r), -1);
  mpfr_set_inf(hi(r), 1);
}

void set_nan(mpfi_ptr r) {
  mpfr_set_nan(lo(r));
  mpfr_set_nan(hi(r));
}

bool divide(mpfi_ptr r, mpfi_srcptr n, mpfi_srcptr d) {
  if (mpfi_nan_p(n) || mpfi_nan_p(d)) {
    set_nan(r);
    return true;
  }
  const int dl = mpfr_sgn(lo(d)), dh = mpfr_sgn(hi(d));
  if (dl > 0 || dh < 0) {
    mpfi_div(r, n, d);
    return false;
  }
  const int nl = mpfr_sgn(lo(n)), nh = mpfr_sgn(hi(n));
  const bool n_has_zero = nl <= 0 && nh >= 0;
  if (n_has_zero || (dl < 0 && dh > 0) || (dl == 0 && dh == 0)) {
    set_entire(r);
    return n_has_zero;
  }
  // d is [0, h] or [l, 0] with h > 0 > l, and n of one sign: one end of n / d is unbounded. The
  // finite end first, so that r may be n or d.
  if (dl == 0) {
    if (nl > 0) {
      mpfr_div(lo(r), lo(n), hi(d), MPFR_RNDD);
      mpfr_set_inf(hi(r), 1);
    } else {
      mpfr_div(hi(r), hi(n), hi(d), MPFR_RNDU);
      mpfr_set_inf(lo(r), -1);
    }
  } else if (nl > 0) {
    mpfr_div(hi(r), lo(n), lo(d), MPFR_RNDU);
    mpfr_set_inf(lo(r), -1);
  } else {
    mpfr_div(lo(r), hi(n), lo(d), MPFR_RNDD);
    mpfr_set_inf(hi(r), 1);
  }
  return false;
}

void power(mpfi_ptr r, mpfi_srcptr a, long k) {
  if (k % 2 != 0 || mpfr_sgn(lo(a)) >= 0) {  // odd, or even on [0, inf): increasing
    mpfr_pow_si(lo(r), lo(a), k, MPFR_RNDD);
    mpfr_pow_si(hi(r), hi(a), k, MPFR_RNDU);
  } else if (mpfr_sgn(hi(a)) <= 0) {  // even on (-inf, 0]: decreasing
    mpfr_pow_si(hi(r), lo(a), k, MPFR_RNDU);
    mpfr_pow_si(lo(r), hi(a), k, MPFR_RNDD);
  } else {  // even, straddling 0: [0, max(|lo|, |hi|)^k]
    mpfr_srcptr far = mpfr_cmpabs(lo(a), hi(a)) > 0 ? lo(a) : hi(a);
    mpfr_pow_si(hi(r), far, k, MPFR_RNDU);
    mpfr_set_ui(lo(r), 0, MPFR_RNDD);
  }
}

bool leaves(mpfi_srcptr a, double min, double max) {
  return mpfr_cmp_d(lo(a), min) < 0 || mpfr_cmp_d(hi(a), max) > 0 || mpfi_nan_p(a);
}

bool clip(mpfi_ptr out, mpfi_srcptr a, double min, double max) {
  if (mpfi_nan_p(a) || mpfr_cmp_d(hi(a), min) < 0 || mpfr_cmp_d(lo(a), max) > 0) return false;
  mpfi_set(out, a);
  if (mpfr_cmp_d(lo(a), min) < 0) mpfr_set_d(lo(out), min, MPFR_RNDD);
  if (mpfr_cmp_d(hi(a), max) > 0) mpfr_set_d(hi(out), max, MPFR_RNDU);
  return true;
}

}  // namespace shaderfit::verify_detail

namespace shaderfit::verify {

using namespace verify_detail;

Dual operator+(const Dual& a, const Dual& b) {
  Cell* r = result(a.get(), b.get());
  for (int s = 0, n = slots(r); s < n; ++s) mpfi_add(out(r, s), slot(a.get(), s), slot(b.get(), s));
  settle(r);
  chain_linear(r, a.get(), nullptr, b.get(), nullptr);
  return Dual(r);
}

Dual operator-(const Dual& a, const Dual& b) {
  Cell* r = result(a.get(), b.get());
  for (int s = 0, n = slots(r); s < n; ++s) mpfi_sub(out(r, s), slot(a.get(), s), slot(b.get(), s));
  settle(r);
  if (wants_gradient(r)) {
    mpfi_ptr m1 = Arena::current().scratch(1);
    mpfi_set_si(m1, -1);
    chain_linear(r, a.get(), nullptr, b.get(), m1);
  }
  return Dual(r);
}

Dual operator-(const Dual& a) {
  Cell* r = result(a.get());
  for (int s = 0, n = slots(r); s < n; ++s) mpfi_neg(out(r, s), slot(a.get(), s));
  if (wants_gradient(r)) {
    mpfi_ptr m1 = Arena::current().scratch(1);
    mpfi_set_si(m1, -1);
    chain(r, a.get(), m1, Arena::current().zero(), m1);
  }
  return Dual(r);
}

Dual operator*(const Dual& a, const Dual& b) {
  Cell* r = result(a.get(), b.get());
  Arena& arena = Arena::current();
  if (a.get() == b.get()) {  // the square: tight where a straddles 0
    for (int s = 0, n = slots(r); s < n; ++s) mpfi_sqr(out(r, s), slot(a.get(), s));
    settle(r);
    if (wants_gradient(r)) {  // 2 a, 2, and 2 a(m)
      mpfi_ptr f1 = arena.scratch(1), f2 = arena.scratch(2), f1m = arena.scratch(3);
      mpfi_mul_ui(f1, &a->v, 2);
      mpfi_set_ui(f2, 2);
      mpfi_mul_ui(f1m, slot(a.get(), 1), 2);
      chain(r, a.get(), f1, f2, f1m);
    }
    return Dual(r);
  }
  for (int s = 0, n = slots(r); s < n; ++s) mpfi_mul(out(r, s), slot(a.get(), s), slot(b.get(), s));
  settle(r);
  if (!wants_gradient(r)) return Dual(r);
  if (a->constant || b->constant) {  // a constant factor: linear in the other
    const Cell* c = a->constant ? a.get() : b.get();
    const Cell* x = a->constant ? b.get() : a.get();
    chain(r, x, &c->v, arena.zero(), &c->v);
    return Dual(r);
  }
  // d_i = a_i B + A b_i; h_ij = a_ij B + a_i b_j + a_j b_i + A b_ij; g_i = a_i(m) b(m) + a(m)
  // b_i(m)
  const int n = arena.dims();
  mpfi_ptr t = arena.scratch(Arena::kScratch - 1), u = arena.scratch(Arena::kScratch - 2);
  mpfi_srcptr av = &a->v, bv = &b->v;
  for (int i = 0; i < n; ++i) {
    mpfi_mul(&r->d[i], &a->d[i], bv);
    mpfi_mul(t, av, &b->d[i]);
    mpfi_add(&r->d[i], &r->d[i], t);
  }
  if (!wants_taylor(r)) return Dual(r);
  for (int i = 0; i < n; ++i) {
    for (int j = i; j < n; ++j) {
      const int k = hessian_index(i, j);
      mpfi_mul(&r->h[k], &a->h[k], bv);
      mpfi_mul(t, av, &b->h[k]);
      mpfi_add(&r->h[k], &r->h[k], t);
      mpfi_mul(t, &a->d[i], &b->d[j]);
      mpfi_mul(u, &a->d[j], &b->d[i]);
      mpfi_add(t, t, u);
      mpfi_add(&r->h[k], &r->h[k], t);
    }
    mpfi_mul(&r->g[i], &a->g[i], slot(b.get(), 1));
    mpfi_mul(t, slot(a.get(), 1), &b->g[i]);
    mpfi_add(&r->g[i], &r->g[i], t);
  }
  return Dual(r);
}

Dual operator/(const Dual& a, const Dual& b) {
  if (mpfi_has_zero(&b->v)) tighten(b.get());
  Cell* r = result(a.get(), b.get());
  for (int s = 0, n = slots(r); s < n; ++s) {
    if (divide(out(r, s), slot(a.get(), s), slot(b.get(), s))) flag_nan(r, s);
  }
  settle(r);
  if (mpfi_has_zero(&b->v)) r->smooth = r->taylor = false;
  if (!wants_gradient(r)) return Dual(r);
  // From a = q b: q_i = (a_i - Q b_i) / B, q_ij = (a_ij - q_i b_j - q_j b_i - Q b_ij) / B, and
  // at the midpoint g_i = (a_i(m) - q(m) b_i(m)) / b(m).
  Arena& arena = Arena::current();
  const int n = arena.dims();
  mpfi_ptr inv = arena.scratch(1), t = arena.scratch(Arena::kScratch - 1),
           u = arena.scratch(Arena::kScratch - 2);
  mpfi_inv(inv, &b->v);
  for (int i = 0; i < n; ++i) {
    mpfi_mul(t, &r->v, D(b.get(), i));
    mpfi_sub(t, D(a.get(), i), t);
    mpfi_mul(&r->d[i], t, inv);
  }
  if (!wants_taylor(r)) return Dual(r);
  mpfi_srcptr bm = slot(b.get(), 1);
  if (mpfi_has_zero(bm)) {
    r->taylor = false;
    return Dual(r);
  }
  for (int i = 0; i < n; ++i) {
    for (int j = i; j < n; ++j) {
      const int k = hessian_index(i, j);
      mpfi_mul(t, &r->v, H(b.get(), k));
      mpfi_sub(t, H(a.get(), k), t);
      mpfi_mul(u, &r->d[i], D(b.get(), j));
      mpfi_sub(t, t, u);
      mpfi_mul(u, &r->d[j], D(b.get(), i));
      mpfi_sub(t, t, u);
      mpfi_mul(&r->h[k], t, inv);
    }
    mpfi_mul(t, slot(r, 1), G(b.get(), i));
    mpfi_sub(t, G(a.get(), i), t);
    mpfi_div(&r->g[i], t, bm);
  }
  return Dual(r);
}

Dual ipow(const Dual& a, int k) {
  if (k == 1) return a;
  if (k == 0) return Dual(1.0);
  const long n = k < 0 ? -static_cast<long>(k) : k;
  if (k < 0 && mpfi_has_zero(&a->v)) tighten(a.get());
  Cell* r = result(a.get());
  Arena& arena = Arena::current();
  mpfi_ptr p = arena.scratch(1), one = arena.scratch(2);
  mpfi_set_ui(one, 1);
  for (int s = 0, m = slots(r); s < m; ++s) {
    if (k > 0) {
      power(out(r, s), slot(a.get(), s), n);
    } else {
      power(p, slot(a.get(), s), n);
      if (divide(out(r, s), one, p)) flag_nan(r, s);
    }
  }
  settle(r);
  if (k < 0 && mpfi_has_zero(&a->v)) r->smooth = false;
  if (wants_gradient(r)) {  // k a^(k-1), k (k-1) a^(k-2), over the box and at the midpoint
    mpfi_ptr f1 = arena.scratch(3), f2 = arena.scratch(4), f1m = arena.scratch(5);
    auto power_of = [&](mpfi_ptr o, mpfi_srcptr x, long e) {  // x^e for any e != 0
      if (e > 0) {
        power(o, x, e);
      } else {
        power(p, x, -e);
        mpfi_inv(o, p);
      }
    };
    const long k1 = static_cast<long>(k) - 1, k2 = static_cast<long>(k) - 2;
    power_of(f1, &a->v, k1);
    mpfi_mul_si(f1, f1, k);
    power_of(f1m, slot(a.get(), 1), k1);
    mpfi_mul_si(f1m, f1m, k);
    if (k2 == 0) {
      mpfi_set_ui(f2, 1);
    } else {
      power_of(f2, &a->v, k2);
    }
    mpfi_mul_si(f2, f2, static_cast<long>(k) * k1);
    chain(r, a.get(), f1, f2, f1m);
  }
  return Dual(r);
}

}  // namespace shaderfit::verify
