#include "shaderfit/codegen/codegen.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <span>

#include "codegen/spelling.hpp"
#include "cost/dag.hpp"
#include "cost/erf_helper.hpp"
#include "cost/op_instructions.hpp"
#include "cost/step_program.hpp"
#include "shaderfit/cost/per_material.hpp"

namespace shaderfit {

namespace {

using cost_detail::Operand;
using cost_detail::Program;
using cost_detail::Step;
using cost_detail::Comparison;
using cost_detail::select_comparison;

// A printed value: its text and its precedence (1 sum, 2 product, 3 unary minus, 4 atom/call).
struct Text {
  std::string s;
  int level = 4;
};

// How a function of a two-part formula (cost/per_material.hpp) reads or returns the values.
struct MaterialParts {
  std::string type;                 // the struct: NAME_material
  std::string object = "m";         // its argument (per pixel) or local (per material)
  std::size_t first_field = 0;      // per pixel: variables from here on are its fields
  std::vector<std::string> fields;  // per material: the program's results, in order
};

using codegen::Form;

class FunctionPrinter {
 public:
  FunctionPrinter(const Expression& e, const CodegenOptions& o, const Program& p,
                  const MaterialParts* parts = nullptr, bool fills = false, Form form = Form::Float)
      : e_(e),
        o_(o),
        p_(p),
        lang_(o.language),
        form_(form),
        texts_(p.steps.size()),
        parts_(parts),
        fills_(fills) {}

  std::string print() {
    std::string body;
    if (o_.bake_parameters) {
      for (std::size_t i = 0; i < e_.parameters.size(); ++i) {
        const double v = i < e_.parameter_values.size() ? e_.parameter_values[i] : 0.0;
        body += fmt::format("  const {} {} = {};\n", type(), e_.parameters[i], lit(v));
      }
    }
    // The operands of sign and select are named: sign reads its operand more than once, and
    // glslang compiles a ?: of named values to OpSelect (of expressions, to branches).
    std::vector<bool> named(p_.steps.size(), false);
    for (const Step& st : p_.steps) {
      if (st.op != Op::Sign && st.op != Op::Select) continue;
      for (int k = 0; k < st.arity; ++k)
        if (st.args[k].kind == Operand::Kind::Step)
          named[static_cast<std::size_t>(st.args[k].index)] = true;
    }
    for (std::size_t i = 0; i < p_.steps.size(); ++i) {
      if (p_.steps[i].compared) continue;  // the selects that read it compare its operands
      Text t = step(p_.steps[i]);
      if (p_.steps[i].uses > 1 || named[i]) t = {temporary(t.s), 4};
      texts_[i] = std::move(t);
    }
    if (fills_) {
      body_ += fmt::format("  {} {};\n", parts_->type, parts_->object);
      for (std::size_t k = 0; k < parts_->fields.size(); ++k)
        body_ += fmt::format("  {}.{} = {};\n", parts_->object, parts_->fields[k],
                             operand(p_.results[k], 0));
      body_ += "  return " + parts_->object + ";\n";
    } else {
      body_ += "  return " + operand(p_.results.front(), 0) + ";\n";
    }
    body += body_;

    std::string out;
    if (!fills_)
      for (const std::string& line : o_.comment) out += "// " + line + "\n";
    out += signature() + " {\n" + body + "}\n";
    return out;
  }

 private:
  // Declares a temporary holding `value` and returns its name.
  std::string temporary(const std::string& value) {
    const std::string name = unused_name_prefix(e_, 't') + std::to_string(temps_++);
    body_ += fmt::format("  {}{} {} = {};\n",
                         lang_ == Language::Glsl || lang_ == Language::Hlsl ? "" : "const ", type(),
                         name, value);
    return name;
  }

  std::string signature() const {
    std::string args;
    auto add = [&](const std::string& type, const std::string& n) {
      args += (args.empty() ? "" : ", ") + type + " " + n;
    };
    const bool reads_parts = parts_ != nullptr && !fills_;
    const std::string value(type());
    for (std::size_t v = 0; v < e_.variables.size(); ++v)
      if (!reads_parts || v < parts_->first_field) add(value, e_.variables[v]);
    if (reads_parts) add(parts_->type, parts_->object);
    if (!o_.bake_parameters)
      for (const std::string& v : e_.parameters) add(value, v);
    const std::string type = fills_ ? parts_->type : value;
    const std::string name = fills_
                                 ? material_function_name(o_.name)
                                 : (form_ == Form::Half2 ? pair_function_name(o_.name) : o_.name);
    switch (lang_) {
      case Language::Cuda:
        // The __half form runs on the host too (cuda_fp16.h's host arithmetic, the helpers).
        return (form_ == Form::Half ? "__host__ __device__ __forceinline__ "
                                    : "__device__ __forceinline__ ") +
               type + " " + name + "(" + args + ")";
      case Language::Cpp:
      case Language::Metal: return "inline " + type + " " + name + "(" + args + ")";
      default: return type + " " + name + "(" + args + ")";
    }
  }

  std::string_view type() const { return codegen::value_type(lang_, form_); }
  std::string lit(double v) const { return codegen::literal(v, lang_, form_); }
  // CUDA's half forms write every operation as a call (__hadd_rn, __hmul2_rn, ...; the _rn forms,
  // which nvcc never contracts into an fma).
  bool calls_only() const { return lang_ == Language::Cuda && form_ != Form::Float; }

  std::string operand(const Operand& o, int min_level) const {
    Text t;
    switch (o.kind) {
      case Operand::Kind::Const: t = {lit(o.value), o.value < 0 ? 3 : 4}; break;
      case Operand::Kind::Var: {
        const auto v = static_cast<std::size_t>(o.index);
        const bool field = parts_ != nullptr && !fills_ && v >= parts_->first_field;
        t = {field ? parts_->object + "." + e_.variables[v] : e_.variables[v], 4};
        break;
      }
      case Operand::Kind::Param: t = {e_.parameters[static_cast<std::size_t>(o.index)], 4}; break;
      default: t = texts_[static_cast<std::size_t>(o.index)]; break;
    }
    return t.level < min_level ? "(" + t.s + ")" : t.s;
  }

  Text fn(Op c, const Step& st) const {
    std::string s = std::string(codegen::call(lang_, c, form_)) + "(";
    for (int k = 0; k < st.arity; ++k) s += (k ? ", " : "") + operand(st.args[k], 0);
    // glslang's HLSL reads half arguments of intrinsics as float: the result is cast back (DXC's
    // half overloads make the cast a no-op).
    if (lang_ == Language::Hlsl && form_ == Form::Half) return {"(half)" + s + ")", 3};
    return {s + ")", 4};
  }
  // A call of `c` with the operands given (CUDA half forms).
  Text call_of(Op c, std::initializer_list<std::string> operands) const {
    std::string s = std::string(codegen::call(lang_, c, form_)) + "(";
    bool first = true;
    for (const std::string& o : operands) {
      s += (first ? "" : ", ") + o;
      first = false;
    }
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
    return {std::string(codegen::call(lang_, Op::Abs)) + "(" + x + ") > " + lit(0.0f) + " ? " +
                std::string(codegen::call(lang_, Op::CopySign)) + "(" + lit(1.0f) + ", " + x +
                ") : " + x,
            0};
  }
  Text copysign(const Step& st) const {
    const std::string b = operand(st.args[1], 0);
    if (!shader())
      return {std::string(codegen::call(lang_, Op::CopySign)) + "(" + operand(st.args[0], 0) +
                  ", " + b + ")",
              4};
    // |a| with b's sign bit; a literal a is written as the bits of |a|.
    const Operand& a = st.args[0];
    const std::string magnitude =
        a.kind == Operand::Kind::Const
            ? fmt::format("0x{:08x}u", std::bit_cast<std::uint32_t>(std::fabs(a.value)))
            : "(" + to_bits(operand(a, 0)) + " & 0x7fffffffu)";
    return {from_bits(magnitude + " | (" + to_bits(b) + " & 0x80000000u)"), 4};
  }
  // a >= 0 ? b : c, or a <= 0 ? b : c for the negated condition -a >= 0; x >= y ? b : c for a
  // compared difference a = x - y (select_comparison).
  // A literal goes on the right, as people write it: x <= 0.5, not 0.5 >= x.
  Text select(const Step& st) const {
    const Comparison cmp = select_comparison(p_, st);
    const bool flip = cmp.lhs.kind == Operand::Kind::Const && cmp.rhs.kind != Operand::Kind::Const;
    const bool le = st.neg_arg != flip;
    return {operand(flip ? cmp.rhs : cmp.lhs, 1) + (le ? " <= " : " >= ") +
                operand(flip ? cmp.lhs : cmp.rhs, 1) + " ? " + operand(st.args[1], 1) + " : " +
                operand(st.args[2], 1),
            0};
  }

  // Half forms: the steps that are calls in CUDA; nullopt for the others.
  std::optional<Text> half_step(const Step& st) const {
    const auto arg = [&](int k) { return operand(st.args[k], 0); };
    if (!calls_only()) return std::nullopt;
    const bool rcp = cost_detail::is_reciprocal(st);
    // -1 / x = 1 / -x: rcp is odd.
    if (rcp)
      return call_of(Op::Rcp, {st.args[0].value < 0 ? call_of(Op::Neg, {arg(1)}).s : arg(1)});
    if (!op_info(st.op).infix && st.op != Op::Neg) return std::nullopt;
    if (st.arity == 1) return call_of(st.op, {arg(0)});
    return call_of(st.op, {arg(0), arg(1)});
  }

  Text step(const Step& st) {
    if (st.arity == 1)
      if (std::optional<codegen::SpelledOut> t =
              codegen::spelled_out(lang_, st.op, form_, operand(st.args[0], 0)))
        return {std::move(t->text), t->level};
    if (form_ != Form::Float)
      if (std::optional<Text> t = half_step(st)) return *std::move(t);
    auto bin = [&](std::string_view op, int level) {
      return Text{
          operand(st.args[0], level) + " " + std::string(op) + " " + operand(st.args[1], level + 1),
          level};
    };
    if (op_info(st.op).infix) return bin(op_info(st.op).name, precedence(st.op));
    switch (st.op) {
      case Op::Neg: return {"-" + operand(st.args[0], 4), 3};
      case Op::Fma:
        if (form_ != Form::Float) return fn(Op::Fma, st);        // the formula's own fma
        if (lang_ == Language::Glsl || lang_ == Language::Hlsl)  // not produced: unfused program
          return {operand(st.args[0], 2) + " * " + operand(st.args[1], 3) + " + " +
                      operand(st.args[2], 2),
                  1};
        return fn(Op::Fma, st);
      case Op::Exp:
        if (st.neg_arg)
          return {std::string(codegen::call(lang_, Op::Exp)) + "(-" + operand(st.args[0], 4) + ")",
                  4};
        return fn(Op::Exp, st);
      case Op::Sign: return sign(st);
      case Op::CopySign: return copysign(st);
      case Op::Select: return select(st);
      default: return fn(st.op, st);  // a call, as codegen::call spells it
    }
  }

  const Expression& e_;
  const CodegenOptions& o_;
  const Program& p_;
  Language lang_;
  Form form_;
  std::vector<Text> texts_;
  std::string body_;  // the statements after the baked parameters
  int temps_ = 0;
  const MaterialParts* parts_;
  bool fills_;
};

}  // namespace

namespace {

void check_names(const Expression& e, const CodegenOptions& options,
                 std::vector<std::string> seen) {
  codegen::check_name(options.name, "function name", SourceLocation{"CodegenOptions::name"});
  seen.push_back(options.name);
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
}

bool fused_language(Language language) {
  return language != Language::Glsl && language != Language::Hlsl;
}

// v over new tables: the named variables and parameters (each of v's read ones among them).
Expression over_tables(const Expression& v, const std::vector<std::string>& variables,
                       const std::vector<std::string>& parameters,
                       const std::vector<double>& values) {
  Expression out = v;
  out.variables = variables;
  out.parameters = parameters;
  out.parameter_values = values;
  auto index_of = [](const std::vector<std::string>& names, const std::string& n) {
    return static_cast<std::int16_t>(std::find(names.begin(), names.end(), n) - names.begin());
  };
  for (Node& n : out.nodes) {
    if (n.op == Op::Var)
      n.index = index_of(variables, v.variables[static_cast<std::size_t>(n.index)]);
    if (n.op == Op::Param)
      n.index = index_of(parameters, v.parameters[static_cast<std::size_t>(n.index)]);
  }
  return out;
}

// A function as it is printed: one formula, or the two parts of a formula that reads per-material
// inputs (CodegenOptions::uniform).
struct Prepared {
  Expression pixel;  // the formula, or its per-pixel part
  Program pixel_program;
  std::optional<MaterialParts> parts;
  Expression material;  // the tables of the per-material function: uniform inputs, parameters
  Program material_program;

  [[nodiscard]] std::vector<const Program*> programs() const {
    if (!parts) return {&pixel_program};
    return {&material_program, &pixel_program};
  }
};

// Half code (docs/precision.md, "Half code"): the checks of what has a half form, then the
// program of the half DAG, which rounds where evaluate_half rounds.
Prepared prepare_half(const Expression& e, const CodegenOptions& options) {
  (void)half_literal(0.0, options.language);  // throws for C++, which has no half type
  if (reads_uniform(e, options.uniform)) {
    throw Error(
        "per-material inputs have no half form in code generation yet: print the formula "
        "in one part, or in float",
        SourceLocation{"CodegenOptions::uniform"});
  }
  std::vector<std::string> seen;
  if (options.language == Language::Cuda) seen.push_back(pair_function_name(options.name));
  check_names(e, options, seen);
  Prepared p;
  p.pixel = e;
  p.pixel_program = cost_detail::build_program(cost_detail::lower_expression(e, true), false);
  // What has a half form is what CUDA's __half spells: the arithmetic, sqrt ... fma, saturate.
  for (const Step& st : p.pixel_program.steps) {
    if (codegen::call(Language::Cuda, st.op, Form::Half).empty()) {
      throw Error(std::string(op_info(st.op).name) +
                      " has no half form in code generation (docs/precision.md)",
                  SourceLocation{"formula"});
    }
  }
  return p;
}

Prepared prepare(const Expression& e, const CodegenOptions& options) {
  if (options.precision == Precision::Double) {
    throw Error("code generation has no double form: print float or half",
                SourceLocation{"CodegenOptions::precision"});
  }
  if (options.precision == Precision::Half) return prepare_half(e, options);
  const bool fused = fused_language(options.language);
  Prepared p;
  if (!reads_uniform(e, options.uniform)) {
    check_names(e, options, {});
    p.pixel = e;
    p.pixel_program = cost_detail::build_program(cost_detail::lower_expression(e), fused);
    return p;
  }
  check_names(e, options, {material_type_name(options.name), material_function_name(options.name)});
  MaterialSplit split = split_per_material(e, options.uniform);
  MaterialParts parts;
  parts.type = material_type_name(options.name);
  parts.first_field = split.per_pixel.variables.size() - split.values.size();
  for (bool clash = true; clash;) {
    clash = false;
    for (const auto* names : {&split.per_pixel.variables, &split.per_pixel.parameters})
      clash = clash || std::find(names->begin(), names->end(), parts.object) != names->end();
    if (clash) parts.object = "_" + parts.object;
  }
  // The per-material function reads the uniform inputs (in the formula's order) and the
  // parameters its values read.
  std::vector<std::string> uniform_inputs, params;
  std::vector<double> values;
  for (const std::string& v : e.variables)
    if (std::find(options.uniform.begin(), options.uniform.end(), v) != options.uniform.end())
      uniform_inputs.push_back(v);
  for (std::size_t k = 0; k < e.parameters.size(); ++k) {
    const bool read =
        std::any_of(split.values.begin(), split.values.end(), [&](const MaterialValue& m) {
          return std::any_of(m.value.nodes.begin(), m.value.nodes.end(), [&](const Node& n) {
            return n.op == Op::Param && static_cast<std::size_t>(n.index) == k;
          });
        });
    if (!read) continue;
    params.push_back(e.parameters[k]);
    values.push_back(k < e.parameter_values.size() ? e.parameter_values[k] : 0.0);
  }
  std::vector<Expression> computed;
  for (const MaterialValue& m : split.values) {
    parts.fields.push_back(m.name);
    computed.push_back(over_tables(m.value, uniform_inputs, params, values));
  }
  p.material = computed.front();
  p.material_program = cost_detail::build_program(cost_detail::lower_expressions(computed), fused);
  p.pixel = std::move(split.per_pixel);
  p.pixel_program = cost_detail::build_program(cost_detail::lower_expression(p.pixel), fused);
  p.parts = std::move(parts);
  return p;
}

std::string print(const Prepared& p, const CodegenOptions& options) {
  if (options.precision == Precision::Half) {
    std::string out =
        FunctionPrinter(p.pixel, options, p.pixel_program, nullptr, false, Form::Half).print();
    if (options.language != Language::Cuda) return out;
    CodegenOptions pair = options;
    pair.comment.clear();
    return out +
           FunctionPrinter(p.pixel, pair, p.pixel_program, nullptr, false, Form::Half2).print();
  }
  if (!p.parts) return FunctionPrinter(p.pixel, options, p.pixel_program).print();
  std::string fields;
  for (const std::string& f : p.parts->fields) fields += "  float " + f + ";\n";
  std::string out;
  for (const std::string& line : options.comment) out += "// " + line + "\n";
  out += fmt::format("struct {} {{\n{}}};\n", p.parts->type, fields);
  out += FunctionPrinter(p.material, options, p.material_program, &*p.parts, true).print();
  CodegenOptions pixel = options;
  pixel.comment.clear();
  out += FunctionPrinter(p.pixel, pixel, p.pixel_program, &*p.parts).print();
  return out;
}

// The C++ headers a printed program needs: codegen::cpp_header of each step that calls a
// function (the fabs and copysign of sign too); operators and ?: need none.
void add_cpp_headers(const Program& p, std::set<std::string_view>* headers) {
  for (const Step& st : p.steps)
    if (!op_info(st.op).infix && st.op != Op::Neg && st.op != Op::Select)
      headers->insert(codegen::cpp_header(st.op));
}

// Whether the printed program calls the erf helper (cost/erf_helper.hpp): GLSL, HLSL and Metal have
// no erf of their own.
bool needs_erf_helper(const Prepared& p, Language language) {
  if (language == Language::Cuda || language == Language::Cpp) return false;
  for (const Program* program : p.programs())
    if (std::any_of(program->steps.begin(), program->steps.end(),
                    [](const Step& st) { return !cost_detail::helper_of(st.op).empty(); }))
      return true;
  return false;
}

// The erf helper in `language`, operation for operation as cost_detail::erf_helper computes it.
std::string erf_helper_source(Language language) {
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
  s += fmt::format("{} {}(float x) {{\n", decl, cost_detail::kErfHelperName);
  s += fmt::format("  {} a = {}(x);\n", local, codegen::call(language, Op::Abs));
  s += fmt::format("  {} s = a * a;\n", local);
  s += fmt::format("  {} r = {};\n", local, horner(cost_detail::kErfSmall, "s"));
  s += fmt::format("  {} t = {}(a, {});\n", local, codegen::call(language, Op::Min),
                   lit(cost_detail::kErfClamp));
  s += fmt::format("  {} q = {};\n", local, horner(cost_detail::kErfLarge, "t"));
  s += fmt::format("  {} lo = a + a * r;\n", local);
  s += fmt::format("  {} hi = {} - {}(q);\n", local, lit(1.0f), codegen::call(language, Op::Exp2));
  // Named values: glslang makes a ?: of names one OpSelect (of expressions, branches).
  s += fmt::format("  {} e = a < {} ? lo : hi;\n", local, lit(cost_detail::kErfSplit));
  s += fmt::format("  {} n = -e;\n", local);
  s += fmt::format("  return x < {} ? n : e;\n}}\n", lit(0.0f));
  return s;
}

// The CUDA __half helpers a half program calls (cuda_half_helpers).
void add_half_helper_calls(const Program& p, std::vector<Op>* calls) {
  for (const Step& st : p.steps) {
    const bool rcp = cost_detail::is_reciprocal(st);
    const Op c = rcp ? Op::Rcp : st.op;
    if (codegen::has_cuda_half_helper(c) &&
        std::find(calls->begin(), calls->end(), c) == calls->end())
      calls->push_back(c);
  }
}

// What a file of half functions needs in `language`, as a first comment (generate_function) or
// as the lines at the top of a file (generate_source).
std::string half_requirement(Language language, bool as_lines) {
  switch (language) {
    case Language::Glsl:
      return std::string(as_lines ? "" : "// needs ") +
             "#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require\n";
    case Language::Hlsl:
      return "// half needs 16-bit types: dxc -enable-16bit-types (glslangValidator "
             "--hlsl-enable-16bit-types)\n";
    case Language::Cuda:
      return std::string(as_lines ? "" : "// needs ") + "#include <cuda_fp16.h>\n";
    default: return {};
  }
}

}  // namespace

std::string generate_function(const Expression& e, const CodegenOptions& options) {
  const Prepared p = prepare(e, options);
  const std::string f = print(p, options);
  if (options.precision == Precision::Half) {
    std::string head = half_requirement(options.language, false);
    if (options.language == Language::Cuda) {
      std::vector<Op> calls;
      add_half_helper_calls(p.pixel_program, &calls);
      head += codegen::cuda_half_helpers(calls);
    }
    return head + f;
  }
  return needs_erf_helper(p, options.language) ? erf_helper_source(options.language) + "\n" + f : f;
}

std::string pair_function_name(const std::string& function_name) { return function_name + "_x2"; }

std::string generate_source(std::span<const SourceFunction> functions, Language language) {
  std::set<std::string_view> headers;
  std::string body;
  bool erf_helper = false, half = false;
  std::vector<Op> half_calls;
  for (const SourceFunction& f : functions) {
    CodegenOptions o = f.options;
    o.language = language;
    const Prepared p = prepare(f.expression, o);
    if (language == Language::Cpp)
      for (const Program* program : p.programs()) add_cpp_headers(*program, &headers);
    erf_helper = erf_helper || needs_erf_helper(p, language);
    if (o.precision == Precision::Half) {
      half = true;
      add_half_helper_calls(p.pixel_program, &half_calls);
    }
    body += (body.empty() ? "" : "\n") + print(p, o);
  }
  if (erf_helper) body = erf_helper_source(language) + "\n" + body;
  if (language == Language::Cuda && !half_calls.empty())
    body = codegen::cuda_half_helpers(half_calls) + "\n" + body;
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
  if (half) head += half_requirement(language, true);
  return head.empty() || body.empty() ? head + body : head + "\n" + body;
}

std::string cost_comment(const Expression& e, std::span<const std::string> uniform,
                         Precision precision) {
  if (precision == Precision::Half) {
    const int n = instruction_count(e, InstructionTarget::SassHalf2);
    return fmt::format("cost model: {} SASS per __half2 ({:g} per value)", n, n / 2.0);
  }
  // "6 SASS, 6 PTX, 7 generic, 6 RDNA" (RDNA 2 and 3 apart where they differ); `part` picks a
  // count of a split.
  const auto counts = [&](auto count) {
    const int rdna2 = count(InstructionTarget::Rdna2), rdna3 = count(InstructionTarget::Rdna3);
    return fmt::format("{} SASS, {} PTX, {} generic, ", count(InstructionTarget::Sass),
                       count(InstructionTarget::Ptx), count(InstructionTarget::Generic)) +
           (rdna2 == rdna3 ? fmt::format("{} RDNA", rdna2) : fmt::format("{} RDNA 2, {} RDNA 3", rdna2, rdna3));
  };
  if (!reads_uniform(e, uniform))
    return "cost model: " + counts([&](InstructionTarget t) { return instruction_count(e, t); }) + " instructions";
  std::map<InstructionTarget, SplitCost> split;
  for (InstructionTarget t : kInstructionTargets)
    if (t != InstructionTarget::SassHalf2) split[t] = split_instruction_count(e, uniform, t);
  return "cost model: per pixel " + counts([&](InstructionTarget t) { return split[t].per_pixel; }) +
         "; per material " + counts([&](InstructionTarget t) { return split[t].per_material; }) + " instructions";
}

std::string material_type_name(const std::string& function_name) {
  return function_name + "_material";
}

std::string material_function_name(const std::string& function_name) {
  return function_name + "_material_values";
}

}  // namespace shaderfit
