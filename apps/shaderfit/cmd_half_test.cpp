// A half-precision search on the seed's Fresnel data, checked against an evaluation the search
// did not do: the CUDA __half code `codegen --precision half` prints for the front, compiled by
// nvcc as host code (cuda_fp16.h's arithmetic) and run on every sample. The numpy float16
// check of the same front is python/tests/precision_test.py.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_test_util.hpp"
#include "codegen/toolchain_test_support.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/eval/evaluate_in.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/precision.hpp"
#include "shaderfit/image/half.hpp"

namespace shaderfit::cli::testing {
namespace {

TEST(CmdHalf, SeedFrontEqualsTheCudaHalfCodeOnEverySample) {
  const auto nvcc = shaderfit::testing::find_tool("nvcc");
  if (!nvcc) GTEST_SKIP() << "skipped: nvcc not found";
  const auto dir = shaderfit::testing::scratch_folder("cmd_half_front");
  const std::string front = (dir / "front.json").string();
  const CliResult s =
      run({"search", "--dataset", "fresnel-seed", "--inputs", "r0,x", "--target", "R",
           "--precision", "half", "--evals", "400000", "--seed", "7", "--json", front});
  ASSERT_EQ(s.status, 0) << s.err;
  const CliResult c =
      run({"codegen", "--front", front, "--lang", "cuda", "--precision", "half", "--name", "m"});
  ASSERT_EQ(c.status, 0) << c.err;
  const nlohmann::json doc = nlohmann::json::parse(shaderfit::testing::read_text(front));
  const std::size_t members = doc["front"].size();
  ASSERT_GE(members, 3u);

  // The seed's samples, as the CLI built them (--data-seed 1).
  Rng rng(1);
  const Dataset data = make_fresnel_seed_dataset(rng);
  const std::vector<double>& r0 = data.numeric("r0").values;
  const std::vector<double>& x = data.numeric("x").values;
  const std::vector<double>& target = data.numeric("R").values;
  std::string rows;
  for (std::size_t i = 0; i < r0.size(); ++i) rows += fmt::format("{:.17g} {:.17g}\n", r0[i], x[i]);
  std::string src = "#include <cstdio>\n" + c.out;
  src +=
      "int main(int argc, char** argv) {\n  FILE* in = std::fopen(argv[1], \"r\");\n"
      "  float r0, x;\n  while (std::fscanf(in, \"%f %f\", &r0, &x) == 2) {\n"
      "    const __half hr0 = __float2half(r0), hx = __float2half(x);\n";
  for (std::size_t k = 0; k < members; ++k)
    src += fmt::format("    std::printf(\"%04x \", __half_as_ushort(m_{}(hr0, hx)));\n", k);
  src += "    std::printf(\"\\n\");\n  }\n  return 0;\n}\n";
  shaderfit::testing::write_text(dir / "host.cu", src);
  shaderfit::testing::write_text(dir / "rows.txt", rows);
  std::string log;
  ASSERT_EQ(
      shaderfit::testing::run_command(
          fmt::format("cd '{}' && '{}' -arch=sm_90 -o host host.cu", dir.string(), *nvcc), &log),
      0)
      << log << src;
  std::string out;
  ASSERT_EQ(shaderfit::testing::run_command(fmt::format("cd '{}' && ./host rows.txt", dir.string()),
                                            &out),
            0);

  ParseOptions po;
  po.variables = {"r0", "x"};
  std::vector<Expression> formulas;
  for (const auto& m : doc["front"])
    formulas.push_back(parse_formula(m["formula"].get<std::string>(), po));
  std::vector<double> max_ulps(members, 0.0), max_abs(members, 0.0);
  std::istringstream results(out);
  for (std::size_t i = 0; i < r0.size(); ++i) {
    for (std::size_t k = 0; k < members; ++k) {
      unsigned bits = 0;
      ASSERT_TRUE(results >> std::hex >> bits) << "row " << i;
      const double cuda = static_cast<double>(half_to_float(static_cast<std::uint16_t>(bits)));
      const double ours = evaluate_half(formulas[k], std::vector<double>{r0[i], x[i]});
      const double ulps = cuda == ours ? 0.0 : std::fabs(cuda - ours) / half_ulp(ours);
      max_ulps[k] = std::max(max_ulps[k], ulps);
      max_abs[k] = std::max(max_abs[k], std::fabs(cuda - target[i]));
    }
  }
  for (std::size_t k = 0; k < members; ++k) {
    const auto& m = doc["front"][k];
    EXPECT_LE(max_ulps[k], 1.0) << m["formula"];
    // The error the front reports in half is the one the CUDA code makes, to a half ulp of
    // the largest error.
    EXPECT_NEAR(m["max_abs"].get<double>(), max_abs[k], half_ulp(max_abs[k])) << m["formula"];
    EXPECT_EQ(m["max_abs"].get<double>(), m["half_max_abs"].get<double>()) << m["formula"];
    std::cout << m["formula"].get<std::string>() << ": max " << max_ulps[k]
              << " half ulp from the CUDA code; max |error| " << max_abs[k] << "\n";
  }
}

}  // namespace
}  // namespace shaderfit::cli::testing
