// Column kernels of the bottom-up enumeration (internal).
//
// A candidate's "screen column" holds its float32 values on the screen rows (a multiple of 8 of
// them, at least 16). These kernels compute a column from its operands' columns, key it for
// deduplication (a hash of its rows that ignores the overall sign and float noise), and
// measure it (finiteness, and the loss of the column and of its negation against the target).
// Keying comes first and is cheap, so duplicates -- most candidates -- are dropped before the
// loss pass. Compiled for AVX2 and for the baseline ISA, picked at load time; both give the
// same bits (no contraction).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "shaderfit/eval/loss.hpp"
#include "shaderfit/expr/op.hpp"

namespace shaderfit::search_detail {

// What an enumerated candidate computes from its operands a and b (b may be negated):
enum class EKind : std::uint8_t {
  Var,       // input variable
  Literal,   // literal constant
  Unary,     // op(a) or op(-a)
  IPow,      // a^k
  AddSub,    // a + b or a - b
  Mul,       // a * b
  Div,       // a / b
  Min,       // min(a, +-b)
  Max,       // max(a, +-b)
  Pow,       // pow(a, +-b)
  FusedAdd,  // m +- b where m's last instruction is a multiply (one FMA)
  CopySign,  // copysign(a, +-b)
  Atan2,     // atan2(a, +-b)
};

// The dedup key (column_key): its head, the first rows, sets the sign and the noise floor and is
// rounded to kKeyHeadBits mantissa bits; the rows after it to kKeyTailBits, its sum rotated by
// kKeyRotation bits from one pair of 8-row blocks to the next.
inline constexpr std::size_t kKeyHeadRows = 16;
inline constexpr int kKeyHeadBits = 10;
inline constexpr int kKeyTailBits = 6;
inline constexpr int kKeyRotation = 5;
// The fewest screen rows: the key's head.
inline constexpr std::size_t kMinScreenRows = kKeyHeadRows;

// out[i] = kind(a[i], b[i]) over n rows (n a multiple of 8). `neg_a` negates a (Unary only),
// `neg_b` negates b; `unary` names the op of Unary; `k` the exponent of IPow.
void compute_column(EKind kind, Op unary, int k, const float* a, const float* b, bool neg_a,
                    bool neg_b, float* out, std::size_t n);

// The screen target: y and per-row weights, normalised so that the loss is sum w * e(row).
struct ScreenTarget {
  const float* y = nullptr;
  const float* w = nullptr;       // for MaxAbs: 1 or 0 (row selected)
  const float* log2_y = nullptr;  // log2(y), for the Log loss
  double wyy = 0;                 // sum w y^2 (mse and rmse expand around it)
  Loss loss = Loss::Mse;
  std::size_t n = 0;
};

// The rel loss's screens count a row's relative error |x / y - 1| as at most this, so that the
// float32 sums stay finite (64 rows of 1e30 each).
inline constexpr float kMaxRelativeError = 1e15f;

// The rel loss divides by y in float32: a row whose target is not a normal float (below 1.2e-38
// in magnitude, as in the far tail of a lobe) is left out of the float32 screens (weight 0, y
// replaced by 1 so that 0 * (x / y) stays finite); the float64 scoring of front members keeps it.
inline bool relative_screen_row(double y) {
  const float f = static_cast<float>(y);
  return std::isnormal(f);
}

struct ColumnStats {
  // Key (column_key).
  std::uint64_t hash = 0;
  bool canonical_neg = false;  // the hash was taken of the negated column
  float scale = 0;             // max |value| over the first 16 rows
  // Measure (column_loss).
  bool valid = false;  // finite everywhere and not (nearly) constant
  float loss_pos = 0;  // loss of the column
  float loss_neg = 0;  // loss of its negation
};

// The dedup key of a column of n rows (a multiple of 8, at least 16): a hash of every row,
// rounded to a relative 1e-3 (the first 16 rows) or 1.5% (the others), values below 1e-6 of the
// largest of the first 16 taken as zero, the column negated first where its first of those
// above that is negative. Columns that columns_equivalent finds the same have one key unless
// a value lies on a rounding boundary, and columns that differ by more than the rounding on any
// row have two, so that a probe rarely compares columns that differ.
void column_key(const float* v, std::size_t n, ColumnStats* stats);
void column_loss(const float* v, const ScreenTarget& target, ColumnStats* stats);
inline ColumnStats analyze_column(const float* v, const ScreenTarget& target) {
  ColumnStats s;
  column_key(v, target.n, &s);
  column_loss(v, target, &s);
  return s;
}

// Whether a and sign * b agree within a relative 2e-5 plus 1e-6 * scale on every row: the
// verification behind a hash match (operations reassociated in float differ by a few ulp).
// False when either holds a NaN.
bool columns_equivalent(const float* a, const float* b, bool negate_b, float scale, std::size_t n);

// Closed-form screening of the fused sums m +- c of a product m with every leaf c (an input or a
// literal), for mse and rmse: sum w (a m + b c - y)^2 = Smm + 2ab Smc - 2a Smy + K(b, c)
// with a, b = +-1, from one pass of dot products over m. `k_plus[j]`, `k_minus[j]` hold
// K(+1, c_j), K(-1, c_j); a leaf is a column (inputs) or a value (literals, column null).
struct FusedScreen {
  std::vector<const float*> leaf_columns;
  std::vector<float> leaf_values;
  std::vector<double> k_plus, k_minus;
  const float* y = nullptr;
  const float* w = nullptr;
  std::size_t n = 0;
};

// The best of the 4 variants (+-m +- c) over all leaves.
struct FusedBest {
  float loss = 3.4e38f;
  std::int16_t leaf = -1;  // index into FusedScreen's leaves; -1: none
  bool neg_leaf = false;   // the sum is m - c rather than m + c
  bool negate = false;     // and the prediction is its negation
};

FusedBest screen_fused(const float* m, const FusedScreen& fs);

}  // namespace shaderfit::search_detail
