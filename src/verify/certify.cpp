// Certified bounds by branch and bound over the domain's box (docs/reference.md, "Certification").
//
// Each box gets an enclosure of the error e = formula - reference: the natural one (e evaluated in
// intervals over the box), intersected with the mean-value form e(m) + sum G_i (x_i - m_i) (m the
// midpoint, G an enclosure of e's gradient over the box) and, where G has one sign in some
// variables, with e's enclosure on the face (corner) where it is largest and smallest: e is
// monotone there. The box's bound is the largest |.| of that enclosure. The attained error is the
// largest |e| enclosed at a point (midpoints, corners): a rigorous lower bound of the maximum. The
// box with the largest bound is split in two until that bound is within the tolerance of the
// attained error, or the budget ends.
#include "shaderfit/verify/certify.hpp"

#include <mpfi.h>
#include <mpfr.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <queue>

#include "shaderfit/core/error.hpp"
#include "verify/interval_detail.hpp"
#include "verify/interval_error.hpp"

namespace shaderfit {

namespace {

using verify::Cell;
using verify::IntervalError;
using verify::kMaxCertifyDims;
using verify_detail::nan_in;
using verify_detail::slot;

constexpr double kInf = std::numeric_limits<double>::infinity();
using Point = std::array<double, kMaxCertifyDims>;

struct Box {
  Point lo{}, hi{};
  double bound = kInf;  // |error| <= bound on the box
  int axis = 0;         // the axis to split it along
  bool operator<(const Box& other) const { return bound < other.bound; }
};

// An mpfi_t owned by RAII.
struct Interval {
  explicit Interval(int precision) { mpfi_init2(v, precision); }
  ~Interval() { mpfi_clear(v); }
  Interval(const Interval&) = delete;
  Interval& operator=(const Interval&) = delete;
  mpfi_t v;
};

std::string point_text(const reference::ReferenceFunction& ref, std::span<const double> p) {
  std::string s;
  for (std::size_t i = 0; i < p.size(); ++i) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s%s = %.9g", i ? ", " : "", ref.domain[i].name.c_str(), p[i]);
    s += buf;
  }
  return s;
}

// Slot s of a cell holds a number at every point: defined and bounded.
bool finite_slot(const Cell& c, int s) { return !nan_in(&c, s) && mpfi_bounded_p(slot(&c, s)); }

double upper(mpfr_srcptr x) { return mpfr_get_d(x, MPFR_RNDU); }

class BranchAndBound {
 public:
  BranchAndBound(IntervalError& error, const reference::ReferenceFunction& reference,
                 const CertifyOptions& options)
      : e_(error),
        ref_(reference),
        options_(options),
        dims_(error.dims()),
        mean_value_(options.precision_bits),
        term_(options.precision_bits),
        box_enclosure_(options.precision_bits),
        face_enclosure_(options.precision_bits) {
    mpfr_init2(scratch_, options.precision_bits);
    for (int i = 0; i < dims_; ++i) gradient_.emplace_back(options.precision_bits);
  }
  ~BranchAndBound() { mpfr_clear(scratch_); }
  BranchAndBound(const BranchAndBound&) = delete;
  BranchAndBound& operator=(const BranchAndBound&) = delete;

  Certificate run();

 private:
  // The error's enclosure on [lo, hi] into `out`: natural, mean-value, and the corners where it is
  // monotone; its gradient into gradient_ (when it has one: *smooth). Its points join the attained
  // maximum. Returns false when it has none (undefined or unbounded somewhere on the box).
  bool enclose(std::span<const double> lo, std::span<const double> hi, mpfi_ptr out, bool* smooth);
  void evaluate(Box& box);
  // The error at a point (slot s of the last evaluation's error cell e) joins the attained
  // maximum; false when it is undefined or unbounded there (the note says which side).
  bool attain(const Cell& e, int s, std::span<const double> point);
  double target() const {
    return std::max((1.0 + options_.tolerance) * attained_, options_.resolution * scale_);
  }
  std::span<const double> span(const Point& p) const {
    return {p.data(), static_cast<std::size_t>(dims_)};
  }

  IntervalError& e_;
  const reference::ReferenceFunction& ref_;
  const CertifyOptions& options_;
  int dims_;
  Interval mean_value_, term_, box_enclosure_, face_enclosure_;
  mpfr_t scratch_;
  std::deque<Interval> gradient_;  // deque: Interval does not move
  double attained_ = 0;
  double scale_ = 0;  // the largest |reference| met at a point
  std::vector<double> attained_point_;
  std::vector<double> trouble_point_;  // Certificate::trouble_point
  bool failed_ = false;                // undefined or infinite at a point: no finite bound
  std::string note_;
  std::size_t boxes_ = 0;
};

bool BranchAndBound::attain(const Cell& e, int s, std::span<const double> point) {
  if (!finite_slot(e, s)) {
    if (!failed_) {
      const bool formula_bad = !finite_slot(e_.formula_value(), s);
      const bool reference_bad = !finite_slot(e_.reference_value(), s);
      note_ = std::string(reference_bad && !formula_bad ? "the reference" : "the formula") +
              " may be undefined (NaN) or infinite at " + point_text(ref_, point);
      trouble_point_.assign(point.begin(), point.end());
    }
    failed_ = true;
    return false;
  }
  mpfi_mig(scratch_, slot(&e_.reference_value(), s));
  scale_ = std::max(scale_, mpfr_get_d(scratch_, MPFR_RNDD));
  mpfi_mig(scratch_, slot(&e, s));
  const double v = mpfr_get_d(scratch_, MPFR_RNDD);
  if (v > attained_ || attained_point_.empty()) {
    attained_ = std::max(attained_, v);
    attained_point_.assign(point.begin(), point.end());
  }
  return true;
}

bool BranchAndBound::enclose(std::span<const double> lo, std::span<const double> hi, mpfi_ptr out,
                             bool* smooth) {
  *smooth = false;
  const std::size_t n = lo.size();
  Point mid{};
  bool degenerate = true;
  for (std::size_t i = 0; i < n; ++i) {
    mid[i] = lo[i] + 0.5 * (hi[i] - lo[i]);
    degenerate = degenerate && lo[i] == hi[i];
  }
  if (degenerate) {  // a point: its value alone
    const Cell& c = e_.at_point(lo);
    if (!attain(c, 0, lo)) return false;
    mpfi_set(out, &c.v);
    return true;
  }
  ++boxes_;
  const Cell& b = e_.over_box(lo, hi);
  const verify::Arena& arena = e_.arena();
  // The points first: where the formula or the reference is infinite or undefined at one, the
  // search ends there.
  for (int k = 0; k < arena.points(); ++k) {
    Point p = mid;
    for (std::size_t i = 0; i < n && k > 0; ++i) p[i] = ((k - 1) >> i) & 1 ? hi[i] : lo[i];
    if (!attain(b, 1 + k, span(p))) return false;
  }
  if (!finite_slot(b, 0)) return false;
  mpfi_set(out, &b.v);
  if (!b.smooth) return true;
  *smooth = true;
  for (std::size_t i = 0; i < n; ++i) {
    if (b.constant) {
      mpfi_set_ui(gradient_[i].v, 0);
    } else {
      mpfi_set(gradient_[i].v, &b.d[i]);
    }
  }
  if (b.constant) return true;
  // The mean-value form: e(m) + sum G_i ([lo_i, hi_i] - m_i).
  mpfi_set(mean_value_.v, &b.p[0]);
  for (std::size_t i = 0; i < n; ++i) {
    mpfi_mul(term_.v, arena.offset(static_cast<int>(i)), gradient_[i].v);
    mpfi_add(mean_value_.v, mean_value_.v, term_.v);
  }
  if (mpfi_bounded_p(mean_value_.v)) {
    mpfi_intersect(mean_value_.v, out, mean_value_.v);
    if (!mpfi_is_empty(mean_value_.v)) mpfi_set(out, mean_value_.v);
  }
  // The second-order Taylor form: e(m) + sum g_i o_i + sum_i h_ii o_i^2 / 2 + sum_i<j h_ij o_i o_j
  // (o_i = [lo_i, hi_i] - m_i, g the gradient at m, h the Hessian over the box).
  if (b.taylor && arena.second_order()) {
    mpfi_set(mean_value_.v, &b.p[0]);
    for (std::size_t i = 0; i < n; ++i) {
      const int ii = static_cast<int>(i);
      mpfi_mul(term_.v, arena.offset(ii), &b.g[i]);
      mpfi_add(mean_value_.v, mean_value_.v, term_.v);
      for (std::size_t j = i; j < n; ++j) {
        const int jj = static_cast<int>(j);
        if (i == j) {
          mpfi_sqr(term_.v, arena.offset(ii));
          mpfi_div_2ui(term_.v, term_.v, 1);
        } else {
          mpfi_mul(term_.v, arena.offset(ii), arena.offset(jj));
        }
        mpfi_mul(term_.v, term_.v, &b.h[verify::hessian_index(ii, jj)]);
        mpfi_add(mean_value_.v, mean_value_.v, term_.v);
      }
    }
    if (mpfi_bounded_p(mean_value_.v)) {
      mpfi_intersect(mean_value_.v, out, mean_value_.v);
      if (!mpfi_is_empty(mean_value_.v)) mpfi_set(out, mean_value_.v);
    }
  }
  // Monotone in every variable (of a box with corners): the extreme corners are the ends.
  if (!arena.corners()) return true;
  int low = 0, high = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (lo[i] == hi[i]) continue;
    if (mpfr_sgn(&gradient_[i].v->left) > 0) {
      high |= 1 << i;
    } else if (mpfr_sgn(&gradient_[i].v->right) < 0) {
      low |= 1 << i;
    } else {
      return true;
    }
  }
  mpfr_min(&out->right, &out->right, &b.p[1 + high].right, MPFR_RNDU);
  mpfr_max(&out->left, &out->left, &b.p[1 + low].left, MPFR_RNDD);
  return true;
}

void BranchAndBound::evaluate(Box& box) {
  const std::span<const double> lo = span(box.lo), hi = span(box.hi);
  // The axis to split: the widest relative to the domain, or where the error changes most.
  box.axis = 0;
  double widest = -1;
  for (int i = 0; i < dims_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double w = (hi[k] - lo[k]) / ref_.domain[k].width();
    if (w > widest) widest = w, box.axis = i;
  }
  bool smooth = false;
  if (!enclose(lo, hi, box_enclosure_.v, &smooth)) {
    box.bound = kInf;
    return;
  }
  if (smooth) {
    double influence = -1;
    int monotone = 0, flat = 0;
    for (int i = 0; i < dims_; ++i) {
      const auto k = static_cast<std::size_t>(i);
      mpfi_mag(scratch_, gradient_[k].v);
      const double w = upper(scratch_) * (hi[k] - lo[k]);
      if (w > influence && hi[k] > lo[k]) influence = w, box.axis = i;
      if (!mpfi_has_zero(gradient_[k].v)) ++monotone;
      if (hi[k] == lo[k]) ++flat;
    }
    // Monotone in some variables but not all (all: enclose used the corners): e's largest value
    // is on the face where it grows to, its smallest on the opposite one.
    const bool all = monotone + flat == dims_ && e_.arena().corners();
    if (monotone > 0 && !all) {
      std::array<int, kMaxCertifyDims> direction{};  // +1, -1, or 0 (not monotone)
      for (int i = 0; i < dims_; ++i) {
        mpfi_srcptr g = gradient_[static_cast<std::size_t>(i)].v;
        direction[static_cast<std::size_t>(i)] =
            mpfi_has_zero(g) ? 0 : (mpfr_sgn(&g->left) > 0 ? 1 : -1);
      }
      for (int side = 0; side < 2; ++side) {  // 0: the largest value, 1: the smallest
        Point flo = box.lo, fhi = box.hi;
        for (std::size_t k = 0; k < static_cast<std::size_t>(dims_); ++k) {
          if (direction[k] == 0) continue;
          const bool up = (direction[k] > 0) == (side == 0);
          flo[k] = fhi[k] = up ? hi[k] : lo[k];
        }
        bool face_smooth = false;
        if (!enclose(span(flo), span(fhi), face_enclosure_.v, &face_smooth)) break;
        if (side == 0) {
          mpfr_min(&box_enclosure_.v->right, &box_enclosure_.v->right, &face_enclosure_.v->right,
                   MPFR_RNDU);
        } else {
          mpfr_max(&box_enclosure_.v->left, &box_enclosure_.v->left, &face_enclosure_.v->left,
                   MPFR_RNDD);
        }
      }
    }
  }
  mpfi_mag(scratch_, box_enclosure_.v);
  box.bound = upper(scratch_);
}

Certificate BranchAndBound::run() {
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  Certificate c;
  Box root;
  for (std::size_t i = 0; i < static_cast<std::size_t>(dims_); ++i) {
    root.lo[i] = ref_.domain[i].lo;
    root.hi[i] = ref_.domain[i].hi;
  }
  std::priority_queue<Box> queue;
  double settled = 0;  // the largest bound of the boxes dropped as good enough
  evaluate(root);
  if (!failed_) queue.push(root);
  while (!failed_ && !queue.empty()) {
    if (queue.top().bound <= target()) break;
    if (boxes_ >= options_.max_boxes || elapsed() >= options_.time_limit_s) {
      note_ = "the budget ended after " + std::to_string(boxes_) + " boxes";
      break;
    }
    Box box = queue.top();
    const auto a = static_cast<std::size_t>(box.axis);
    const double mid = box.lo[a] + 0.5 * (box.hi[a] - box.lo[a]);
    if (!(mid > box.lo[a] && mid < box.hi[a])) {  // as narrow as doubles go
      Point centre{};
      for (std::size_t i = 0; i < static_cast<std::size_t>(dims_); ++i) {
        centre[i] = box.lo[i] + 0.5 * (box.hi[i] - box.lo[i]);
      }
      if (std::isinf(box.bound)) trouble_point_.assign(centre.begin(), centre.begin() + dims_);
      note_ = std::isinf(box.bound)
                  ? "no finite bound near " + point_text(ref_, span(centre)) +
                        ": the formula or the reference may be unbounded or undefined there"
                  : "the boxes near " + point_text(ref_, span(centre)) +
                        " are as narrow as doubles go (a jump there?)";
      break;
    }
    queue.pop();
    Box halves[2] = {box, box};
    halves[0].hi[a] = mid;
    halves[1].lo[a] = mid;
    for (Box& h : halves) {
      evaluate(h);
      if (failed_) break;
      if (h.bound <= target()) {
        settled = std::max(settled, h.bound);
      } else {
        queue.push(h);
      }
    }
  }
  double bound = settled;
  if (failed_) bound = kInf;
  if (!queue.empty()) bound = std::max(bound, queue.top().bound);
  c.bound = std::max(bound, attained_);
  c.attained = attained_;
  c.attained_point = attained_point_;
  if (std::isinf(c.bound)) c.trouble_point = trouble_point_;
  c.converged = !failed_ && c.bound <= target();
  c.boxes = boxes_;
  c.time_s = elapsed();
  if (!c.converged) c.note = note_.empty() ? "no finite bound found" : note_;
  return c;
}

}  // namespace

Certificate certify(const Expression& formula, const std::vector<std::string>& inputs,
                    const reference::ReferenceFunction& reference, const CertifyOptions& options) {
  const SourceLocation where{"CertifyOptions"};
  if (!(options.tolerance >= 0)) throw Error("tolerance must be >= 0", where);
  if (!(options.resolution >= 0)) throw Error("resolution must be >= 0", where);
  if (!(options.time_limit_s > 0)) throw Error("time_limit_s must be > 0", where);
  if (options.precision_bits < 53 || options.precision_bits > 4096) {
    throw Error("precision_bits must be in [53, 4096]", where);
  }
  for (const reference::DomainAxis& axis : reference.domain) {
    if (!(std::isfinite(axis.lo) && std::isfinite(axis.hi) && axis.lo < axis.hi)) {
      throw Error("the domain of '" + axis.name + "' must be finite and not empty",
                  SourceLocation{"certify"});
    }
  }
  IntervalError error(formula, inputs, reference, options.precision_bits);
  BranchAndBound bb(error, reference, options);
  return bb.run();
}

}  // namespace shaderfit
