#include "shaderfit/gpu/evaluator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>

#include "gpu/backend.hpp"
#include "gpu/pack.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/gpu/device.hpp"

namespace shaderfit {

using gpu_detail::Affine;
using gpu_detail::RowSums;

namespace {

void check(const std::string& failure) {
  if (!failure.empty()) throw Error("GPU: " + failure);
}

}  // namespace

LinearScaling PopulationScore::linear_scaling() const {
  LinearScaling s;
  if (!finite) {
    s.mse = std::numeric_limits<double>::infinity();
    return s;
  }
  if (!(sum_w > 0)) return {};
  s.a = sff > 0 ? sfy / sff : 0.0;
  s.b = mean_y - s.a * mean_f;
  // a f + b - y = a (f - mean_f) - (y - mean_y)
  s.mse = std::max(s.a * s.a * sff - 2 * s.a * sfy + syy, 0.0) / sum_w;
  return s;
}

struct GpuEvaluator::Impl {
  gpu_detail::DeviceData* data = nullptr;
  std::size_t rows = 0, columns = 0;
  double syy = 0;            // sum w (y - mean y)^2 over the rows with weight > 0
  mutable std::mutex mutex;  // one launch at a time on the shared buffers

  ~Impl() { gpu_detail::destroy_device_data(data); }
};

GpuEvaluator::GpuEvaluator(std::span<const double* const> columns, std::span<const double> target,
                           std::span<const double> weights)
    : impl_(std::make_unique<Impl>()) {
  resolve_device(ComputeDevice::Cuda, {"GpuEvaluator"});
  const std::size_t rows = target.size();
  if (columns.empty()) throw Error("GpuEvaluator: no input columns");
  if (rows == 0) throw Error("GpuEvaluator: no rows");
  if (!weights.empty() && weights.size() != rows)
    throw Error("GpuEvaluator: the weights have a different number of rows than the target");
  std::vector<float> packed(columns.size() * rows);
  for (std::size_t v = 0; v < columns.size(); ++v) {
    if (columns[v] == nullptr)
      throw Error("GpuEvaluator: input column " + std::to_string(v) + " is null");
    for (std::size_t r = 0; r < rows; ++r) packed[v * rows + r] = static_cast<float>(columns[v][r]);
  }
  double sw = 0, swy = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    const double w = weights.empty() ? 1.0 : weights[r];
    if (w > 0) {
      sw += w;
      swy += w * target[r];
    }
  }
  const double my = sw > 0 ? swy / sw : 0.0;
  for (std::size_t r = 0; r < rows; ++r) {
    const double w = weights.empty() ? 1.0 : weights[r];
    if (w > 0) impl_->syy += w * (target[r] - my) * (target[r] - my);
  }
  impl_->rows = rows;
  impl_->columns = columns.size();
  check(gpu_detail::create_device_data(packed.data(), columns.size(), rows, target.data(),
                                       weights.empty() ? nullptr : weights.data(), &impl_->data));
}

GpuEvaluator::~GpuEvaluator() = default;
GpuEvaluator::GpuEvaluator(GpuEvaluator&&) noexcept = default;
GpuEvaluator& GpuEvaluator::operator=(GpuEvaluator&&) noexcept = default;

std::size_t GpuEvaluator::rows() const { return impl_->rows; }
std::size_t GpuEvaluator::columns() const { return impl_->columns; }

std::vector<PopulationScore> GpuEvaluator::evaluate_population(
    std::span<const Expression* const> population, Loss loss,
    std::span<const LinearScaling> scaling) const {
  if (!scaling.empty() && scaling.size() != population.size())
    throw Error("GpuEvaluator: " + std::to_string(scaling.size()) + " scalings for " +
                std::to_string(population.size()) + " formulas");
  if (population.empty()) return {};
  const gpu_detail::PackedPrograms p = gpu_detail::pack_programs(population, impl_->columns);
  std::vector<Affine> affine;
  for (const LinearScaling& s : scaling) affine.push_back({s.a, s.b});
  std::vector<RowSums> sums(population.size());
  {
    const std::lock_guard<std::mutex> lock(impl_->mutex);
    check(gpu_detail::population_sums(impl_->data, p.nodes.data(), p.nodes.size(), p.offsets.data(),
                                      p.size(), affine.empty() ? nullptr : affine.data(), loss,
                                      sums.data()));
  }
  std::vector<PopulationScore> out;
  out.reserve(sums.size());
  for (const RowSums& s : sums) out.push_back(gpu_detail::to_score(s, loss, impl_->syy));
  return out;
}

NormalEquations GpuEvaluator::normal_equations(std::span<const Expression* const> basis,
                                               const Expression* offset) const {
  if (basis.empty() || basis.size() > static_cast<std::size_t>(gpu_detail::kMaxBasis))
    throw Error("GpuEvaluator: between 1 and 8 basis functions (got " +
                std::to_string(basis.size()) + ")");
  gpu_detail::PackedPrograms p = gpu_detail::pack_programs(basis, impl_->columns);
  if (offset != nullptr) gpu_detail::append_program(p, *offset, impl_->columns);
  const int k = static_cast<int>(basis.size());
  gpu_detail::NormalSums s;
  {
    const std::lock_guard<std::mutex> lock(impl_->mutex);
    check(gpu_detail::normal_sums(impl_->data, p.nodes.data(), p.nodes.size(), p.offsets.data(), k,
                                  offset != nullptr, &s));
  }
  NormalEquations n;
  n.k = basis.size();
  n.jtj.resize(n.k * n.k);
  n.jtr.resize(n.k);
  for (std::size_t i = 0; i < n.k; ++i) {
    n.jtr[i] = s.jtr[i];
    for (std::size_t j = i; j < n.k; ++j) {
      const double v = s.jtj[gpu_detail::packed_index(static_cast<int>(i), static_cast<int>(j), k)];
      n.jtj[i * n.k + j] = v;
      n.jtj[j * n.k + i] = v;
    }
  }
  n.rr = s.rr;
  n.sum_w = s.w;
  n.finite = s.bad == 0;
  return n;
}

}  // namespace shaderfit
