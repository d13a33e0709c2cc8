// Per-language spelling: literals, names, reserved words.
#include "codegen/spelling.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "cost/erf_helper.hpp"
#include "cost/float_text.hpp"
#include "cost/op_instructions.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/precision.hpp"

namespace shaderfit {

std::string float32_literal(double v, Language language) {
  const float f = static_cast<float>(v);
  if (!std::isfinite(f)) {
    throw Error("constant " + cost_detail::float_text(f) +
                    " is not a finite float32; code generation needs finite constants",
                SourceLocation{"formula"});
  }
  std::string t = cost_detail::float_text(f);
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

namespace {

// An operator's spelling in five columns (the tables below say which); empty: none, written out
// by the printer (GLSL clamp, C++'s 1 / std::sqrt, operators).
struct OpSpelling {
  Op op;
  std::array<std::string_view, 5> names;
};

// Float spellings, in the columns glsl, hlsl, cuda, cpp, metal (Language's order), that differ
// from the rule in `float_spellings`.
constexpr OpSpelling kFloatExceptions[] = {
    {Op::Rsqrt, {"inversesqrt", "rsqrt", "rsqrtf", "", "rsqrt"}},
    {Op::Abs, {"abs", "abs", "fabsf", "std::fabs", "fabs"}},
    {Op::Min, {"min", "min", "fminf", "std::fmin", "fmin"}},
    {Op::Max, {"max", "max", "fmaxf", "std::fmax", "fmax"}},
    {Op::Fma, {"", "", "fmaf", "std::fma", "fma"}},
    {Op::Saturate, {"", "saturate", "__saturatef", "", "saturate"}},
    {Op::Atan2, {"atan", "atan2", "atan2f", "std::atan2", "atan2"}},  // GLSL: atan(y, x)
};

// Every operator's float spelling: the exceptions above; none for the arithmetic, written as
// operators; else the operator's name in GLSL, HLSL and Metal (or the helper code generation
// writes where they lack the function: erf), name + "f" in CUDA, std::name in C++.
const std::vector<std::array<std::string, 5>>& float_spellings() {
  static const std::vector<std::array<std::string, 5>> table = [] {
    std::vector<std::array<std::string, 5>> t(kOpCount);
    for (int i = 0; i < kOpCount; ++i) {
      const Op op = static_cast<Op>(i);
      const OpInfo& info = op_info(op);
      if (info.infix || info.search == 0 || op == Op::Rcp) continue;
      const std::string name(info.name);
      const std::string shader(cost_detail::helper_of(op).empty() ? info.name
                                                                  : cost_detail::helper_of(op));
      t[static_cast<std::size_t>(i)] = {shader, shader, name + "f", "std::" + name, shader};
    }
    for (const OpSpelling& e : kFloatExceptions)
      for (std::size_t l = 0; l < 5; ++l)
        t[static_cast<std::size_t>(e.op)][l] = std::string(e.names[l]);
    return t;
  }();
  return table;
}

// Half spellings in the columns glsl, hlsl, cuda __half, cuda __half2, metal; none in C++, and
// no half form of the operators not listed (sign, select, asin ... erf). The functions' __half2
// calls (h2sqrt ...) are their cost record's (cost/op_instructions.hpp: half2_call), which the
// sass-half2 listing names; "" here.
constexpr OpSpelling kHalfSpellings[] = {
    {Op::Sqrt, {"sqrt", "sqrt", "sf_hsqrt", "", "sqrt"}},
    {Op::Rsqrt, {"inversesqrt", "rsqrt", "sf_hrsqrt", "", "rsqrt"}},
    {Op::Exp2, {"exp2", "exp2", "sf_hexp2", "", "exp2"}},
    {Op::Log2, {"log2", "log2", "sf_hlog2", "", "log2"}},
    {Op::Exp, {"exp", "exp", "sf_hexp", "", "exp"}},
    {Op::Log, {"log", "log", "sf_hlog", "", "log"}},
    {Op::Sin, {"sin", "sin", "sf_hsin", "", "sin"}},
    {Op::Cos, {"cos", "cos", "sf_hcos", "", "cos"}},
    {Op::Abs, {"abs", "abs", "__habs", "__habs2", "fabs"}},
    {Op::Min, {"min", "min", "__hmin", "__hmin2", "fmin"}},
    {Op::Max, {"max", "max", "__hmax", "__hmax2", "fmax"}},
    {Op::Fma, {"fma", "mad", "sf_hfma", "__hfma2", "fma"}},
    {Op::Saturate, {"", "saturate", "__hadd_sat", "__hadd2_sat", "saturate"}},
    // Spelled as calls only in CUDA (operators elsewhere).
    {Op::Rcp, {"", "", "sf_hrcp", "h2rcp", ""}},
    {Op::Add, {"", "", "__hadd_rn", "__hadd2_rn", ""}},
    {Op::Sub, {"", "", "__hsub_rn", "__hsub2_rn", ""}},
    {Op::Mul, {"", "", "__hmul_rn", "__hmul2_rn", ""}},
    {Op::Div, {"", "", "__hdiv", "__h2div", ""}},
    {Op::Neg, {"", "", "__hneg", "__hneg2", ""}},
};

// The CUDA __half helpers (cuda_half_helpers): for the functions cuda_fp16.h has on the device
// only, the value on the device and on the host. sin and cos: float's __sinf and __cosf
// (cuda_fp16.h's hsin and hcos reduce the argument in full range: about 23 SASS instructions per
// value against 3.5; docs/precision.md).
struct HalfHelper {
  Op op;
  const char* device;  // the __half value on the device
  const char* host;    // the float value on the host
};
constexpr HalfHelper kHalfHelpers[] = {
    {Op::Sqrt, "hsqrt(x)", "sqrtf(__half2float(x))"},
    {Op::Rsqrt, "hrsqrt(x)", "1.0f / sqrtf(__half2float(x))"},
    {Op::Rcp, "hrcp(x)", "1.0f / __half2float(x)"},
    {Op::Exp2, "hexp2(x)", "exp2f(__half2float(x))"},
    {Op::Log2, "hlog2(x)", "log2f(__half2float(x))"},
    {Op::Exp, "hexp(x)", "expf(__half2float(x))"},
    {Op::Log, "hlog(x)", "logf(__half2float(x))"},
    {Op::Sin, "__float2half(__sinf(__half2float(x)))", "sinf(__half2float(x))"},
    {Op::Cos, "__float2half(__cosf(__half2float(x)))", "cosf(__half2float(x))"},
    {Op::Fma, "__hfma(x, y, z)", "fmaf(__half2float(x), __half2float(y), __half2float(z))"},
};

}  // namespace

std::string_view call(Language l, Op op, Form form) {
  if (form == Form::Float) {
    if (static_cast<int>(op) >= kOpCount) return {};
    return float_spellings()[static_cast<std::size_t>(op)][static_cast<std::size_t>(l)];
  }
  int column = 0;
  switch (l) {
    case Language::Glsl: column = 0; break;
    case Language::Hlsl: column = 1; break;
    case Language::Cuda:
      if (form == Form::Half2)
        if (const cost_detail::OpInstructions* f = cost_detail::op_instructions(op);
            f != nullptr && !f->half2_call.empty())
          return f->half2_call;
      column = form == Form::Half2 ? 3 : 2;
      break;
    case Language::Metal: column = 4; break;
    case Language::Cpp: return {};
  }
  for (const OpSpelling& h : kHalfSpellings)
    if (h.op == op) return h.names[static_cast<std::size_t>(column)];
  return {};
}

bool has_cuda_half_helper(Op op) {
  return std::any_of(std::begin(kHalfHelpers), std::end(kHalfHelpers),
                     [op](const HalfHelper& h) { return h.op == op; });
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

std::optional<SpelledOut> spelled_out(Language l, Op op, Form form, const std::string& x) {
  const auto lit = [&](double v) { return literal(v, l, form); };
  if (op == Op::Saturate) {
    if (l == Language::Glsl) return SpelledOut{"clamp(" + x + ", " + lit(0) + ", " + lit(1) + ")", 4};
    if (l == Language::Cpp)
      return SpelledOut{"std::clamp(" + x + ", " + lit(0) + ", " + lit(1) + ")", 4};
    if (l == Language::Cuda && form != Form::Float)
      return SpelledOut{std::string(call(l, op, form)) + "(" + x + ", " + lit(0) + ")", 4};
  }
  if (op == Op::Rsqrt && l == Language::Cpp)
    return SpelledOut{lit(1) + " / std::sqrt(" + x + ")", precedence(Op::Div)};
  return std::nullopt;
}

std::string_view cpp_header(Op op) { return op == Op::Saturate ? "<algorithm>" : "<cmath>"; }

std::string literal(double v, Language l, Form form) {
  switch (form) {
    case Form::Float: return float32_literal(v, l);
    case Form::Half: return half_literal(v, l);
    case Form::Half2: break;
  }
  const std::string scalar = half_literal(v, Language::Cuda);  // __float2half(0.5f)
  return "__float2half2_rn" + scalar.substr(scalar.find('('));
}

std::string cuda_half_helpers(std::span<const Op> calls) {
  std::string out;
  for (const HalfHelper& h : kHalfHelpers) {
    if (std::find(calls.begin(), calls.end(), h.op) == calls.end()) continue;
    const bool fma = h.op == Op::Fma;
    out += fmt::format(
        "__host__ __device__ __forceinline__ __half {}({}) {{\n#ifdef __CUDA_ARCH__\n"
        "  return {};\n#else\n  return __float2half({});\n#endif\n}}\n",
        call(Language::Cuda, h.op, Form::Half), fma ? "__half x, __half y, __half z" : "__half x",
        h.device, h.host);
  }
  for (const Op c : {Op::Sin, Op::Cos}) {
    if (std::find(calls.begin(), calls.end(), c) == calls.end()) continue;
    const char* f = c == Op::Sin ? "__sinf" : "__cosf";
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
