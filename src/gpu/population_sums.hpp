// Internal: the batched population evaluation's per-row loss accumulation and its reduction
// order, shared by the CUDA kernel (src/gpu/backend_cuda.cu) and its CPU emulation (the tests).
//
// Work split: a population of packed programs over `rows` rows. Rows are cut into chunks of
// kChunkRows; one warp handles one (expression, chunk). Within a chunk, lane l takes rows
// base + j * 32 + l for j < kRowsPerLane, base stepping by 32 * kRowsPerLane, so a warp's loads
// of one variable are consecutive. Each lane accumulates a RowSums; the warp folds its 32 lanes
// in the order of a shuffle-down tree (warp_fold); the chunks of an expression are then folded in
// chunk order. The order depends only on the row count, so results are deterministic and do not
// depend on the batch an expression is evaluated in.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "gpu/device_program.hpp"
#include "shaderfit/eval/loss.hpp"

namespace shaderfit::gpu_detail {

inline constexpr unsigned kWarpLanes = 32;
inline constexpr int kRowsPerLane = 4;
inline constexpr std::size_t kChunkRows = kWarpLanes * kRowsPerLane * 64;  // 8192

// The prediction of expression e is a * f + b (a = 1, b = 0 for the formula itself).
struct Affine {
  double a = 1;
  double b = 0;
};

// Sums over the rows with w > 0. The f sums are of the raw formula (for its linear scaling), taken
// about a shift (the first value of f the lane saw): a formula that is nearly constant would lose
// its variance to cancellation in plain sums of f and f^2. The error sums are of a * f + b
// against y, for the loss kind evaluated.
struct RowSums {
  double shift = 0;  // the f sums are of d = f - shift
  double w = 0, wd = 0, wdd = 0, wdy = 0, wy = 0;
  double we = 0;           // sum w e: e = d^2 (mse, rmse), (d / y)^2 (rel), (ln p - ln y)^2 (log)
  double max_e = 0;        // max |p - y| (max_abs)
  std::uint32_t rows = 0;  // rows summed
  std::uint32_t bad_prediction = 0;  // rows where a * f + b is NaN or infinite
  std::uint32_t bad_target = 0;      // rows where y = 0 (rel) or y <= 0 (log)

  // One row: f the formula's float32 value, y the target, w > 0 its weight.
  SF_CPU_GPU void add(float f, double y, double weight, Loss loss, const Affine& s) {
    const double x = static_cast<double>(f);
    const double p = s.a * x + s.b;
    if (!(p - p == 0.0)) {  // NaN or infinite (isfinite without a device-specific call)
      ++bad_prediction;
      return;
    }
    if (rows == 0) shift = x;
    ++rows;
    const double dx = x - shift;
    const double wx = weight * dx;
    w += weight;
    wd += wx;
    wdd += wx * dx;
    wdy += wx * y;
    wy += weight * y;
    const double d = p - y;
    const double ad = d < 0 ? -d : d;
    max_e = ad > max_e ? ad : max_e;
    switch (loss) {
      case Loss::Relative:
        if (y != 0) {
          const double r = d / y;
          we += weight * r * r;
        } else {
          ++bad_target;
        }
        break;
      case Loss::Log:
        if (y > 0) {
          const double l = log(p > 1e-30 ? p : 1e-30) - log(y);
          we += weight * l * l;
        } else {
          ++bad_target;
        }
        break;
      default: we += weight * d * d; break;
    }
  }

  // Adds o's rows; o's f sums are moved to this shift: with e = o.shift - shift,
  // sum w (d + e) = wd + e w, sum w (d + e)^2 = wdd + 2 e wd + e^2 w, sum w (d + e) y = wdy + e wy.
  SF_CPU_GPU void merge(const RowSums& o) {
    bad_prediction += o.bad_prediction;
    bad_target += o.bad_target;
    if (o.rows == 0) return;
    if (rows == 0) shift = o.shift;
    const double e = o.shift - shift;
    wdd += o.wdd + 2 * e * o.wd + e * e * o.w;
    wd += o.wd + e * o.w;
    wdy += o.wdy + e * o.wy;
    w += o.w;
    wy += o.wy;
    we += o.we;
    max_e = o.max_e > max_e ? o.max_e : max_e;
    rows += o.rows;
  }
};

// What loss_of(kind, a * f + b, y, w) gives, from the sums: +infinity when a prediction is not
// finite, NaN when the target does not admit the loss, 0 when no row has weight.
inline double loss_from_sums(Loss kind, const RowSums& s) {
  if (s.bad_prediction != 0) return HUGE_VAL;
  if (!(s.w > 0)) return 0.0;
  switch (kind) {
    case Loss::Mse:
    case Loss::Display: return s.we / s.w;  // the display loss's rows come weighted
    case Loss::Rmse: return std::sqrt(s.we / s.w);
    case Loss::MaxAbs: return s.max_e;
    case Loss::Relative:
    case Loss::Log: return s.bad_target != 0 ? NAN : s.we / s.w;
    case Loss::MaxRel: return NAN;  // scored on the CPU only (search_device)
  }
  return s.we / s.w;
}

// What the kernels read: device pointers on the GPU, host pointers in the CPU emulation.
struct PopulationView {
  const GpuNode* nodes = nullptr;
  const std::uint32_t* offsets = nullptr;  // programs + 1 entries
  const Affine* affine = nullptr;          // one per program; null: a = 1, b = 0
  const float* columns = nullptr;          // variable v of row r at columns[v * rows + r]
  const double* y = nullptr;
  const double* w = nullptr;  // null: every row weighs 1
  std::size_t rows = 0;
  Loss loss = Loss::Mse;
};

inline std::size_t chunk_count(std::size_t rows) { return (rows + kChunkRows - 1) / kChunkRows; }

// One lane's sums over chunk `chunk` of program e (the body of the population kernel).
SF_CPU_GPU inline RowSums lane_sums(const PopulationView& v, std::uint32_t e, std::size_t chunk,
                                    unsigned lane) {
  RowSums s;
  const std::uint32_t first = v.offsets[e];
  const GpuNode* code = v.nodes + first;
  const std::uint32_t count = v.offsets[e + 1] - first;
  const Affine scale = v.affine != nullptr ? v.affine[e] : Affine{};
  const std::size_t begin = chunk * kChunkRows;
  const std::size_t end = begin + kChunkRows < v.rows ? begin + kChunkRows : v.rows;
  constexpr std::size_t kStep = std::size_t{kWarpLanes} * kRowsPerLane;
  for (std::size_t base = begin; base < end; base += kStep) {
    std::size_t row[kRowsPerLane];
    for (int j = 0; j < kRowsPerLane; ++j) {
      const std::size_t r = base + static_cast<std::size_t>(j) * kWarpLanes + lane;
      row[j] = r < end ? r : begin;  // rows past the end compute row `begin`, then are dropped
    }
    float f[kRowsPerLane];
    run_program<kRowsPerLane>(code, count, v.columns, v.rows, row, f);
    for (int j = 0; j < kRowsPerLane; ++j) {
      if (base + static_cast<std::size_t>(j) * kWarpLanes + lane >= end) continue;
      const double weight = v.w != nullptr ? v.w[row[j]] : 1.0;
      if (!(weight > 0)) continue;
      s.add(f[j], v.y[row[j]], weight, v.loss, scale);
    }
  }
  return s;
}

// The order in which the kernel's shuffle-down tree combines a warp's lanes: afterwards
// lanes[0] holds the warp's sums. The kernel computes exactly this with __shfl_down_sync.
template <typename Sums>
SF_CPU_GPU inline void warp_fold(Sums (&lanes)[kWarpLanes]) {
  for (unsigned offset = kWarpLanes / 2; offset > 0; offset /= 2)
    for (unsigned i = 0; i < offset; ++i) lanes[i].merge(lanes[i + offset]);
}

}  // namespace shaderfit::gpu_detail
