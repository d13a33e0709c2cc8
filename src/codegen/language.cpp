// Per-language spelling: literals, names, reserved words.
#include "codegen/language.hpp"

#include <algorithm>
#include <cmath>

#include "cost/erf_helper.hpp"
#include "cost/float_text.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit {

std::string float32_literal(double v, Language language) {
  const float f = static_cast<float>(v);
  if (!std::isfinite(f)) {
    throw Error("constant " + lowering::float_text(f) + " is not a finite float32; code generation needs finite constants",
                SourceLocation{"formula"});
  }
  std::string t = lowering::float_text(f);
  if (t.find_first_of(".e") == std::string::npos) t += ".0";
  if (language != Language::Glsl) t += 'f';
  return t;
}

std::optional<Language> language_from_name(std::string_view name) {
  if (name == "glsl") return Language::Glsl;
  if (name == "hlsl") return Language::Hlsl;
  if (name == "cuda") return Language::Cuda;
  if (name == "cpp" || name == "c++") return Language::Cpp;
  if (name == "metal") return Language::Metal;
  return std::nullopt;
}

std::string_view language_name(Language language) {
  switch (language) {
    case Language::Glsl: return "glsl";
    case Language::Hlsl: return "hlsl";
    case Language::Cuda: return "cuda";
    case Language::Cpp: return "cpp";
    case Language::Metal: return "metal";
  }
  return "glsl";
}

namespace codegen {

namespace {

// Words a name may not be in any of the languages (keywords, types, qualifiers), plus the
// functions the generated code calls: one list keeps the check simple and the output portable.
constexpr std::string_view kReserved[] = {
    "abs", "active", "alignas", "alignof", "and", "asm", "attribute", "auto", "bool", "break", "buffer",
    "case", "catch", "cbuffer", "centroid", "char", "clamp", "class", "coherent", "column_major",
    "common", "compile", "const", "constant", "constexpr", "continue", "cos", "cosf", "default",
    "delete", "device", "discard", "do", "double", "dvec2", "dvec3", "dvec4", "else", "enum", "exp",
    "exp2", "exp2f", "expf", "explicit", "extern", "fabs", "fabsf", "false", "filter", "fixed",
    "flat", "float", "float2", "float3", "float4", "fma", "fmaf", "fmax", "fmaxf", "fmin", "fminf",
    "for", "fragment", "friend", "goto", "groupshared", "half", "highp", "if", "in", "inline",
    "inout", "input", "int", "inversesqrt", "invariant", "kernel", "layout", "line", "linear",
    "log", "log2", "log2f", "logf", "long", "lowp", "mat2", "mat3", "mat4", "matrix", "max",
    "mediump", "min", "mutable", "namespace", "new", "noexcept", "noperspective",
    "nointerpolation", "not", "nullptr", "operator", "or", "out", "output", "packoffset",
    "partition", "pass", "patch", "point", "precise", "precision", "private", "protected",
    "public", "readonly", "register", "restrict", "return", "row_major", "rsqrt", "rsqrtf",
    "sample", "sampler", "saturate", "shared", "short", "signed", "sin", "sinf", "sizeof",
    "smooth", "snorm", "sqrt", "sqrtf", "static", "std", "string", "struct", "subroutine",
    "switch", "tbuffer", "technique", "template", "texture", "this", "thread", "threadgroup",
    "throw", "triangle", "true", "try", "typedef", "typename", "uint", "uniform", "union",
    "unorm", "unsigned", "using", "varying", "vec2", "vec3", "vec4", "vector", "vertex",
    "virtual", "void", "volatile", "while", "writeonly", "xor",
    // copysign and its bit-level spellings (GLSL, HLSL)
    "asfloat", "asuint", "copysign", "copysignf", "floatBitsToUint", "uintBitsToFloat",
    // asin ... erf, and the erf helper of GLSL, HLSL and Metal (cost/erf_helper.hpp)
    "acos", "acosf", "asin", "asinf", "atan", "atan2", "atan2f", "atanf", "erf", "erff", "sf_erf",
    "tanh", "tanhf",
};

}  // namespace

void check_name(const std::string& name, std::string_view what, const SourceLocation& where) {
  const bool ident = !name.empty() && (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
                     std::all_of(name.begin(), name.end(), [](char c) {
                       return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
                     });
  if (!ident) throw Error(std::string(what) + " '" + name + "' is not an identifier", where);
  if (name.find("__") != std::string::npos || name.rfind("gl_", 0) == 0) {
    throw Error(std::string(what) + " '" + name + "' is reserved in GLSL and C++ (it starts with gl_ or holds __)", where);
  }
  if (std::find(std::begin(kReserved), std::end(kReserved), name) != std::end(kReserved)) {
    throw Error(std::string(what) + " '" + name + "' is a reserved word or a function the generated code calls", where);
  }
}

std::string_view call(Language l, Call c) {
  // Spellings per language, in the order glsl, hlsl, cuda, cpp, metal.
  static constexpr std::string_view kNames[][5] = {
      {"sqrt", "sqrt", "sqrtf", "std::sqrt", "sqrt"},
      {"inversesqrt", "rsqrt", "rsqrtf", "", "rsqrt"},
      {"exp2", "exp2", "exp2f", "std::exp2", "exp2"},
      {"log2", "log2", "log2f", "std::log2", "log2"},
      {"exp", "exp", "expf", "std::exp", "exp"},
      {"log", "log", "logf", "std::log", "log"},
      {"sin", "sin", "sinf", "std::sin", "sin"},
      {"cos", "cos", "cosf", "std::cos", "cos"},
      {"abs", "abs", "fabsf", "std::fabs", "fabs"},
      {"min", "min", "fminf", "std::fmin", "fmin"},
      {"max", "max", "fmaxf", "std::fmax", "fmax"},
      {"", "", "fmaf", "std::fma", "fma"},
      {"", "saturate", "__saturatef", "", "saturate"},
      {"asin", "asin", "asinf", "std::asin", "asin"},
      {"acos", "acos", "acosf", "std::acos", "acos"},
      {"atan", "atan", "atanf", "std::atan", "atan"},
      {"atan", "atan2", "atan2f", "std::atan2", "atan2"},  // GLSL: atan(y, x)
      {"tanh", "tanh", "tanhf", "std::tanh", "tanh"},
      {lowering::kErfHelperName, lowering::kErfHelperName, "erff", "std::erf",
       lowering::kErfHelperName},
  };
  return kNames[static_cast<int>(c)][static_cast<int>(l)];
}

}  // namespace codegen

}  // namespace shaderfit
