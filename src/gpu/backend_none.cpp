// The GPU backend of builds without CUDA (SHADERFIT_CUDA off, or no nvcc found): every call
// reports that, and the host library turns it into shaderfit::Error. Replaced by
// backend_cuda.cu in CUDA builds (CMakeLists.txt picks one).
#include "gpu/backend.hpp"

namespace shaderfit::gpu_detail {

namespace {
const char* const kNoCuda = "this build has no CUDA support; rebuild with nvcc and SHADERFIT_CUDA";
}

bool backend_compiled() { return false; }

int backend_device_count(std::string* why) {
  if (why != nullptr) *why = kNoCuda;
  return 0;
}

std::string backend_device_name(int) { return {}; }

std::string create_device_data(const float*, std::size_t, std::size_t, const double*, const double*,
                               DeviceData** out) {
  *out = nullptr;
  return kNoCuda;
}

void destroy_device_data(DeviceData*) {}

std::string population_sums(DeviceData*, const GpuNode*, std::size_t, const std::uint32_t*,
                            std::size_t, const Affine*, Loss, RowSums*) {
  return kNoCuda;
}

std::string normal_sums(DeviceData*, const GpuNode*, std::size_t, const std::uint32_t*, int, bool,
                        NormalSums*) {
  return kNoCuda;
}

std::string create_screen_data(const float*, const float*, const float*, std::size_t, double, Loss,
                               ScreenData** out) {
  *out = nullptr;
  return kNoCuda;
}

void destroy_screen_data(ScreenData*) {}

std::string screen_add_columns(ScreenData*, const float*, std::size_t) { return kNoCuda; }

std::string screen_candidates(ScreenData*, const ColumnCandidate*, std::size_t, ScreenResult*,
                              float*) {
  return kNoCuda;
}

}  // namespace shaderfit::gpu_detail
