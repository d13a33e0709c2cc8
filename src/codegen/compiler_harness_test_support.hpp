// Test support: many generated functions in one source file and one compiler call per language,
// with the arithmetic instruction count of each function as the compiler emitted it.
#pragma once

#include <fmt/format.h>

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
