// Per-language spelling: literals, names, reserved words.
#include "codegen/spelling.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "cost/erf_helper.hpp"
#include "cost/float_text.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/precision.hpp"

namespace shaderfit {

std::string float32_literal(double v, Language language) {
  const float f = static_cast<float>(v);
  if (!std::isfinite(f)) {
    throw Error("constant " + lowering::float_text(f) +
                    " is not a finite float32; code generation needs finite constants",
                SourceLocation{"formula"});
  }
  std::string t = lowering::float_text(f);
  if (t.find_first_of(".e") == std::string::npos) t += ".0";
  if (language != Language::Glsl) t += 'f';
  return t;
}

namespace {

// The shortest decimal text ("0.1", "1.0", "6.55e+04") of the binary16 value h that reads back
// to h both when rounded to binary16 directly and when rounded to float32 first (a compiler may
// read a half literal either way).
std::string half_text(double h) {
  std::string t;
  for (int digits = 1; digits <= 17; ++digits) {
    t = fmt::format("{:.{}g}", h, digits);
    if (round_to_half(std::strtod(t.c_str(), nullptr)) == h &&
        round_to_half(static_cast<double>(std::strtof(t.c_str(), nullptr))) == h)
      break;
  }
  if (t.find_first_of(".e") == std::string::npos) t += ".0";
  return t;
}

}  // namespace

std::string half_literal(double v, Language language) {
  const double h = round_to_half(v);
  if (!std::isfinite(h)) {
    throw Error(fmt::format("constant {} is not a finite binary16 value (half holds magnitudes "
                            "below 65520); code generation needs finite constants",
                            v),
                SourceLocation{"formula"});
  }
  const std::string t = half_text(h);
  switch (language) {
    case Language::Glsl: return t + "hf";
    case Language::Hlsl:
    case Language::Metal: return t + "h";
    case Language::Cuda: return "__float2half(" + t + "f)";
    case Language::Cpp: break;
  }
  throw Error(
      "C++ has no half type that both g++ and clang++ compile (clang++ 14 rejects "
      "_Float16 on x86-64); for half code on the CPU use CUDA's __half (--lang cuda)",
      SourceLocation{"CodegenOptions::precision"});
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
    "abs",
    "active",
    "alignas",
    "alignof",
    "and",
    "asm",
    "attribute",
    "auto",
    "bool",
    "break",
    "buffer",
    "case",
    "catch",
    "cbuffer",
    "centroid",
    "char",
    "clamp",
    "class",
    "coherent",
    "column_major",
    "common",
    "compile",
    "const",
    "constant",
    "constexpr",
    "continue",
    "cos",
    "cosf",
    "default",
    "delete",
    "device",
    "discard",
    "do",
    "double",
    "dvec2",
    "dvec3",
    "dvec4",
    "else",
    "enum",
    "exp",
    "exp2",
    "exp2f",
    "expf",
    "explicit",
    "extern",
    "fabs",
    "fabsf",
    "false",
    "filter",
    "fixed",
    "flat",
    "float",
    "float2",
    "float3",
    "float4",
    "fma",
    "fmaf",
    "fmax",
    "fmaxf",
    "fmin",
    "fminf",
    "for",
    "fragment",
    "friend",
    "goto",
    "groupshared",
    "half",
    "highp",
    "if",
    "in",
    "inline",
    "inout",
    "input",
    "int",
    "inversesqrt",
    "invariant",
    "kernel",
    "layout",
    "line",
    "linear",
    "log",
    "log2",
    "log2f",
    "logf",
    "long",
    "lowp",
    "mat2",
    "mat3",
    "mat4",
    "matrix",
    "max",
    "mediump",
    "min",
    "mutable",
    "namespace",
    "new",
    "noexcept",
    "noperspective",
    "nointerpolation",
    "not",
    "nullptr",
    "operator",
    "or",
    "out",
    "output",
    "packoffset",
    "partition",
    "pass",
    "patch",
    "point",
    "precise",
    "precision",
    "private",
    "protected",
    "public",
    "readonly",
    "register",
    "restrict",
    "return",
    "row_major",
    "rsqrt",
    "rsqrtf",
    "sample",
    "sampler",
    "saturate",
    "shared",
    "short",
    "signed",
    "sin",
    "sinf",
    "sizeof",
    "smooth",
    "snorm",
    "sqrt",
    "sqrtf",
    "static",
    "std",
    "string",
    "struct",
    "subroutine",
    "switch",
    "tbuffer",
    "technique",
    "template",
    "texture",
    "this",
    "thread",
    "threadgroup",
    "throw",
    "triangle",
    "true",
    "try",
    "typedef",
    "typename",
    "uint",
    "uniform",
    "union",
    "unorm",
    "unsigned",
    "using",
    "varying",
    "vec2",
    "vec3",
    "vec4",
    "vector",
    "vertex",
    "virtual",
    "void",
    "volatile",
    "while",
    "writeonly",
    "xor",
    // copysign and its bit-level spellings (GLSL, HLSL)
    "asfloat",
    "asuint",
    "copysign",
    "copysignf",
    "floatBitsToUint",
    "uintBitsToFloat",
    // asin ... erf, and the erf helper of GLSL, HLSL and Metal (cost/erf_helper.hpp)
    "acos",
    "acosf",
    "asin",
    "asinf",
    "atan",
    "atan2",
    "atan2f",
    "atanf",
    "erf",
    "erff",
    "sf_erf",
    "tanh",
    "tanhf",
    // half forms: GLSL's type, cuda_fp16.h's functions and the helpers that call them
    "float16_t",
    "h2cos",
    "h2exp",
    "h2exp2",
    "h2log",
    "h2log2",
    "h2rcp",
    "h2rsqrt",
    "h2sin",
    "h2sqrt",
    "hcos",
    "hexp",
    "hexp2",
    "hlog",
    "hlog2",
    "hrcp",
    "hrsqrt",
    "hsin",
    "hsqrt",
    "sf_h2cos",
    "sf_h2sin",
    "sf_hcos",
    "sf_hexp",
    "sf_hexp2",
    "sf_hfma",
    "sf_hlog",
    "sf_hlog2",
    "sf_hrcp",
    "sf_hrsqrt",
    "sf_hsin",
    "sf_hsqrt",
};

}  // namespace

void check_name(const std::string& name, std::string_view what, const SourceLocation& where) {
  const bool ident =
      !name.empty() && (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
      std::all_of(name.begin(), name.end(),
                  [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
  if (!ident) throw Error(std::string(what) + " '" + name + "' is not an identifier", where);
  if (name.find("__") != std::string::npos || name.rfind("gl_", 0) == 0) {
    throw Error(std::string(what) + " '" + name +
                    "' is reserved in GLSL and C++ (it starts with gl_ or holds __)",
                where);
  }
  if (std::find(std::begin(kReserved), std::end(kReserved), name) != std::end(kReserved)) {
    throw Error(std::string(what) + " '" + name +
                    "' is a reserved word or a function the generated code calls",
                where);
  }
}

std::string_view call(Language l, Call c, Form form) {
  if (form != Form::Float) {
    // Half spellings in the order glsl, hlsl, cuda __half, cuda __half2, metal; none in C++.
    static constexpr std::string_view kHalf[][5] = {
        {"sqrt", "sqrt", "sf_hsqrt", "h2sqrt", "sqrt"},
        {"inversesqrt", "rsqrt", "sf_hrsqrt", "h2rsqrt", "rsqrt"},
        {"exp2", "exp2", "sf_hexp2", "h2exp2", "exp2"},
        {"log2", "log2", "sf_hlog2", "h2log2", "log2"},
        {"exp", "exp", "sf_hexp", "h2exp", "exp"},
        {"log", "log", "sf_hlog", "h2log", "log"},
        {"sin", "sin", "sf_hsin", "sf_h2sin", "sin"},
        {"cos", "cos", "sf_hcos", "sf_h2cos", "cos"},
        {"abs", "abs", "__habs", "__habs2", "fabs"},
        {"min", "min", "__hmin", "__hmin2", "fmin"},
        {"max", "max", "__hmax", "__hmax2", "fmax"},
        {"fma", "mad", "sf_hfma", "__hfma2", "fma"},
        {"", "saturate", "__hadd_sat", "__hadd2_sat", "saturate"},
        // asin ... erf: no half form
        {},
        {},
        {},
        {},
        {},
        {},
        {"", "", "sf_hrcp", "h2rcp", ""},
        {"", "", "__hadd_rn", "__hadd2_rn", ""},
        {"", "", "__hsub_rn", "__hsub2_rn", ""},
        {"", "", "__hmul_rn", "__hmul2_rn", ""},
        {"", "", "__hdiv", "__h2div", ""},
        {"", "", "__hneg", "__hneg2", ""},
    };
    int column = 0;
    switch (l) {
      case Language::Glsl: column = 0; break;
      case Language::Hlsl: column = 1; break;
      case Language::Cuda: column = form == Form::Half2 ? 3 : 2; break;
      case Language::Metal: column = 4; break;
      case Language::Cpp: return {};
    }
    return kHalf[static_cast<int>(c)][column];
  }
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
      // rcp and the operators: written as operators
      {},
      {},
      {},
      {},
      {},
      {},
  };
  return kNames[static_cast<int>(c)][static_cast<int>(l)];
}

std::string_view value_type(Language l, Form form) {
  switch (form) {
    case Form::Float: return "float";
    case Form::Half2: return "__half2";
    case Form::Half: break;
  }
  switch (l) {
    case Language::Glsl: return "float16_t";
    case Language::Cuda: return "__half";
    default: return "half";
  }
}

std::string literal(double v, Language l, Form form) {
  switch (form) {
    case Form::Float: return float32_literal(v, l);
    case Form::Half: return half_literal(v, l);
    case Form::Half2: break;
  }
  const std::string scalar = half_literal(v, Language::Cuda);  // __float2half(0.5f)
  return "__float2half2_rn" + scalar.substr(scalar.find('('));
}

std::string cuda_half_helpers(std::span<const Call> calls) {
  struct Helper {
    Call call;
    const char* device;  // the __half value on the device
    const char* host;    // the float value on the host
  };
  // sin and cos: float's __sinf and __cosf (cuda_fp16.h's hsin and hcos reduce the argument in
  // full range: about 23 SASS instructions per value against 3.5; docs/precision.md).
  static constexpr Helper kHelpers[] = {
      {Call::Sqrt, "hsqrt(x)", "sqrtf(__half2float(x))"},
      {Call::Rsqrt, "hrsqrt(x)", "1.0f / sqrtf(__half2float(x))"},
      {Call::Rcp, "hrcp(x)", "1.0f / __half2float(x)"},
      {Call::Exp2, "hexp2(x)", "exp2f(__half2float(x))"},
      {Call::Log2, "hlog2(x)", "log2f(__half2float(x))"},
      {Call::Exp, "hexp(x)", "expf(__half2float(x))"},
      {Call::Log, "hlog(x)", "logf(__half2float(x))"},
      {Call::Sin, "__float2half(__sinf(__half2float(x)))", "sinf(__half2float(x))"},
      {Call::Cos, "__float2half(__cosf(__half2float(x)))", "cosf(__half2float(x))"},
      {Call::Fma, "__hfma(x, y, z)", "fmaf(__half2float(x), __half2float(y), __half2float(z))"},
  };
  std::string out;
  for (const Helper& h : kHelpers) {
    if (std::find(calls.begin(), calls.end(), h.call) == calls.end()) continue;
    const bool fma = h.call == Call::Fma;
    out += fmt::format(
        "__host__ __device__ __forceinline__ __half {}({}) {{\n#ifdef __CUDA_ARCH__\n"
        "  return {};\n#else\n  return __float2half({});\n#endif\n}}\n",
        call(Language::Cuda, h.call, Form::Half), fma ? "__half x, __half y, __half z" : "__half x",
        h.device, h.host);
  }
  for (const Call c : {Call::Sin, Call::Cos}) {
    if (std::find(calls.begin(), calls.end(), c) == calls.end()) continue;
    const char* f = c == Call::Sin ? "__sinf" : "__cosf";
    out += fmt::format(
        "__device__ __forceinline__ __half2 {}(__half2 x) {{\n"
        "  return __floats2half2_rn({}(__low2float(x)), {}(__high2float(x)));\n}}\n",
        call(Language::Cuda, c, Form::Half2), f, f);
  }
  if (out.empty()) return out;
  return "// cuda_fp16.h has hsqrt, hexp2, __hfma, ... on the device only: on the host\n"
         "// these compute in float and round once to half.\n" +
         out;
}

}  // namespace codegen

}  // namespace shaderfit
