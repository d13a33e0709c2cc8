// HLSL and GLSL for sampling the FV tables and for the texture-free endpoint variant.
#include <fmt/format.h>

#include <cmath>

#include "shaderfit/expr/print.hpp"
#include "shaderfit/lut/fv_output.hpp"

namespace shaderfit::lut {

namespace {

// A float literal that reads back to the same float.
std::string literal(double v) {
  const auto f = static_cast<float>(v);
  std::string s = fmt::format("{}", f);
  if (s.find_first_of(".eE") == std::string::npos && s.find("inf") == std::string::npos) s += ".0";
  return s;
}

struct Dialect {
  const char* f2;
  const char* f3;
  const char* fma;
  bool hlsl;
};

std::string header(const FvBake& bake, const FvLutOptions& o, const char* comment_lang) {
  return fmt::format(
      "// shaderfit lut ({}): seed 002's combined Fresnel x visibility, reference {}.\n"
      "//   FV(d) = exp2((P0 d + P1) d + P2), d = dot(L,H): one exp2 and two FMAs per light.\n"
      "// Texture: {} x {} RGBA, texel (P0, P1, P2, valid); u = roughness, v = sqrt(F0) (texel\n"
      "// centres at (i + 0.5) / {}). Sample with bilinear filtering and clamp-to-edge "
      "addressing.\n"
      "// The visibility leaves out the BRDF's 1/4 (so FV(1) = F0): the specular term is D * FV / "
      "4.\n"
      "// Roughness must be above 0 (the endpoint form divides by alpha^2).\n",
      comment_lang, bake.reference, o.size, o.size, o.size);
}

std::string body(const FvBake& bake, const Dialect& d) {
  const EndpointAdjustment& a = bake.adjustment;
  std::string s;
  s += fmt::format(
      "\n// One texture read per pixel (roughness and F0 are per-pixel), then FvPoly per light.\n");
  s += fmt::format("{} FvPolyFetch(float roughness, float f0)\n{{\n", d.f3);
  if (d.hlsl)
    s += "    return FvPolyTexture.SampleLevel(FvPolySampler, float2(roughness, sqrt(f0)), "
         "0).xyz;\n}\n";
  else
    s += "    return textureLod(FvPolyTexture, vec2(roughness, sqrt(f0)), 0.0).xyz;\n}\n";
  s += fmt::format("\nfloat FvPoly({} poly, float dotLH)\n{{\n", d.f3);
  s += fmt::format("    return exp2({0}({0}(poly.x, dotLH, poly.y), dotLH, poly.z));\n}}\n", d.fma);
  s += fmt::format(
      "\n// The endpoint variant without a texture: A = s(roughness) log2(V90 / f0), V90 = 4 / "
      "alpha^2,\n"
      "// s a cubic in sqrt(roughness) fitted by this bake; B = C = 0, folded and expanded like "
      "the\n"
      "// texels. Per pixel: sqrt, two log2 (one is log2(f0)) and a few FMAs.\n");
  s += fmt::format("{} FvEndpointPoly(float roughness, float f0)\n{{\n", d.f3);
  s += "    float u = sqrt(roughness);\n";
  s += fmt::format("    float s = {0}({0}({0}({1}, u, {2}), u, {3}), u, {4});\n", d.fma,
                   literal(a.c[3]), literal(a.c[2]), literal(a.c[1]), literal(a.c[0]));
  s += "    float alpha = roughness * roughness;\n";
  s += "    float log2f0 = log2(f0);\n";
  s += "    float A = s * (log2(4.0 / (alpha * alpha)) - log2f0);\n";
  s += fmt::format("    return {}(A, -2.0 * A, A + log2f0);\n}}\n", d.f3);
  return s;
}

}  // namespace

std::string fv_hlsl(const FvBake& bake, const FvLutOptions& o) {
  std::string s = header(bake, o, "HLSL");
  s += "\nTexture2D<float4> FvPolyTexture : register(t0);\n";
  s += "SamplerState FvPolySampler : register(s0);  // linear filter, clamp addressing\n";
  s += body(bake, {"float2", "float3", "mad", true});
  return s;
}

std::string fv_glsl(const FvBake& bake, const FvLutOptions& o) {
  std::string s = header(bake, o, "GLSL 4.00+");
  s += "\nuniform sampler2D FvPolyTexture;  // GL_LINEAR, GL_CLAMP_TO_EDGE; rows uploaded in file "
       "order\n";
  s += body(bake, {"vec2", "vec3", "fma", false});
  return s;
}

}  // namespace shaderfit::lut
