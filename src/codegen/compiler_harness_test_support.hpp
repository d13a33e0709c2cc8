// Test support: many generated functions in one source file and one compiler call per language,
// with the arithmetic instruction count of each function as the compiler emitted it.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "codegen/toolchain_test_support.hpp"
#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit::testing {

// Per formula; -1 where the compiler output had no such function. `log` holds the compiler's
// messages when it failed (ok == false).
struct CompiledCounts {
  bool ok = false;
  std::string log;
  std::vector<int> ptx, sass, spirv;
  std::vector<int> valu;  // AMDGPU VALU instructions (compile_amdgpu)
  bool have_sass = false;
  std::map<std::string, int> spirv_functions;  // every function of the SPIR-V, by name
};

inline std::size_t input_count(const Expression& e) { return e.variables.size() + e.parameters.size(); }

// The formulas as functions f0, f1, ... exactly as `shaderfit codegen` prints them: a file that
// compiles on its own (generate_source). The compile helpers below add only entry points after it.
inline std::string printed_source(const std::vector<Expression>& formulas, Language lang) {
  std::vector<SourceFunction> functions;
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    SourceFunction f{formulas[i], {}};
    f.options.name = "f" + std::to_string(i);
    functions.push_back(std::move(f));
  }
  return generate_source(functions, lang);
}

// All formulas as CUDA functions f<i> (printed_source) and kernels k<i> after them in one .cu
// file, compiled by one nvcc call (--use_fast_math -arch=sm_90, keeping the PTX); SASS counts when
// cuobjdump is found (have_sass). A cuobjdump that is found but fails makes the result !ok.
inline CompiledCounts compile_cuda(const std::vector<Expression>& formulas, const std::string& nvcc,
                                   const std::string& folder_name) {
  const auto dir = scratch_folder(folder_name);
  std::string src = printed_source(formulas, Language::Cuda);
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    const std::size_t n = input_count(formulas[i]);
    std::string args;
    for (std::size_t k = 0; k < n; ++k) args += fmt::format("{}in[i * {} + {}]", k ? ", " : "", n, k);
    src += fmt::format(
        "extern \"C\" __global__ void k{0}(const float* __restrict__ in, float* __restrict__ out) {{\n"
        "  const int i = threadIdx.x;\n  out[i] = f{0}({1});\n}}\n",
        i, args);
  }
  write_text(dir / "all.cu", src);
  CompiledCounts r;
  const std::string cmd = fmt::format("cd '{}' && '{}' --use_fast_math -arch=sm_90 -cubin -keep -o all.cubin all.cu",
                                      dir.string(), nvcc);
  if (run_command(cmd, &r.log) != 0) return r;
  const auto ptx = count_ptx(read_text(dir / "all.ptx"));
  std::map<std::string, int> sass;
  const SassDump dumped = dump_sass(dir / "all.cubin", &sass, &r.log);
  if (dumped == SassDump::Failed) return r;
  r.have_sass = dumped == SassDump::Done;
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    const std::string k = "k" + std::to_string(i);
    r.ptx.push_back(ptx.count(k) ? ptx.at(k) : -1);
    r.sass.push_back(sass.count(k) ? sass.at(k) : -1);
  }
  r.ok = true;
  return r;
}

// All formulas as GLSL or HLSL functions f<i> (printed_source), then a compute entry point that
// calls them, in one file compiled to SPIR-V by one glslangValidator call.
inline CompiledCounts compile_spirv(const std::vector<Expression>& formulas, Language lang,
                                    const std::string& glslang, const std::string& folder_name) {
  const auto dir = scratch_folder(folder_name);
  const bool glsl = lang == Language::Glsl;
  std::string src = printed_source(formulas, lang);
  src += glsl ? "layout(local_size_x = 1) in;\n"
                "layout(std430, binding = 0) buffer Data { float data[]; };\n"
              : "RWStructuredBuffer<float> data : register(u0);\n";
  std::string body;
  std::size_t offset = formulas.size();
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    std::string args;
    for (std::size_t k = 0; k < input_count(formulas[i]); ++k) args += fmt::format("{}data[{}]", k ? ", " : "", offset++);
    body += fmt::format("  data[{}] = f{}({});\n", i, i, args);
  }
  src += glsl ? "void main() {\n" + body + "}\n" : "[numthreads(1, 1, 1)]\nvoid main() {\n" + body + "}\n";
  const std::string file = glsl ? "all.comp" : "all.hlsl";
  write_text(dir / file, src);
  CompiledCounts r;
  const std::string cmd = fmt::format("cd '{}' && '{}' -V {} -o all.spv {}", dir.string(), glslang,
                                      glsl ? "" : "-D -Od -S comp -e main", file);
  if (run_command(cmd, &r.log) != 0) return r;
  const auto counts = count_spirv(read_text(dir / "all.spv"));
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    const std::string f = "f" + std::to_string(i);
    r.spirv.push_back(counts.count(f) ? counts.at(f) : -1);
  }
  r.spirv_functions = counts;
  r.ok = true;
  return r;
}

// sign, copysign and select formulas that the compiler checks share (compiler_check_test.cpp,
// rdna_check_test.cpp). The kernels read their inputs from memory; a select of a bare input would
// become a predicated load there, which no shader's register inputs allow, so the branches are
// computed values, literals or values read twice.
inline constexpr const char* kNewOperators[] = {
    "select(x - y >= 0, x * y, x + 1)",
    "select(x >= 0, 2, 0.5) * y",
    "sign(x) * y + sign(y)",
    "copysign(x, y) * copysign(1, y) + copysign(x * x, -y)",
    "select(-x >= 0, y, x * x) + select(-x >= 0, x * x, y) * y",
    "select(x * y >= 0, sqrt(x), rcp(y))",
    "sign(x - y) * copysign(y, x - y)",
    "select(x < y, x * 2, y * 3) - select(y > x, x + 1, y * y)",
    "sign(x * y + 1) * (x + y)",
    "copysign(x + y, x - y) * 0.5",
};

// asin, acos, atan, atan2, tanh and erf in formulas, as the compiler checks count them.
inline constexpr const char* kLibraryOperators[] = {
    "asin(x) * y",      "acos(x * y)",          "atan(x) + y",      "atan2(x, y) * 2",
    "tanh(x * y + 1)",  "erf(x) * y",           "atan(-x * y) * y", "asin(-x * y)",
    "acos(1 - x)",      "atan2(x, -(x * y))",   "-atan(x)",         "acos(-x * y)",
    "atan2(-x, y + 1)", "erf(x - y) + tanh(x)", "erf(x) + erf(y)",  "atan(x, y)",
};

// A clang that compiles OpenCL C for `mcpu` (gfx1030, gfx1100): clang-15, then clang (clang 14
// has gfx1030 but not gfx1100); nullopt when none has the AMDGPU target or the processor.
inline std::optional<std::string> find_amdgpu_clang(const std::string& mcpu) {
  for (const char* name : {"clang-15", "clang"}) {
    const auto path = find_tool(name);
    if (!path) continue;
    std::string log;
    const std::string cmd = fmt::format(
        "echo 'kernel void k(global float* o) {{ o[0] = 1.0f; }}' | '{}' -x cl -cl-std=CL2.0 -target "
        "amdgcn-amd-amdhsa -mcpu={} -nogpulib -S -o /dev/null -",
        *path, mcpu);
    if (run_command(cmd, &log) == 0) return path;
  }
  return std::nullopt;
}

// ROCm's device library folder (Debian's rocm-device-libs: ocml.bc and its option files), for
// the library functions; nullopt where absent.
inline std::optional<std::filesystem::path> find_ocml() {
  const std::filesystem::path dir = "/usr/lib/x86_64-linux-gnu/amdgcn/bitcode";
  std::error_code ec;
  if (std::filesystem::is_regular_file(dir / "ocml.bc", ec)) return dir;
  return std::nullopt;
}

// A VALU operation that is no arithmetic of the formula: a move (v_mov_b32: constants and
// copies), or address arithmetic (the work-item id times 4, 64-bit shifts and carries).
inline bool amdgpu_bookkeeping(const std::string& ins) {
  for (const char* prefix : {"v_mov_b32", "v_dual_mov_b32", "v_lshlrev_b64", "v_add_co_", "v_add_co_ci_"})
    if (starts_with(ins, prefix)) return true;
  return (starts_with(ins, "v_lshlrev_b32") || starts_with(ins, "v_dual_lshlrev_b32")) &&
         ins.find(", 2, v0") != std::string::npos;
}

// VALU instructions per kernel of AMDGPU assembly but amdgpu_bookkeeping's; a VOPD pair of
// RDNA 3 (v_dual_a ... :: v_dual_b ...) counts as its operations.
inline std::map<std::string, int> count_amdgpu(const std::string& assembly) {
  std::map<std::string, int> out;
  std::istringstream lines(assembly);
  std::string kernel;
  for (std::string line; std::getline(lines, line);) {
    const std::size_t colon = line.find(':');
    if (colon != std::string::npos && colon > 0 &&
        std::all_of(line.begin(), line.begin() + static_cast<std::ptrdiff_t>(colon),
                    [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) != 0 || ch == '_'; })) {
      kernel = line.substr(0, line.find(':'));
      out[kernel] = 0;
      continue;
    }
    std::size_t at = line.find_first_not_of(" \t");
    if (kernel.empty() || at == std::string::npos || line.compare(at, 2, "v_") != 0) continue;
    const std::string ins = line.substr(at);
    const std::size_t second = ins.find(" :: ");
    if (second == std::string::npos) {
      out[kernel] += amdgpu_bookkeeping(ins) ? 0 : 1;
    } else {
      out[kernel] += amdgpu_bookkeeping(ins.substr(0, second)) ? 0 : 1;
      out[kernel] += amdgpu_bookkeeping(ins.substr(second + 4)) ? 0 : 1;
    }
  }
  return out;
}

// All formulas as the CUDA functions of printed_source and OpenCL kernels k<i> after them, one
// file compiled by one clang call as OpenCL C for an AMD GPU (-O3 -cl-fast-relaxed-math,
// -mcpu=gfx1030 or gfx1100), the CUDA math functions defined as clang's built-ins (which lower to
// the hardware's instructions under fast math) and the library functions as ROCm's OCML ones
// (linked from `ocml` where given; else they stay calls and the count means nothing). Each
// kernel reads its inputs at the work-item's index; the counts are count_amdgpu's, in `valu`.
inline CompiledCounts compile_amdgpu(const std::vector<Expression>& formulas, const std::string& clang,
                                     const std::string& mcpu, const std::string& folder_name,
                                     const std::optional<std::filesystem::path>& ocml = std::nullopt) {
  const auto dir = scratch_folder(folder_name);
  std::string src =
      "#define __device__\n#define __forceinline__ static inline __attribute__((always_inline))\n"
      "#define sqrtf __builtin_sqrtf\n#define rsqrtf(x) (1.0f / __builtin_sqrtf(x))\n"
      "#define exp2f __builtin_exp2f\n#define log2f __builtin_log2f\n#define expf __builtin_expf\n"
      "#define logf __builtin_logf\n#define sinf __builtin_sinf\n#define cosf __builtin_cosf\n"
      "#define fabsf __builtin_fabsf\n#define fminf __builtin_fminf\n#define fmaxf __builtin_fmaxf\n"
      "#define fmaf __builtin_fmaf\n#define copysignf __builtin_copysignf\n"
      "#define __saturatef(x) __builtin_fminf(__builtin_fmaxf((x), 0.0f), 1.0f)\n"
      "float __ocml_asin_f32(float); float __ocml_acos_f32(float); float __ocml_atan_f32(float);\n"
      "float __ocml_atan2_f32(float, float); float __ocml_tanh_f32(float); float __ocml_erf_f32(float);\n"
      "#define asinf __ocml_asin_f32\n#define acosf __ocml_acos_f32\n#define atanf __ocml_atan_f32\n"
      "#define atan2f __ocml_atan2_f32\n#define tanhf __ocml_tanh_f32\n#define erff __ocml_erf_f32\n";
  src += printed_source(formulas, Language::Cuda);
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    const std::size_t n = input_count(formulas[i]);
    std::string params, args;
    for (std::size_t k = 0; k < n; ++k) {
      params += fmt::format(", __global const float* restrict in{}", k);
      args += fmt::format("{}in{}[g]", k ? ", " : "", k);
    }
    src += fmt::format(
        "__kernel void k{0}(__global float* restrict out{1}) {{\n"
        "  const uint g = __builtin_amdgcn_workitem_id_x();\n  out[g] = f{0}({2});\n}}\n",
        i, params, args);
  }
  write_text(dir / "all.cl", src);
  std::string link;
  if (ocml) {
    for (const char* f : {"ocml", "oclc_unsafe_math_on", "oclc_finite_only_on", "oclc_daz_opt_on",
                          "oclc_correctly_rounded_sqrt_off", "oclc_wavefrontsize64_off",
                          "oclc_isa_version_1030", "oclc_abi_version_400"})
      link += fmt::format(" -Xclang -mlink-builtin-bitcode -Xclang '{}'", (*ocml / (std::string(f) + ".bc")).string());
  }
  CompiledCounts r;
  const std::string cmd = fmt::format(
      "cd '{}' && '{}' -x cl -cl-std=CL2.0 -target amdgcn-amd-amdhsa -mcpu={} -O3 "
      "-cl-fast-relaxed-math -nogpulib{} -S -o all.s all.cl",
      dir.string(), clang, mcpu, link);
  if (run_command(cmd, &r.log) != 0) return r;
  const auto counts = count_amdgpu(read_text(dir / "all.s"));
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    const std::string k = "k" + std::to_string(i);
    r.valu.push_back(counts.count(k) ? counts.at(k) : -1);
  }
  r.ok = true;
  return r;
}

// A random formula of the kind the search produces: sums, products, quotients and integer powers
// of the inputs and small constants, with now and then a function call.
inline void grow_formula(Rng& rng, Expression& e, int depth) {
  if (depth <= 0 || bernoulli(rng, 0.3)) {
    if (bernoulli(rng, 0.7)) {
      e.nodes.push_back(Node::variable(static_cast<int>(uniform_index(rng, e.variables.size()))));
    } else {
      static constexpr double kConsts[] = {1.0, 0.5, 2.0, -1.0, 0.25, 3.0, -2.5, 0.1, 1.5};
      e.nodes.push_back(Node::constant(kConsts[uniform_index(rng, std::size(kConsts))]));
    }
    return;
  }
  static constexpr Op kOps[] = {Op::Add, Op::Add, Op::Sub, Op::Sub, Op::Mul, Op::Mul, Op::Mul, Op::Div,
                                Op::IPow, Op::IPow, Op::Neg, Op::Fma, Op::Sqrt, Op::Rsqrt, Op::Rcp,
                                Op::Exp2, Op::Log2, Op::Exp, Op::Log, Op::Abs, Op::Saturate, Op::Sin,
                                Op::Cos, Op::Min, Op::Max, Op::Pow};
  const Op op = kOps[uniform_index(rng, std::size(kOps))];
  for (int k = 0; k < arity(op); ++k) grow_formula(rng, e, depth - 1);
  if (op == Op::IPow) {
    static constexpr int kPowers[] = {2, 2, 3, 4, 4, 5, 8, -1, -2};
    e.nodes.push_back(Node::ipow(kPowers[uniform_index(rng, std::size(kPowers))]));
  } else {
    e.nodes.push_back(Node::op_node(op));
  }
}

inline Expression random_formula(Rng& rng, const std::vector<std::string>& inputs, int depth) {
  Expression e;
  e.variables = inputs;
  grow_formula(rng, e, depth);
  e.update_lengths();
  return e;
}

// `count` random formulas with at least one operator whose constants stay finite once folded
// (code generation refuses NaN and infinite literals).
inline std::vector<Expression> random_formulas(Rng& rng, std::size_t count, const std::vector<std::string>& inputs) {
  std::vector<Expression> out;
  while (out.size() < count) {
    Expression e = random_formula(rng, inputs, 1 + static_cast<int>(uniform_index(rng, 4)));
    if (e.nodes.size() < 2) continue;
    try {
      (void)generate_function(e, CodegenOptions{});
    } catch (const Error&) {
      continue;
    }
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace shaderfit::testing
