#include "gpu/screen.hpp"

#include <string>

#include "gpu/backend.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/gpu/device.hpp"

namespace shaderfit::gpu_detail {

namespace {

void check(const std::string& failure) {
  if (!failure.empty()) throw Error("GPU: " + failure);
}

}  // namespace

GpuScreen::GpuScreen(std::span<const float> y, std::span<const float> w,
                     std::span<const float> log2_y, double wyy, Loss loss) {
  resolve_device(ComputeDevice::Cuda, {"GpuScreen"});
  const std::size_t n = y.size();
  if (n < 16 || n % 8 != 0)
    throw Error("GpuScreen: the screen rows must be a multiple of 8, at least 16");
  if (w.size() != n) throw Error("GpuScreen: the weights have another number of rows");
  if (loss == Loss::Log && log2_y.size() != n)
    throw Error("GpuScreen: the log loss needs log2(y) on every screen row");
  check(create_screen_data(y.data(), w.data(), log2_y.empty() ? nullptr : log2_y.data(), n, wyy,
                           loss, &data_));
  rows_ = n;
}

GpuScreen::~GpuScreen() { destroy_screen_data(data_); }

std::uint32_t GpuScreen::add_columns(std::span<const float> columns) {
  if (columns.size() % rows_ != 0)
    throw Error("GpuScreen: " + std::to_string(columns.size()) + " values are not whole columns");
  const auto first = static_cast<std::uint32_t>(stored_);
  const std::size_t count = columns.size() / rows_;
  check(screen_add_columns(data_, columns.data(), count));
  stored_ += count;
  return first;
}

std::vector<ScreenResult> GpuScreen::screen(std::span<const ColumnCandidate> candidates,
                                            std::vector<float>* columns_out) {
  for (const ColumnCandidate& c : candidates)
    if (c.a >= stored_ || c.b >= stored_)
      throw Error("GpuScreen: a candidate reads a column that is not stored");
  std::vector<ScreenResult> out(candidates.size());
  if (columns_out != nullptr) columns_out->resize(candidates.size() * rows_);
  check(screen_candidates(data_, candidates.data(), candidates.size(), out.data(),
                          columns_out != nullptr ? columns_out->data() : nullptr));
  return out;
}

std::vector<ScreenResult> screen_on_cpu(std::span<const ColumnCandidate> candidates,
                                        std::span<const float> store,
                                        const ScreenTargetView& target,
                                        std::vector<float>* columns_out) {
  std::vector<ScreenResult> out(candidates.size());
  std::vector<float> scratch(target.n);
  if (columns_out != nullptr) columns_out->resize(candidates.size() * target.n);
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    float* col = columns_out != nullptr ? columns_out->data() + i * target.n : scratch.data();
    out[i] = screen_candidate(candidates[i], store.data(), target, col);
  }
  return out;
}

}  // namespace shaderfit::gpu_detail
