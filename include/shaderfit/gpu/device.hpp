// Which device runs the hot loops: the CPU, or a CUDA GPU when this build has CUDA and one is
// present (docs/gpu.md).
//
//   if (shaderfit::cuda_available()) std::cout << shaderfit::cuda_device_name() << '\n';
//   ComputeDevice d = resolve_device(*device_from_name("auto"));  // Cuda or Cpu
//   resolve_device(ComputeDevice::Cuda);  // throws shaderfit::Error when there is no GPU
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

enum class ComputeDevice {
  Auto,  // the GPU when cuda_available(), else the CPU
  Cpu,
  Cuda,
};

// "auto", "cpu", "cuda" (and back); nullopt for anything else.
std::optional<ComputeDevice> device_from_name(std::string_view name);
std::string_view device_name(ComputeDevice device);

// Whether this build has the CUDA backend (CMake option SHADERFIT_CUDA, on when nvcc is found).
bool cuda_built();
// Whether the CUDA backend can run here: built with it, a driver, and at least one device.
// Checked once per process.
bool cuda_available();
// "NVIDIA H100 80GB HBM3 (sm_90)" for device 0; empty when cuda_available() is false.
std::string cuda_device_name();
// Why cuda_available() is false, in one line: "no CUDA device (<cause>)", the cause being "this
// build has no CUDA support ...", the driver's message, or "the driver reports no device";
// empty when it is true.
std::string cuda_unavailable_reason();

// The device to use for a request: Cpu stays Cpu, Auto becomes Cuda or Cpu, Cuda stays Cuda when
// available and otherwise throws Error("cannot use the GPU: <reason>", where).
ComputeDevice resolve_device(ComputeDevice requested,
                             const SourceLocation& where = {"ComputeDevice"});

}  // namespace shaderfit
