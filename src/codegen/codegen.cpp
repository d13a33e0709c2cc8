#include "shaderfit/codegen/codegen.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <regex>
#include <set>
#include <span>

#include "codegen/language.hpp"
#include "cost/dag.hpp"
#include "cost/erf_helper.hpp"
#include "cost/program.hpp"

namespace shaderfit {

namespace {

using lowering::Operand;
using lowering::Program;
using lowering::Step;
using lowering::StepOp;

// A printed value: its text and its precedence (1 sum, 2 product, 3 unary minus, 4 atom/call).
struct Text {
  std::string s;
  int level = 4;
};

class FunctionPrinter {
 public:
  FunctionPrinter(const Expression& e, const CodegenOptions& o, const Program& p)
      : e_(e), o_(o), p_(p), lang_(o.language), texts_(p.steps.size()) {}

  std::string print() {
    std::string body;
    if (o_.bake_parameters) {
      for (std::size_t i = 0; i < e_.parameters.size(); ++i) {
        const double v = i < e_.parameter_values.size() ? e_.parameter_values[i] : 0.0;
        body +=
            fmt::format("  const float {} = {};\n", e_.parameters[i], float32_literal(v, lang_));
      }
    }
    // The operands of sign and select are named: sign reads its operand more than once, and
    // glslang compiles a ?: of named values to OpSelect (of expressions, to branches).
    std::vector<bool> named(p_.steps.size(), false);
    for (const Step& st : p_.steps) {
      if (st.op != StepOp::Sign && st.op != StepOp::Select) continue;
      for (int k = 0; k < st.arity; ++k)
        if (st.args[k].kind == Operand::Kind::Step)
          named[static_cast<std::size_t>(st.args[k].index)] = true;
    }
    for (std::size_t i = 0; i < p_.steps.size(); ++i) {
      Text t = step(p_.steps[i]);
      if (p_.steps[i].uses > 1 || named[i]) t = {temporary(t.s), 4};
      texts_[i] = std::move(t);
    }
    body_ += "  return " + operand(p_.result, 0) + ";\n";
    body += body_;

    std::string out;
    for (const std::string& line : o_.comment) out += "// " + line + "\n";
    out += signature() + " {\n" + body + "}\n";
    return out;
  }

 private:
  // Declares a temporary holding `value` and returns its name.
  std::string temporary(const std::string& value) {
    const std::string name = temp_prefix() + std::to_string(temps_++);
    body_ += fmt::format("  {}float {} = {};\n",
                         lang_ == Language::Glsl || lang_ == Language::Hlsl ? "" : "const ", name,
                         value);
    return name;
  }

  std::string temp_prefix() const {
    std::string prefix = "t";
    const std::regex taken("^_*t[0-9]+$");
    for (bool clash = true; clash;) {
      clash = false;
      for (const auto* names : {&e_.variables, &e_.parameters})
        for (const std::string& n : *names)
          if (std::regex_match(n, taken) && n.rfind(prefix, 0) == 0) clash = true;
      if (clash) prefix = "_" + prefix;
    }
    return prefix;
  }

  std::string signature() const {
    std::string args;
    auto add = [&](const std::string& n) { args += (args.empty() ? "float " : ", float ") + n; };
    for (const std::string& v : e_.variables) add(v);
    if (!o_.bake_parameters)
      for (const std::string& v : e_.parameters) add(v);
    switch (lang_) {
      case Language::Cuda: return "__device__ __forceinline__ float " + o_.name + "(" + args + ")";
      case Language::Cpp:
      case Language::Metal: return "inline float " + o_.name + "(" + args + ")";
      default: return "float " + o_.name + "(" + args + ")";
    }
  }

  std::string lit(float v) const { return float32_literal(v, lang_); }

  std::string operand(const Operand& o, int min_level) const {
    Text t;
    switch (o.kind) {
      case Operand::Kind::Const: t = {lit(o.value), o.value < 0 ? 3 : 4}; break;
      case Operand::Kind::Var: t = {e_.variables[static_cast<std::size_t>(o.index)], 4}; break;
      case Operand::Kind::Param: t = {e_.parameters[static_cast<std::size_t>(o.index)], 4}; break;
      default: t = texts_[static_cast<std::size_t>(o.index)]; break;
    }
    return t.level < min_level ? "(" + t.s + ")" : t.s;
  }

  Text fn(codegen::Call c, const Step& st) const {
    std::string s = std::string(codegen::call(lang_, c)) + "(";
    for (int k = 0; k < st.arity; ++k) s += (k ? ", " : "") + operand(st.args[k], 0);
    return {s + ")", 4};
  }

  bool shader() const { return lang_ == Language::Glsl || lang_ == Language::Hlsl; }

  // The bits of a float as an unsigned integer and back (GLSL, HLSL: they have no copysign).
  std::string to_bits(const std::string& x) const {
    return (lang_ == Language::Glsl ? "floatBitsToUint(" : "asuint(") + x + ")";
  }
  std::string from_bits(const std::string& x) const {
    return (lang_ == Language::Glsl ? "uintBitsToFloat(" : "asfloat(") + x + ")";
  }

  // Exactly op.hpp's meaning in every language (docs/codegen.md, "Sign, copysign, select").
  Text sign(const Step& st) {
    const std::string x = operand(st.args[0], 4);
    if (shader()) {
      // x > 0 ? 1 : (x < 0 ? -1 : x), the inner select named so that both become OpSelect.
      const std::string inner = temporary(x + " < " + lit(0.0f) + " ? " + lit(-1.0f) + " : " + x);
      return {x + " > " + lit(0.0f) + " ? " + lit(1.0f) + " : " + inner, 0};
    }
    const char* abs =
        lang_ == Language::Cuda ? "fabsf" : (lang_ == Language::Cpp ? "std::fabs" : "fabs");
    return {std::string(abs) + "(" + x + ") > " + lit(0.0f) + " ? " + std::string(copysign_name()) +
                "(" + lit(1.0f) + ", " + x + ") : " + x,
            0};
  }
  const char* copysign_name() const {
    return lang_ == Language::Cuda ? "copysignf"
                                   : (lang_ == Language::Cpp ? "std::copysign" : "copysign");
  }
  Text copysign(const Step& st) const {
    const std::string b = operand(st.args[1], 0);
    if (!shader())
      return {std::string(copysign_name()) + "(" + operand(st.args[0], 0) + ", " + b + ")", 4};
    // |a| with b's sign bit; a literal a is written as the bits of |a|.
    const Operand& a = st.args[0];
    const std::string magnitude =
        a.kind == Operand::Kind::Const
            ? fmt::format("0x{:08x}u", std::bit_cast<std::uint32_t>(std::fabs(a.value)))
            : "(" + to_bits(operand(a, 0)) + " & 0x7fffffffu)";
    return {from_bits(magnitude + " | (" + to_bits(b) + " & 0x80000000u)"), 4};
  }
  // a >= 0 ? b : c, or a <= 0 ? b : c for the negated condition -a >= 0.
  Text select(const Step& st) const {
    return {operand(st.args[0], 1) + (st.neg_arg ? " <= " : " >= ") + lit(0.0f) + " ? " +
                operand(st.args[1], 1) + " : " + operand(st.args[2], 1),
            0};
  }

  Text step(const Step& st) {
    using codegen::Call;
    auto bin = [&](const char* op, int level) {
      return Text{operand(st.args[0], level) + " " + op + " " + operand(st.args[1], level + 1),
                  level};
    };
    switch (st.op) {
      case StepOp::Add: return bin("+", 1);
      case StepOp::Sub: return bin("-", 1);
      case StepOp::Mul: return bin("*", 2);
      case StepOp::Div: return bin("/", 2);
      case StepOp::Neg: return {"-" + operand(st.args[0], 4), 3};
      case StepOp::Fma:
        if (lang_ == Language::Glsl || lang_ == Language::Hlsl)  // not produced: unfused program
          return {operand(st.args[0], 2) + " * " + operand(st.args[1], 3) + " + " +
                      operand(st.args[2], 2),
                  1};
        return fn(Call::Fma, st);
      case StepOp::Abs: return fn(Call::Abs, st);
      case StepOp::Sqrt: return fn(Call::Sqrt, st);
      case StepOp::Rsqrt:
        if (lang_ == Language::Cpp)
          return {lit(1.0f) + " / std::sqrt(" + operand(st.args[0], 0) + ")", 2};
        return fn(Call::Rsqrt, st);
      case StepOp::Exp2: return fn(Call::Exp2, st);
      case StepOp::Log2: return fn(Call::Log2, st);
      case StepOp::Exp:
        if (st.neg_arg)
          return {
              std::string(codegen::call(lang_, Call::Exp)) + "(-" + operand(st.args[0], 4) + ")",
              4};
        return fn(Call::Exp, st);
      case StepOp::Log: return fn(Call::Log, st);
      case StepOp::Sin: return fn(Call::Sin, st);
      case StepOp::Cos: return fn(Call::Cos, st);
      case StepOp::Min: return fn(Call::Min, st);
      case StepOp::Max: return fn(Call::Max, st);
      case StepOp::Sat:
        if (lang_ == Language::Glsl) return {"clamp(" + operand(st.args[0], 0) + ", 0.0, 1.0)", 4};
        if (lang_ == Language::Cpp)
          return {"std::clamp(" + operand(st.args[0], 0) + ", 0.0f, 1.0f)", 4};
        return fn(Call::Saturate, st);
      case StepOp::Sign: return sign(st);
      case StepOp::CopySign: return copysign(st);
      case StepOp::Select: return select(st);
      case StepOp::Asin: return fn(Call::Asin, st);
      case StepOp::Acos: return fn(Call::Acos, st);
      case StepOp::Atan: return fn(Call::Atan, st);
      case StepOp::Atan2: return fn(Call::Atan2, st);
      case StepOp::Tanh: return fn(Call::Tanh, st);
      case StepOp::Erf: return fn(Call::Erf, st);
    }
    return {};
  }

  const Expression& e_;
  const CodegenOptions& o_;
  const Program& p_;
  Language lang_;
  std::vector<Text> texts_;
  std::string body_;  // the statements after the baked parameters
  int temps_ = 0;
};

}  // namespace

namespace {

// The name checks, and the program the cost model counts for this language.
Program checked_program(const Expression& e, const CodegenOptions& options) {
  codegen::check_name(options.name, "function name", SourceLocation{"CodegenOptions::name"});
  std::vector<std::string> seen = {options.name};
  for (const auto* names : {&e.variables, &e.parameters}) {
    const bool params = names == &e.parameters;
    for (const std::string& n : *names) {
      codegen::check_name(
          n, params ? "parameter name" : "input name",
          SourceLocation{params ? "Expression::parameters" : "Expression::variables"});
      if (std::find(seen.begin(), seen.end(), n) != seen.end()) {
        throw Error(
            "name '" + n + "' is used twice (function, inputs and parameters need distinct names)",
            SourceLocation{params ? "Expression::parameters" : "Expression::variables"});
      }
      seen.push_back(n);
    }
  }
  const bool fused = options.language != Language::Glsl && options.language != Language::Hlsl;
  return lowering::build_program(lowering::lower_expression(e), fused);
}

// The C++ headers a printed program needs: <cmath> for every function it calls (fma, sqrt, the
// fabs and copysign of sign, ...), <algorithm> for the std::clamp of saturate. Operators and ?:
// need none.
void add_cpp_headers(const Program& p, std::set<std::string_view>* headers) {
  for (const Step& st : p.steps) {
    switch (st.op) {
      case StepOp::Add:
      case StepOp::Sub:
      case StepOp::Mul:
      case StepOp::Div:
      case StepOp::Neg:
      case StepOp::Select: break;
      case StepOp::Sat: headers->insert("<algorithm>"); break;
      default: headers->insert("<cmath>"); break;
    }
  }
}

// Whether the printed program calls the erf helper (cost/erf_helper.hpp): GLSL, HLSL and Metal have
// no erf of their own.
bool needs_erf_helper(const Program& p, Language language) {
  if (language == Language::Cuda || language == Language::Cpp) return false;
  return std::any_of(p.steps.begin(), p.steps.end(),
                     [](const Step& st) { return st.op == StepOp::Erf; });
}

// The erf helper in `language`, operation for operation as lowering::erf_helper computes it.
std::string erf_helper_source(Language language) {
  using codegen::Call;
  const auto lit = [&](float v) { return float32_literal(v, language); };
  const auto horner = [&](const float(&c)[7], const char* x) {
    std::string p = lit(c[6]);
    for (int k = 5; k >= 0; --k) {
      p = (k == 5 ? p : "(" + p + ")") + " * " + x + (c[k] < 0 ? " - " : " + ") +
          lit(std::fabs(c[k]));
    }
    return p;
  };
  const char* decl = language == Language::Metal ? "inline float" : "float";
  const char* local = language == Language::Metal ? "const float" : "float";
  std::string s;
  s +=
      "// erf(x): a + a R(a^2) for a = |x| < 1, else 1 - 2^Q(min(a, 4)), with x's sign; max error\n"
      "// 1.32 ulp in float32 arithmetic (GPU exp2 adds its own, times erfc(a) <= 0.16).\n";
  s += fmt::format("{} {}(float x) {{\n", decl, lowering::kErfHelperName);
  s += fmt::format("  {} a = {}(x);\n", local, codegen::call(language, Call::Abs));
  s += fmt::format("  {} s = a * a;\n", local);
  s += fmt::format("  {} r = {};\n", local, horner(lowering::kErfSmall, "s"));
  s += fmt::format("  {} t = {}(a, {});\n", local, codegen::call(language, Call::Min),
                   lit(lowering::kErfClamp));
  s += fmt::format("  {} q = {};\n", local, horner(lowering::kErfLarge, "t"));
  s += fmt::format("  {} lo = a + a * r;\n", local);
  s +=
      fmt::format("  {} hi = {} - {}(q);\n", local, lit(1.0f), codegen::call(language, Call::Exp2));
  // Named values: glslang makes a ?: of names one OpSelect (of expressions, branches).
  s += fmt::format("  {} e = a < {} ? lo : hi;\n", local, lit(lowering::kErfSplit));
  s += fmt::format("  {} n = -e;\n", local);
  s += fmt::format("  return x < {} ? n : e;\n}}\n", lit(0.0f));
  return s;
}

}  // namespace

std::string generate_function(const Expression& e, const CodegenOptions& options) {
  const Program program = checked_program(e, options);
  const std::string f = FunctionPrinter(e, options, program).print();
  return needs_erf_helper(program, options.language)
             ? erf_helper_source(options.language) + "\n" + f
             : f;
}

std::string generate_source(std::span<const SourceFunction> functions, Language language) {
  std::set<std::string_view> headers;
  std::string body;
  bool erf_helper = false;
  for (const SourceFunction& f : functions) {
    CodegenOptions o = f.options;
    o.language = language;
    const Program program = checked_program(f.expression, o);
    if (language == Language::Cpp) add_cpp_headers(program, &headers);
    erf_helper = erf_helper || needs_erf_helper(program, language);
    body += (body.empty() ? "" : "\n") + FunctionPrinter(f.expression, o, program).print();
  }
  if (erf_helper) body = erf_helper_source(language) + "\n" + body;
  std::string head;
  switch (language) {
    case Language::Cpp:
      for (std::string_view h : headers) head += fmt::format("#include {}\n", h);
      break;
    case Language::Glsl: head = "#version 450\n"; break;
    case Language::Metal: head = "#include <metal_stdlib>\nusing namespace metal;\n"; break;
    case Language::Cuda:
    case Language::Hlsl: break;
  }
  return head.empty() || body.empty() ? head + body : head + "\n" + body;
}

}  // namespace shaderfit
