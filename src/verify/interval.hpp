// Interval enclosures with first and second derivatives, over MPFI (outward rounding throughout),
// for the certified bounds of verify/certify.hpp: the number type that the reference program's one
// interpreter (reference/program_evaluate.hpp) and the formula's operators are evaluated on.
//
//   Arena arena(64, 1);                       // 64-bit endpoints, one domain variable
//   ArenaScope scope(arena);                  // Dual values below live in `arena`
//   arena.begin(lo, hi, true);                // a box (lo, hi: one double per variable)
//   Dual x = Dual::variable(0);
//   Dual y = acos(x) - sqrt(Dual(1.0) - x * x);
//   y->v;      // encloses y over the box
//   y->p[0];   // encloses y at the box's midpoint; p[1..] at its corners (Arena::points())
//   y->d[0];   // encloses dy/dx over the box (when y->smooth)
//
// A Dual is a handle to a Cell of the current thread's Arena: each operation takes a fresh cell
// (allocation-free once the arena has grown to an evaluation's size) and never changes its
// operands' values, except to tighten them; handles copy freely, and arena.begin() recycles every
// cell of the previous evaluation.
//
// A cell holds values in slots: slot 0 the box (`v`), slot 1 + k the box's point k (`p[k]`: the
// midpoint, then the corners where the box has at most kCornerDims variables). The points are
// evaluated alongside the box so that each operation can tighten an operand's box enclosure
// where it matters (the mean-value form from the midpoint, and the corners where the operand is
// monotone: sqrt(p(x)) with p decreasing to exactly 0 at the box's end stays defined), and so
// that one pass gives the error at the points, for the attained maximum.
//
// What a cell promises, for every point q of the box:
//  - `v` holds the value at q, unless the value is undefined (NaN) at q; nan bit 0 is set when
//    that may happen somewhere on the box, nan bit 1 + k when it may at point k;
//  - when `smooth`, the value is Lipschitz on the box and d[i] holds the i-th component of every
//    (Clarke generalised) gradient on it, so the mean-value form f(q) in f(m) + sum d[i] (q_i -
//    m_i) holds. Kinks (abs, min, max, saturate) keep it, with the hull of the one-sided slopes;
//    jumps (an undecided select, copysign, sign, floor) and unbounded slopes clear it;
//  - when `taylor` (boxes of up to kTaylorDims variables), moreover the gradient is continuous on
//    the box, g holds it at the midpoint m and h[hessian_index(i, j)] every second derivative
//    d2f / dx_i dx_j on the box (where it exists), so the second-order Taylor form f(q) in f(m) +
//    g . (q - m) + (q - m)' H (q - m) / 2 holds. Kinks clear it;
//  - when `constant`, the value is the same at every point of the box (v; p unset) and every
//    derivative is 0 (d, g, h unset).
// Real arithmetic: a formula's constants as stored, no float32 or float64 rounding. A zero's sign
// is + (copysign(a, 0) = |a|; select and comparisons treat 0 as the reals do).
#pragma once

#include <mpfi.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "shaderfit/expr/op.hpp"
#include "shaderfit/reference/program_evaluate.hpp"

namespace shaderfit::verify {

inline constexpr int kMaxCertifyDims = 8;  // domain variables a certificate may have
inline constexpr int kCornerDims = 2;      // boxes of up to this many variables carry corners
inline constexpr int kMaxPoints = 1 + (1 << kCornerDims);  // the midpoint and the corners
inline constexpr int kTaylorDims = 3;  // boxes of up to this many variables carry second order
inline constexpr int kMaxHessian = kTaylorDims * (kTaylorDims + 1) / 2;

// Where the Hessian's entry (i, j), i <= j, is kept: the upper triangle row by row.
constexpr int hessian_index(int i, int j) { return i * kTaylorDims + j - i * (i + 1) / 2; }

struct Cell {
  __mpfi_struct v;                   // slot 0: the box
  __mpfi_struct p[kMaxPoints];       // slots 1..: the points, p[0..Arena::points())
  __mpfi_struct d[kMaxCertifyDims];  // the gradient over the box, d[0..dims)
  __mpfi_struct g[kTaylorDims];      // the gradient at the midpoint, when `taylor`
  __mpfi_struct h[kMaxHessian];      // the Hessian over the box, when `taylor`
  std::uint16_t nan = 0;             // bit s: NaN possible in slot s
  bool constant = true;              // one value over the box, gradient 0
  bool smooth = true;                // d encloses every gradient on the box (see above)
  bool taylor = true;                // with smooth: gradient continuous, h and g valid (above)
  // A comparison's result (reference programs): its operands, for select's min/max pattern.
  const Cell* cmp_lhs = nullptr;
  const Cell* cmp_rhs = nullptr;
  reference::ProgramOp cmp_op = reference::ProgramOp::Count_;

  [[nodiscard]] bool undefined() const { return (nan & 1u) != 0; }
};

// The cells of evaluations at one precision and dimension; one per certificate and thread.
class Arena {
 public:
  Arena(int precision_bits, int dims);
  ~Arena();
  Arena(const Arena&) = delete;
  Arena& operator=(const Arena&) = delete;

  // Starts an evaluation over the box [lo, hi] (dims() values each; lo == hi: a point): every
  // cell handed out before is free again. With `derivatives`, cells carry gradients and the
  // box's points (its midpoint, and its corners in up to kCornerDims variables); without, the
  // box alone.
  void begin(std::span<const double> lo, std::span<const double> hi, bool derivatives);
  Cell* fresh();  // a cell with flags cleared: constant, smooth, defined

  [[nodiscard]] int precision() const { return precision_; }
  [[nodiscard]] int dims() const { return dims_; }
  [[nodiscard]] bool derivatives() const { return derivatives_; }
  // Whether cells carry second order (derivatives, and at most kTaylorDims variables).
  [[nodiscard]] bool second_order() const { return derivatives_ && dims_ <= kTaylorDims; }
  [[nodiscard]] int points() const { return points_; }  // 0, 1 (the midpoint) or 1 + 2^dims
  [[nodiscard]] bool corners() const { return points_ > 1; }
  // Corner k (k in [0, 2^dims)) is point 1 + k: variable i at its upper end where bit i of k is 1.
  [[nodiscard]] double lo(int i) const { return lo_[static_cast<std::size_t>(i)]; }
  [[nodiscard]] double hi(int i) const { return hi_[static_cast<std::size_t>(i)]; }
  [[nodiscard]] double mid(int i) const { return mid_[static_cast<std::size_t>(i)]; }
  // [lo_i, hi_i] - mid_i, for mean-value forms.
  [[nodiscard]] mpfi_srcptr offset(int i) const { return &offset_[i]; }
  // Scratch intervals for the operations' own use (kScratch of them).
  static constexpr int kScratch = 8;
  [[nodiscard]] mpfi_ptr scratch(int i) { return &scratch_[i]; }
  [[nodiscard]] mpfi_srcptr zero() const { return &zero_; }

  // The arena of this thread's current ArenaScope (throws shaderfit::Error when none).
  static Arena& current();

 private:
  static constexpr std::size_t kChunk = 256;
  void grow();

  int precision_, dims_;
  bool derivatives_ = true;
  int points_ = 0;
  std::vector<double> lo_, hi_, mid_;
  std::vector<std::unique_ptr<Cell[]>> chunks_;
  std::size_t next_ = 0;
  __mpfi_struct offset_[kMaxCertifyDims];
  __mpfi_struct scratch_[kScratch];
  __mpfi_struct zero_;
};

// Makes `arena` the current thread's for its lifetime (scopes nest).
class ArenaScope {
 public:
  explicit ArenaScope(Arena& arena);
  ~ArenaScope();
  ArenaScope(const ArenaScope&) = delete;
  ArenaScope& operator=(const ArenaScope&) = delete;

 private:
  Arena* previous_;
};

class Dual {
 public:
  explicit Dual(double constant);                                       // exact (precision >= 53)
  explicit Dual(int constant) : Dual(static_cast<double>(constant)) {}  // T(0) in templates
  explicit Dual(Cell* cell) : cell_(cell) {}
  // Variable `axis` of the current evaluation's box, with gradient e_axis.
  static Dual variable(int axis);

  [[nodiscard]] Cell* operator->() const { return cell_; }
  [[nodiscard]] Cell& operator*() const { return *cell_; }
  [[nodiscard]] Cell* get() const { return cell_; }

 private:
  Cell* cell_;
};

// The arithmetic and C math library, with C's meaning at every point where it is defined (and
// NaN flagged where C gives NaN); division by an interval holding 0 gives an unbounded result.
Dual operator+(const Dual& a, const Dual& b);
Dual operator-(const Dual& a, const Dual& b);
Dual operator*(const Dual& a, const Dual& b);  // the same handle twice: the square
Dual operator/(const Dual& a, const Dual& b);
Dual operator-(const Dual& a);
Dual abs(const Dual& a);
Dual sqrt(const Dual& a);
Dual cbrt(const Dual& a);
Dual exp(const Dual& a);
Dual exp2(const Dual& a);
Dual expm1(const Dual& a);
Dual log(const Dual& a);
Dual log2(const Dual& a);
Dual log10(const Dual& a);
Dual log1p(const Dual& a);
Dual sin(const Dual& a);
Dual cos(const Dual& a);
Dual tan(const Dual& a);
Dual asin(const Dual& a);
Dual acos(const Dual& a);
Dual atan(const Dual& a);
Dual sinh(const Dual& a);
Dual cosh(const Dual& a);
Dual tanh(const Dual& a);
Dual asinh(const Dual& a);
Dual acosh(const Dual& a);
Dual atanh(const Dual& a);
Dual erf(const Dual& a);
Dual erfc(const Dual& a);
Dual floor(const Dual& a);
Dual ceil(const Dual& a);
Dual trunc(const Dual& a);
Dual round(const Dual& a);               // half away from zero
Dual pow(const Dual& a, const Dual& b);  // std::pow: a < 0 only with an integer constant b
Dual atan2(const Dual& y, const Dual& x);
Dual hypot(const Dual& a, const Dual& b);
Dual fmod(const Dual& a, const Dual& b);
Dual fmin(const Dual& a, const Dual& b);  // a NaN operand flags the result (C takes the other)
Dual fmax(const Dual& a, const Dual& b);
Dual copysign(const Dual& a, const Dual& b);  // |a| where b >= 0 (zero's sign +), else -|a|

// The formula operators that differ from the above (expr/op.hpp).
Dual ipow(const Dual& a, int k);                           // a^k, the exact real power
Dual gpu_pow(const Dual& a, const Dual& b);                // Op::Pow: exp2(b log2 a), NaN for a < 0
Dual saturate(const Dual& a);                              // clamp to [0, 1]
Dual sign(const Dual& a);                                  // 1, -1, or 0 at 0
Dual select(const Dual& a, const Dual& b, const Dual& c);  // a >= 0 ? b : c (NaN a: c)

// Comparisons as truth values ([0, 0], [1, 1], or [0, 1] where the box does not decide), and the
// choice between two values by one (reference::choose, found by argument-dependent lookup): the
// built-in reference templates' branches (reference/fresnel.hpp), with ProgramLogic's meaning.
Dual operator<(const Dual& a, const Dual& b);
Dual operator<=(const Dual& a, const Dual& b);
Dual operator>(const Dual& a, const Dual& b);
Dual operator>=(const Dual& a, const Dual& b);
Dual choose(const Dual& condition, const Dual& a, const Dual& b);

// The formula's operators by Op (expr/op.hpp), in real arithmetic.
Dual apply_op(Op op, int index, std::span<const Dual> operands);

// True when the cell is a constant of one number.
bool is_point(const Cell& c);

}  // namespace shaderfit::verify

namespace shaderfit::reference {

// Comparisons and logic give [0, 0], [1, 1] or [0, 1] (undecided) in each slot; a select with an
// undecided condition joins both operands (not smooth), except where it is a min or max of the
// compared operands themselves (x > 0 ? x : 0), which stays continuous. Built-in references are
// their templates (reference/builtin_evaluate.hpp) on Dual, their branches through choose().
template <>
struct ProgramLogic<verify::Dual> {
  using T = verify::Dual;
  static T compare(ProgramOp op, const T& a, const T& b);
  static T logic(ProgramOp op, const T& a, const T& b);
  static T select(const T& c, const T& a, const T& b);
  static T sign(const T& a) { return verify::sign(a); }
  static T builtin(BuiltinId id, std::span<const T> args);
  static T apply(Op op, const T& a, const T& b) {
    const T operands[] = {a, b};
    return verify::apply_op(op, 0, std::span<const T>(operands, arity(op)));
  }
};

}  // namespace shaderfit::reference
