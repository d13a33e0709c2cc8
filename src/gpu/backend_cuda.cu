// The CUDA backend (shaderfit_cuda): kernels, device memory and launches behind gpu/backend.hpp.
//
// The kernels are thin: each thread or warp calls the shared SF_CPU_GPU code of
// gpu/population_sums.hpp, gpu/normal_sums.hpp and gpu/screen_column.hpp, whose CPU emulation the
// tests check against the CPU evaluator and the CPU enumerator. What is specific to the GPU is
// only the work split and the shuffles, which reproduce warp_fold's order exactly.
// Built with --fmad=false (no contraction, as -ffp-contract=off on the host).
#include <cuda_runtime.h>

#include <string>
#include <utility>
#include <vector>

#include "gpu/backend.hpp"

namespace shaderfit::gpu_detail {

namespace {

std::string cuda_error(const char* what, cudaError_t e) {
  return std::string(what) + ": " + cudaGetErrorString(e);
}

#define SF_CUDA_TRY(call)                                                                     \
  do {                                                                                        \
    if (const cudaError_t sf_e = (call); sf_e != cudaSuccess) return cuda_error(#call, sf_e); \
  } while (0)

// A device allocation that grows (never shrinks) to the largest size asked for.
struct Buffer {
  void* ptr = nullptr;
  std::size_t bytes = 0;
  Buffer() = default;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  ~Buffer() { cudaFree(ptr); }
  std::string reserve(std::size_t n) {
    if (n <= bytes) return {};
    cudaFree(ptr);
    ptr = nullptr;
    bytes = 0;
    SF_CUDA_TRY(cudaMalloc(&ptr, n));
    bytes = n;
    return {};
  }
  std::string upload(const void* src, std::size_t n) {
    if (n == 0) return {};
    if (std::string e = reserve(n); !e.empty()) return e;
    SF_CUDA_TRY(cudaMemcpy(ptr, src, n, cudaMemcpyHostToDevice));
    return {};
  }
  template <typename T>
  T* as() const {
    return static_cast<T*>(ptr);
  }
};

constexpr unsigned kFullMask = 0xffffffffu;
constexpr int kBlock = 128;  // threads per block: 4 warps

// One warp's shuffle-down tree over RowSums: lane 0 ends with warp_fold's result.
__device__ void warp_reduce(RowSums& s) {
  for (unsigned offset = kWarpLanes / 2; offset > 0; offset /= 2) {
    RowSums o;
    o.shift = __shfl_down_sync(kFullMask, s.shift, offset);
    o.w = __shfl_down_sync(kFullMask, s.w, offset);
    o.wd = __shfl_down_sync(kFullMask, s.wd, offset);
    o.wdd = __shfl_down_sync(kFullMask, s.wdd, offset);
    o.wdy = __shfl_down_sync(kFullMask, s.wdy, offset);
    o.wy = __shfl_down_sync(kFullMask, s.wy, offset);
    o.we = __shfl_down_sync(kFullMask, s.we, offset);
    o.max_e = __shfl_down_sync(kFullMask, s.max_e, offset);
    o.rows = __shfl_down_sync(kFullMask, s.rows, offset);
    o.bad_prediction = __shfl_down_sync(kFullMask, s.bad_prediction, offset);
    o.bad_target = __shfl_down_sync(kFullMask, s.bad_target, offset);
    s.merge(o);
  }
}

__device__ void warp_reduce(NormalSums& s) {
  for (unsigned offset = kWarpLanes / 2; offset > 0; offset /= 2) {
    NormalSums o;
    o.k = s.k;
    for (int i = 0; i < kPackedSymmetric; ++i)
      o.jtj[i] = __shfl_down_sync(kFullMask, s.jtj[i], offset);
    for (int i = 0; i < kMaxBasis; ++i) o.jtr[i] = __shfl_down_sync(kFullMask, s.jtr[i], offset);
    o.rr = __shfl_down_sync(kFullMask, s.rr, offset);
    o.w = __shfl_down_sync(kFullMask, s.w, offset);
    o.bad = __shfl_down_sync(kFullMask, s.bad, offset);
    s.merge(o);
  }
}

// One warp per (program, chunk); whole warps leave together, so the shuffles see full warps.
__global__ void population_kernel(PopulationView v, std::size_t programs, std::size_t chunks,
                                  RowSums* partial) {
  const std::size_t warp = (blockIdx.x * std::size_t{blockDim.x} + threadIdx.x) / kWarpLanes;
  const unsigned lane = threadIdx.x % kWarpLanes;
  if (warp >= programs * chunks) return;
  RowSums s = lane_sums(v, static_cast<std::uint32_t>(warp / chunks), warp % chunks, lane);
  warp_reduce(s);
  if (lane == 0) partial[warp] = s;
}

// The chunks of each program (one thread each), folded in chunk order.
template <typename Sums>
__global__ void fold_chunks(const Sums* partial, std::size_t programs, std::size_t chunks,
                            Sums* out) {
  const std::size_t e = blockIdx.x * std::size_t{blockDim.x} + threadIdx.x;
  if (e >= programs) return;
  Sums s = partial[e * chunks];
  for (std::size_t c = 1; c < chunks; ++c) s.merge(partial[e * chunks + c]);
  out[e] = s;
}

__global__ void normal_kernel(PopulationView v, int k, bool has_offset, std::size_t chunks,
                              NormalSums* partial) {
  const std::size_t warp = (blockIdx.x * std::size_t{blockDim.x} + threadIdx.x) / kWarpLanes;
  const unsigned lane = threadIdx.x % kWarpLanes;
  if (warp >= chunks) return;
  NormalSums s = lane_normal_sums(v, k, has_offset, warp, lane);
  warp_reduce(s);
  if (lane == 0) partial[warp] = s;
}

// Eight threads per candidate, thread l in the role of the CPU kernels' vector lane l.
__global__ void screen_kernel(const ColumnCandidate* candidates, std::size_t count,
                              const float* store, ScreenTargetView t, ScreenResult* results,
                              float* columns) {
  const std::size_t thread = blockIdx.x * std::size_t{blockDim.x} + threadIdx.x;
  const std::size_t g = thread / kScreenLanes;
  if (g >= count) return;  // whole groups of eight leave together
  const int l = static_cast<int>(thread % kScreenLanes);
  const unsigned first = threadIdx.x % kWarpLanes - static_cast<unsigned>(l);
  const unsigned mask = 0xffu << first;
  const ColumnCandidate c = candidates[g];
  const float* a = store + std::size_t{c.a} * t.n;
  const float* b = store + std::size_t{c.b} * t.n;
  float* out = columns + g * t.n;
  ScreenLane lane;
  for (std::size_t i = static_cast<std::size_t>(l); i < t.n; i += kScreenLanes) {
    out[i] = screen_row(c, a[i], b[i]);
    lane.add(out[i], i, t);
  }
  __syncwarp(mask);  // the group's column writes are visible to its first thread
  ScreenLane lanes[kScreenLanes];
  for (int src = 0; src < kScreenLanes; ++src) {
    lanes[src].vmin = __shfl_sync(mask, lane.vmin, src, kScreenLanes);
    lanes[src].vmax = __shfl_sync(mask, lane.vmax, src, kScreenLanes);
    lanes[src].a = __shfl_sync(mask, lane.a, src, kScreenLanes);
    lanes[src].b = __shfl_sync(mask, lane.b, src, kScreenLanes);
    lanes[src].nan = __shfl_sync(mask, lane.nan, src, kScreenLanes);
  }
  if (l != 0) return;
  ScreenResult r;
  screen_key(out, t.n, &r);
  screen_loss_fold(lanes, t, &r);
  results[g] = r;
}

unsigned blocks_for(std::size_t threads) {
  return static_cast<unsigned>((threads + kBlock - 1) / kBlock);
}

std::string after_launch() {
  SF_CUDA_TRY(cudaGetLastError());
  SF_CUDA_TRY(cudaDeviceSynchronize());
  return {};
}

}  // namespace

struct DeviceData {
  Buffer columns, y, w, nodes, offsets, affine, partial, out;
  std::size_t rows = 0;
  bool weighted = false;

  PopulationView view(Loss loss, bool with_affine) const {
    PopulationView v;
    v.nodes = nodes.as<const GpuNode>();
    v.offsets = offsets.as<const std::uint32_t>();
    v.affine = with_affine ? affine.as<const Affine>() : nullptr;
    v.columns = columns.as<const float>();
    v.y = y.as<const double>();
    v.w = weighted ? w.as<const double>() : nullptr;
    v.rows = rows;
    v.loss = loss;
    return v;
  }
  std::string upload_programs(const GpuNode* n, std::size_t num_nodes, const std::uint32_t* o,
                              std::size_t programs) {
    if (std::string e = nodes.upload(n, num_nodes * sizeof(GpuNode)); !e.empty()) return e;
    return offsets.upload(o, (programs + 1) * sizeof(std::uint32_t));
  }
};

struct ScreenData {
  Buffer y, w, log2_y, store, candidates, results, columns;
  std::size_t rows = 0, stored = 0;
  double wyy = 0;
  Loss loss = Loss::Mse;
};

bool backend_compiled() { return true; }

int backend_device_count(std::string* why) {
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess) {
    if (why != nullptr) *why = cudaGetErrorString(e);
    return 0;
  }
  if (n == 0 && why != nullptr) *why = "the driver reports no device";
  return n;
}

std::string backend_device_name(int device) {
  cudaDeviceProp p{};
  if (cudaGetDeviceProperties(&p, device) != cudaSuccess) return {};
  return std::string(p.name) + " (sm_" + std::to_string(p.major) + std::to_string(p.minor) + ")";
}

std::string create_device_data(const float* columns, std::size_t num_columns, std::size_t rows,
                               const double* y, const double* w, DeviceData** out) {
  *out = nullptr;
  auto* d = new DeviceData;
  d->rows = rows;
  d->weighted = w != nullptr;
  std::string e = d->columns.upload(columns, num_columns * rows * sizeof(float));
  if (e.empty()) e = d->y.upload(y, rows * sizeof(double));
  if (e.empty() && w != nullptr) e = d->w.upload(w, rows * sizeof(double));
  if (!e.empty()) {
    delete d;
    return e;
  }
  *out = d;
  return {};
}

void destroy_device_data(DeviceData* data) { delete data; }

std::string population_sums(DeviceData* d, const GpuNode* nodes, std::size_t num_nodes,
                            const std::uint32_t* offsets, std::size_t programs,
                            const Affine* affine, Loss loss, RowSums* out) {
  if (programs == 0) return {};
  if (std::string e = d->upload_programs(nodes, num_nodes, offsets, programs); !e.empty()) return e;
  if (affine != nullptr) {
    if (std::string e = d->affine.upload(affine, programs * sizeof(Affine)); !e.empty()) return e;
  }
  const std::size_t chunks = chunk_count(d->rows);
  if (std::string e = d->partial.reserve(programs * chunks * sizeof(RowSums)); !e.empty()) return e;
  const PopulationView v = d->view(loss, affine != nullptr);
  population_kernel<<<blocks_for(programs * chunks * kWarpLanes), kBlock>>>(
      v, programs, chunks, d->partial.as<RowSums>());
  const RowSums* result = d->partial.as<RowSums>();
  if (chunks > 1) {
    if (std::string e = d->out.reserve(programs * sizeof(RowSums)); !e.empty()) return e;
    fold_chunks<<<blocks_for(programs), kBlock>>>(d->partial.as<RowSums>(), programs, chunks,
                                                  d->out.as<RowSums>());
    result = d->out.as<RowSums>();
  }
  if (std::string e = after_launch(); !e.empty()) return e;
  SF_CUDA_TRY(cudaMemcpy(out, result, programs * sizeof(RowSums), cudaMemcpyDeviceToHost));
  return {};
}

std::string normal_sums(DeviceData* d, const GpuNode* nodes, std::size_t num_nodes,
                        const std::uint32_t* offsets, int k, bool has_offset, NormalSums* out) {
  const std::size_t programs = static_cast<std::size_t>(k) + (has_offset ? 1 : 0);
  if (std::string e = d->upload_programs(nodes, num_nodes, offsets, programs); !e.empty()) return e;
  const std::size_t chunks = chunk_count(d->rows);
  if (std::string e = d->partial.reserve(chunks * sizeof(NormalSums)); !e.empty()) return e;
  if (std::string e = d->out.reserve(sizeof(NormalSums)); !e.empty()) return e;
  normal_kernel<<<blocks_for(chunks * kWarpLanes), kBlock>>>(
      d->view(Loss::Mse, false), k, has_offset, chunks, d->partial.as<NormalSums>());
  fold_chunks<<<1, kBlock>>>(d->partial.as<NormalSums>(), 1, chunks, d->out.as<NormalSums>());
  if (std::string e = after_launch(); !e.empty()) return e;
  SF_CUDA_TRY(cudaMemcpy(out, d->out.ptr, sizeof(NormalSums), cudaMemcpyDeviceToHost));
  return {};
}

std::string create_screen_data(const float* y, const float* w, const float* log2_y,
                               std::size_t rows, double wyy, Loss loss, ScreenData** out) {
  *out = nullptr;
  auto* d = new ScreenData;
  d->rows = rows;
  d->wyy = wyy;
  d->loss = loss;
  std::string e = d->y.upload(y, rows * sizeof(float));
  if (e.empty()) e = d->w.upload(w, rows * sizeof(float));
  if (e.empty() && log2_y != nullptr) e = d->log2_y.upload(log2_y, rows * sizeof(float));
  if (!e.empty()) {
    delete d;
    return e;
  }
  *out = d;
  return {};
}

void destroy_screen_data(ScreenData* data) { delete data; }

std::string screen_add_columns(ScreenData* d, const float* columns, std::size_t count) {
  const std::size_t column_bytes = d->rows * sizeof(float);
  const std::size_t need = (d->stored + count) * column_bytes;
  if (need > d->store.bytes) {
    // Grow by half again, keeping what is stored.
    Buffer bigger;
    if (std::string e = bigger.reserve(need + need / 2); !e.empty()) return e;
    if (d->stored > 0)
      SF_CUDA_TRY(
          cudaMemcpy(bigger.ptr, d->store.ptr, d->stored * column_bytes, cudaMemcpyDeviceToDevice));
    std::swap(d->store.ptr, bigger.ptr);
    std::swap(d->store.bytes, bigger.bytes);
  }
  SF_CUDA_TRY(cudaMemcpy(d->store.as<char>() + d->stored * column_bytes, columns,
                         count * column_bytes, cudaMemcpyHostToDevice));
  d->stored += count;
  return {};
}

std::string screen_candidates(ScreenData* d, const ColumnCandidate* candidates, std::size_t count,
                              ScreenResult* out, float* columns_out) {
  if (count == 0) return {};
  if (std::string e = d->candidates.upload(candidates, count * sizeof(ColumnCandidate)); !e.empty())
    return e;
  if (std::string e = d->results.reserve(count * sizeof(ScreenResult)); !e.empty()) return e;
  if (std::string e = d->columns.reserve(count * d->rows * sizeof(float)); !e.empty()) return e;
  ScreenTargetView t;
  t.y = d->y.as<const float>();
  t.w = d->w.as<const float>();
  t.log2_y = d->log2_y.as<const float>();
  t.wyy = d->wyy;
  t.loss = d->loss;
  t.n = d->rows;
  screen_kernel<<<blocks_for(count * kScreenLanes), kBlock>>>(
      d->candidates.as<const ColumnCandidate>(), count, d->store.as<const float>(), t,
      d->results.as<ScreenResult>(), d->columns.as<float>());
  if (std::string e = after_launch(); !e.empty()) return e;
  SF_CUDA_TRY(
      cudaMemcpy(out, d->results.ptr, count * sizeof(ScreenResult), cudaMemcpyDeviceToHost));
  if (columns_out != nullptr)
    SF_CUDA_TRY(cudaMemcpy(columns_out, d->columns.ptr, count * d->rows * sizeof(float),
                           cudaMemcpyDeviceToHost));
  return {};
}

}  // namespace shaderfit::gpu_detail
