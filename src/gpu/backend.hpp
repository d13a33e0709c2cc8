// Internal: the seam between the host library and the CUDA target.
//
// src/gpu/backend_cuda.cu implements these functions in the shaderfit_cuda library (kernels,
// device memory, launches); src/gpu/backend_none.cpp implements them in builds without CUDA,
// where every call reports that. The host library (src/gpu/evaluator.cpp, device.cpp,
// screen.cpp) packs the work, calls these, and turns a failure into shaderfit::Error. So the
// CUDA target depends on nothing but header-only shared code, and no CUDA type crosses here.
//
// Every function returns an empty string on success, otherwise what went wrong in one line.
// Calls are synchronous; one DeviceData or ScreenData must not be used by two threads at once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "gpu/normal_sums.hpp"
#include "gpu/population_sums.hpp"
#include "gpu/screen_column.hpp"

namespace shaderfit::gpu_detail {

// Whether this build has the CUDA target.
bool backend_compiled();
// The number of CUDA devices; when 0, the cause in *why ("this build has no CUDA support ...",
// the driver's error message, "the driver reports no device").
int backend_device_count(std::string* why);
std::string backend_device_name(int device);

// The data of a population evaluation, on the device, with scratch buffers that grow as needed.
struct DeviceData;
std::string create_device_data(const float* columns, std::size_t num_columns, std::size_t rows,
                               const double* y, const double* w, DeviceData** out);
void destroy_device_data(DeviceData* data);

// RowSums of each of `programs` packed programs (nodes, offsets as in PopulationView; affine
// null or one per program) over every row: out[programs].
std::string population_sums(DeviceData* data, const GpuNode* nodes, std::size_t num_nodes,
                            const std::uint32_t* offsets, std::size_t programs,
                            const Affine* affine, Loss loss, RowSums* out);

// Normal-equation sums of basis programs 0..k-1 and offset program k (when has_offset).
std::string normal_sums(DeviceData* data, const GpuNode* nodes, std::size_t num_nodes,
                        const std::uint32_t* offsets, int k, bool has_offset, NormalSums* out);

// The enumeration's column store and screen target, on the device.
struct ScreenData;
std::string create_screen_data(const float* y, const float* w, const float* log2_y,
                               std::size_t rows, double wyy, Loss loss, ScreenData** out);
void destroy_screen_data(ScreenData* data);
// Appends `count` columns (rows floats each) to the store; they get the next indices.
std::string screen_add_columns(ScreenData* data, const float* columns, std::size_t count);
// For each candidate: its ScreenResult, and (columns_out not null) its column, rows floats each.
std::string screen_candidates(ScreenData* data, const ColumnCandidate* candidates,
                              std::size_t count, ScreenResult* out, float* columns_out);

}  // namespace shaderfit::gpu_detail
