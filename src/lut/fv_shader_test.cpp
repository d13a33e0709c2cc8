#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "shaderfit/lut/fv_output.hpp"

namespace shaderfit::lut {
namespace {

FvBake tiny_bake(FvLutOptions* o) {
  o->size = 4;
  o->fit_samples = 20;
  o->eval_samples = 20;
  o->endpoint_grid = 4;
  const std::array<FvVariant, 1> v = {FvVariant::endpoint};
  return bake_fv_luts(*o, v);
}

TEST(FvShader, CodeSamplesTheTableWithOneExp2AndTwoFmas) {
  FvLutOptions o;
  const FvBake b = tiny_bake(&o);
  const std::string hlsl = fv_hlsl(b, o), glsl = fv_glsl(b, o);
  EXPECT_NE(hlsl.find("exp2(mad(mad(poly.x, dotLH, poly.y), dotLH, poly.z))"), std::string::npos)
      << hlsl;
  EXPECT_NE(glsl.find("exp2(fma(fma(poly.x, dotLH, poly.y), dotLH, poly.z))"), std::string::npos)
      << glsl;
  EXPECT_NE(hlsl.find("float2(roughness, sqrt(f0))"), std::string::npos);
  EXPECT_NE(glsl.find("vec2(roughness, sqrt(f0))"), std::string::npos);
}

// Compiles the generated code with glslangValidator (Debian glslang-tools) where it is installed.
TEST(FvShader, CompilesWithGlslang) {
  if (std::system("command -v glslangValidator > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "skipped: glslangValidator not found";
  FvLutOptions o;
  const FvBake b = tiny_bake(&o);
  const auto dir = std::filesystem::temp_directory_path() / "shaderfit_shader_test";
  std::filesystem::create_directories(dir);
  const std::string frag = (dir / "fv.frag").string(), hlsl = (dir / "fv.hlsl").string();
  std::ofstream(frag) << "#version 450\n"
                      << fv_glsl(b, o)
                      << "layout(location = 0) in vec3 d;\nlayout(location = 0) out vec4 color;\n"
                         "void main() { color = vec4(FvPoly(FvPolyFetch(d.x, d.y), d.z) + "
                         "FvEndpointPoly(d.x, d.y).x); }\n";
  std::ofstream(hlsl)
      << fv_hlsl(b, o)
      << "float4 main(float3 d : TEXCOORD0) : SV_Target\n"
         "{ return FvPoly(FvPolyFetch(d.x, d.y), d.z) + FvEndpointPoly(d.x, d.y).x; }\n";
  const std::string spv = (dir / "fv.spv").string();
  EXPECT_EQ(std::system(("glslangValidator " + frag + " > /dev/null").c_str()), 0);
  EXPECT_EQ(
      std::system(("glslangValidator -D -V -e main -S frag " + hlsl + " -o " + spv + " > /dev/null")
                      .c_str()),
      0);
}

}  // namespace
}  // namespace shaderfit::lut
