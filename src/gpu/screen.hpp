// Internal: the bottom-up enumeration's column step on the GPU.
//
// The enumerator keeps every class's screen column (float32, n rows) in its store; the GPU keeps
// a copy. A step is a batch of candidates -- an operator over one or two stored columns -- for
// which the device computes the candidate column, its dedup key and its screen losses, with the
// same bits as search_detail::compute_column / column_key / column_loss (gpu/screen_column.hpp),
// and returns (key, losses, valid) per candidate. The host then deduplicates as now, and
// appends the new classes' columns (returned with the results when asked) to both stores:
//
//   GpuScreen gpu(target);                         // the enumerator's ScreenTarget arrays
//   gpu.add_columns(leaf_columns);                 // leaves first, in class order
//   for each level, for each tile of candidates (operand class indices into the store):
//     auto r = gpu.screen(tile, &columns);         // one launch per tile of thousands
//     ... dedup r[i].hash against the class table; for each new class: keep columns[i * n ...]
//     gpu.add_columns(new_class_columns);          // in the order the classes are committed
//
// docs/gpu.md describes the integration; the enumerator itself does not call this yet.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "gpu/screen_column.hpp"

namespace shaderfit::gpu_detail {

struct ScreenData;  // gpu/backend.hpp

class GpuScreen {
 public:
  // y, w (and log2_y for the log loss) hold n screen rows, n a multiple of 8 and >= 16; wyy and
  // loss as in search_detail::ScreenTarget. Throws shaderfit::Error when CUDA is unavailable.
  GpuScreen(std::span<const float> y, std::span<const float> w, std::span<const float> log2_y,
            double wyy, Loss loss);
  ~GpuScreen();
  GpuScreen(const GpuScreen&) = delete;
  GpuScreen& operator=(const GpuScreen&) = delete;

  [[nodiscard]] std::size_t rows() const { return rows_; }
  [[nodiscard]] std::size_t stored() const { return stored_; }

  // Appends columns.size() / rows() columns to the device store; returns the first's index.
  std::uint32_t add_columns(std::span<const float> columns);

  // The results of each candidate (operands < stored()); with columns_out, also the candidates'
  // columns, rows() floats each, in candidate order.
  std::vector<ScreenResult> screen(std::span<const ColumnCandidate> candidates,
                                   std::vector<float>* columns_out = nullptr);

 private:
  ScreenData* data_ = nullptr;
  std::size_t rows_ = 0, stored_ = 0;
};

// The same step on the CPU through the shared code (tests; and the reference of the GPU tests).
std::vector<ScreenResult> screen_on_cpu(std::span<const ColumnCandidate> candidates,
                                        std::span<const float> store,
                                        const ScreenTargetView& target,
                                        std::vector<float>* columns_out = nullptr);

}  // namespace shaderfit::gpu_detail
