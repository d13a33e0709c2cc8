// Internal: the normal-equation sums of a linear least-squares fit, shared by the CUDA kernel and
// its CPU emulation.
//
// A formula linear in its parameters is f = g0 + sum_j p_j g_j (fit/fit.hpp). With the basis
// g_1..g_K and the offset g0 as packed programs, one pass over the rows gives
//   JtJ[i][j] = sum w g_i g_j,  Jtr[i] = sum w g_i r,  rr = sum w r^2,  with r = y - g0,
// from which the host solves the K x K system. Work split as the population kernel: one warp per
// chunk of kChunkRows rows, one row per lane per step, the lanes folded by warp_fold and the
// chunks in chunk order (so the result depends only on the row count).
#pragma once

#include <cstddef>
#include <cstdint>

#include "gpu/population_sums.hpp"

namespace shaderfit::gpu_detail {

inline constexpr int kMaxBasis = 8;  // SearchOptions::max_parameters is at most 8
inline constexpr int kPackedSymmetric = kMaxBasis * (kMaxBasis + 1) / 2;

// Index of (i, j), i <= j, in the packed upper triangle of a symmetric k x k matrix.
SF_CPU_GPU inline int packed_index(int i, int j, int k) {
  return i * k - i * (i - 1) / 2 + (j - i);
}

struct NormalSums {
  double jtj[kPackedSymmetric] = {};
  double jtr[kMaxBasis] = {};
  double rr = 0, w = 0;
  std::uint32_t bad = 0;  // rows where a basis function or the offset is NaN or infinite
  int k = 0;

  SF_CPU_GPU void add(const float* g, float offset, double y, double weight) {
    const double r = y - static_cast<double>(offset);
    bool ok = r - r == 0.0;
    for (int i = 0; i < k; ++i) ok = ok && g[i] - g[i] == 0.0f;
    if (!ok) {
      ++bad;
      return;
    }
    w += weight;
    rr += weight * r * r;
    for (int i = 0; i < k; ++i) {
      const double wg = weight * static_cast<double>(g[i]);
      jtr[i] += wg * r;
      for (int j = i; j < k; ++j) jtj[packed_index(i, j, k)] += wg * static_cast<double>(g[j]);
    }
  }

  SF_CPU_GPU void merge(const NormalSums& o) {
    for (int i = 0; i < kPackedSymmetric; ++i) jtj[i] += o.jtj[i];
    for (int i = 0; i < kMaxBasis; ++i) jtr[i] += o.jtr[i];
    rr += o.rr;
    w += o.w;
    bad += o.bad;
  }
};

// Programs 0..k-1 of the view are the basis; program k, when has_offset, is g0 (else g0 = 0).
// The view's affine and loss are not used.
SF_CPU_GPU inline NormalSums lane_normal_sums(const PopulationView& v, int k, bool has_offset,
                                              std::size_t chunk, unsigned lane) {
  NormalSums s;
  s.k = k;
  const std::size_t begin = chunk * kChunkRows;
  const std::size_t end = begin + kChunkRows < v.rows ? begin + kChunkRows : v.rows;
  for (std::size_t r = begin + lane; r < end; r += kWarpLanes) {
    const double weight = v.w != nullptr ? v.w[r] : 1.0;
    if (!(weight > 0)) continue;
    const std::size_t row[1] = {r};
    float g[kMaxBasis];
    for (int i = 0; i < k; ++i) {
      float value[1];
      run_program<1>(v.nodes + v.offsets[i], v.offsets[i + 1] - v.offsets[i], v.columns, v.rows,
                     row, value);
      g[i] = value[0];
    }
    float offset[1] = {0.0f};
    if (has_offset)
      run_program<1>(v.nodes + v.offsets[k], v.offsets[k + 1] - v.offsets[k], v.columns, v.rows,
                     row, offset);
    s.add(g, offset[0], v.y[r], weight);
  }
  return s;
}

}  // namespace shaderfit::gpu_detail
