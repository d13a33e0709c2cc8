#include "shaderfit/gpu/device.hpp"

#include "gpu/backend.hpp"

namespace shaderfit {

namespace {

struct Probe {
  bool available = false;
  std::string name, reason;
};

// The driver is asked once: the answer does not change while the process runs.
const Probe& probe() {
  static const Probe p = [] {
    Probe r;
    std::string why;
    if (gpu_detail::backend_device_count(&why) > 0) {
      r.available = true;
      r.name = gpu_detail::backend_device_name(0);
    } else {
      r.reason = why.empty() ? "no CUDA device" : "no CUDA device (" + why + ")";
    }
    return r;
  }();
  return p;
}

}  // namespace

std::optional<ComputeDevice> device_from_name(std::string_view name) {
  if (name == "auto") return ComputeDevice::Auto;
  if (name == "cpu") return ComputeDevice::Cpu;
  if (name == "cuda" || name == "gpu") return ComputeDevice::Cuda;
  return std::nullopt;
}

std::string_view device_name(ComputeDevice device) {
  switch (device) {
    case ComputeDevice::Auto: return "auto";
    case ComputeDevice::Cpu: return "cpu";
    case ComputeDevice::Cuda: return "cuda";
  }
  return "auto";
}

bool cuda_built() { return gpu_detail::backend_compiled(); }
bool cuda_available() { return probe().available; }
std::string cuda_device_name() { return probe().name; }
std::string cuda_unavailable_reason() { return probe().reason; }

ComputeDevice resolve_device(ComputeDevice requested, const SourceLocation& where) {
  switch (requested) {
    case ComputeDevice::Cpu: return ComputeDevice::Cpu;
    case ComputeDevice::Auto: return cuda_available() ? ComputeDevice::Cuda : ComputeDevice::Cpu;
    case ComputeDevice::Cuda:
      if (!cuda_available()) throw Error("cannot use the GPU: " + cuda_unavailable_reason(), where);
      return ComputeDevice::Cuda;
  }
  return ComputeDevice::Cpu;
}

}  // namespace shaderfit
