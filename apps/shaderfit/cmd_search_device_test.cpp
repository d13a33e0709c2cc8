// shaderfit search --device: the choice of CPU or GPU, and the one-line error without a GPU.
#include <gtest/gtest.h>

#include "cli_test_util.hpp"
#include "shaderfit/gpu/device.hpp"

namespace shaderfit::cli {
namespace {

using testing::run;

TEST(CmdSearchDevice, CudaWithoutAGpuIsOneLineAndStatus2) {
  const auto r = run({"search", "--dataset", "fresnel-seed", "--time", "0.2", "--device", "cuda"});
  if (cuda_available()) {
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("device cuda ("), std::string::npos) << r.out;
    return;
  }
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(testing::line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--device"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cannot use the GPU"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;  // stopped before any work
}

TEST(CmdSearchDevice, CpuAndAutoRun) {
  for (const char* device : {"cpu", "auto"}) {
    const auto r = run({"search", "--dataset", "fresnel-seed", "--time", "0.2", "--strategy",
                        "enumerate", "--device", device});
    EXPECT_EQ(r.status, 0) << device << ": " << r.err;
    const bool gpu = std::string(device) == "auto" && cuda_available();
    EXPECT_NE(r.out.find(gpu ? "device cuda (" : "device cpu"), std::string::npos) << r.out;
  }
}

TEST(CmdSearchDevice, UnknownDevice) {
  const auto r = run({"search", "--dataset", "fresnel-seed", "--device", "tpu"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown device 'tpu' (known: auto, cpu, cuda)"), std::string::npos)
      << r.err;
  EXPECT_EQ(testing::line_count(r.err), 1) << r.err;
}

}  // namespace
}  // namespace shaderfit::cli
