// The program builder (constant folding through the one interpreter) and the functions the
// reference language knows: C's math library for formulas, the shading languages' built-ins for
// shaders, each an instruction or a short expansion into instructions.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include "language_internal.hpp"
#include "shaderfit/reference/program_evaluate.hpp"

namespace shaderfit::reference_detail {

using namespace shaderfit::reference;  // the area's public names

// --- builder -------------------------------------------------------------------------------

ProgramBuilder::ProgramBuilder(Program& program, std::string source)
    : program_(program), source_(std::move(source)) {}

Reg ProgramBuilder::append(const Instruction& in) {
  if (program_.code.size() >= kMaxInstructions) {
    throw Error("the reference is too large: more than " + std::to_string(kMaxInstructions) +
                    " instructions (with every call inlined)",
                SourceLocation{source_, line_, column_});
  }
  program_.code.push_back(in);
  return static_cast<Reg>(program_.code.size() - 1);
}

Reg ProgramBuilder::constant(double v) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(v);
  if (const auto it = constants_.find(bits); it != constants_.end()) return it->second;
  Instruction in;
  in.op = ProgramOp::Const;
  in.value = v;
  const Reg r = append(in);
  constants_.emplace(bits, r);
  return r;
}

Reg ProgramBuilder::input(int index) {
  Instruction in;
  in.op = ProgramOp::Input;
  in.index = index;
  return append(in);
}

std::optional<double> ProgramBuilder::constant_value(Reg r) const {
  const Instruction& in = program_.code[r];
  if (in.op != ProgramOp::Const) return std::nullopt;
  return in.value;
}

Reg ProgramBuilder::emit(ProgramOp op, std::span<const Reg> operands, std::int32_t index) {
  if (op == ProgramOp::Select) {
    if (const auto c = constant_value(operands[0])) {
      // The interpreter's own truth test decides, as it would at run time.
      return ProgramLogic<double>::is_true(*c) ? operands[1] : operands[2];
    }
    if (operands[1] == operands[2]) return operands[1];
  }
  // x + 0, x - 0, x * 1, x / 1 are x (and, in shaders, x * 0 is 0), as shader compilers fold
  // them: a dot product with a zero component, a weight of one.
  if (operands.size() == 2) {
    const auto a = constant_value(operands[0]), c = constant_value(operands[1]);
    if (a.has_value() != c.has_value()) {
      const bool add = op == ProgramOp::Add, mul = op == ProgramOp::Mul;
      if (mul && zero_products_ && ((a && *a == 0.0) || (c && *c == 0.0))) return constant(0.0);
      if (c && *c == 0.0 && (add || op == ProgramOp::Sub)) return operands[0];
      if (c && *c == 1.0 && (mul || op == ProgramOp::Div)) return operands[0];
      if (a && *a == 0.0 && add) return operands[1];
      if (a && *a == 1.0 && mul) return operands[1];
    }
  }
  Instruction in;
  in.op = op;
  in.index = index;
  in.arity = static_cast<std::uint8_t>(operands.size());
  for (std::size_t k = 0; k < operands.size(); ++k) in.operands[k] = operands[k];
  const bool foldable = std::all_of(operands.begin(), operands.end(),
                                    [&](Reg r) { return constant_value(r).has_value(); });
  if (!foldable) return append(in);
  // All operands constant: run the instruction on them, by the interpreter itself.
  fold_.code.clear();
  for (std::size_t k = 0; k < operands.size(); ++k) {
    Instruction c;
    c.op = ProgramOp::Const;
    c.value = *constant_value(operands[k]);
    fold_.code.push_back(c);
    in.operands[k] = static_cast<Reg>(k);
  }
  fold_.code.push_back(in);
  evaluate_program<double>(fold_, std::span<const double>(), fold_registers_);
  return constant(fold_registers_.back());
}

void remove_dead_code(Program& program) {
  std::vector<char> live(program.code.size(), 0);
  for (const Reg r : program.outputs) live[r] = 1;
  for (std::size_t i = program.code.size(); i-- > 0;) {
    if (live[i] == 0) continue;
    const Instruction& in = program.code[i];
    for (int k = 0; k < in.arity; ++k) live[in.operands[static_cast<std::size_t>(k)]] = 1;
  }
  std::vector<Reg> renumbered(program.code.size(), 0);
  std::size_t next = 0;
  for (std::size_t i = 0; i < program.code.size(); ++i) {
    if (live[i] == 0) continue;
    Instruction in = program.code[i];
    for (int k = 0; k < in.arity; ++k) {
      auto& r = in.operands[static_cast<std::size_t>(k)];
      r = renumbered[r];
    }
    renumbered[i] = static_cast<Reg>(next);
    program.code[next++] = in;
  }
  program.code.resize(next);
  for (Reg& r : program.outputs) r = renumbered[r];
}

// --- types ---------------------------------------------------------------------------------

std::optional<Type> scalar_type(std::string_view name) {
  for (const std::string_view f : {"float", "half", "double", "min16float", "min10float"})
    if (name == f) return Type::Float;
  for (const std::string_view i : {"int", "uint", "min16int", "min12int", "min16uint"})
    if (name == i) return Type::Int;
  if (name == "bool") return Type::Bool;
  return std::nullopt;
}

namespace {

// A matrix's shape: rows x columns floats.
Shape matrix_shape(int rows, int columns, bool glsl) {
  return Shape{Type::Float, 0, nullptr, rows, columns, glsl};
}

bool is_size(char c) { return c >= '2' && c <= '4'; }

}  // namespace

std::optional<Shape> shader_type(std::string_view name) {
  if (const auto s = scalar_type(name)) return Shape{*s, 1};
  if (name.empty()) return std::nullopt;
  // GLSL: matN, matCxR (C columns of R rows), dmat likewise.
  for (const std::string_view stem : {"mat", "dmat"}) {
    if (name.substr(0, stem.size()) != stem) continue;
    const std::string_view n = name.substr(stem.size());
    if (n.size() == 1 && is_size(n[0])) return matrix_shape(n[0] - '0', n[0] - '0', true);
    if (n.size() == 3 && n[1] == 'x' && is_size(n[0]) && is_size(n[2]))
      return matrix_shape(n[2] - '0', n[0] - '0', true);
  }
  // HLSL: a float type's name and RxC.
  if (name.size() > 3 && name[name.size() - 2] == 'x' && is_size(name.back()) &&
      is_size(name[name.size() - 3])) {
    if (scalar_type(name.substr(0, name.size() - 3)) == Type::Float)
      return matrix_shape(name[name.size() - 3] - '0', name.back() - '0', false);
    return std::nullopt;
  }
  const char last = name.back();
  if (last < '2' || last > '4') return std::nullopt;
  const int width = last - '0';
  const std::string_view stem = name.substr(0, name.size() - 1);
  // GLSL: vecN, ivecN, uvecN, bvecN, dvecN.
  if (stem == "vec" || stem == "dvec") return Shape{Type::Float, width};
  if (stem == "ivec" || stem == "uvec") return Shape{Type::Int, width};
  if (stem == "bvec") return Shape{Type::Bool, width};
  // HLSL: a scalar type's name and N.
  if (const auto s = scalar_type(stem)) return Shape{*s, width};
  return std::nullopt;
}

int StructType::member(std::string_view n) const {
  for (std::size_t k = 0; k < members.size(); ++k)
    if (members[k].name == n) return static_cast<int>(k);
  return -1;
}

std::string shape_name(Shape s) {
  if (s.record != nullptr) return s.record->name;
  if (s.is_matrix()) {
    const std::string r = std::to_string(s.rows), c = std::to_string(s.columns);
    if (!s.glsl) return "float" + r + "x" + c;
    return s.rows == s.columns ? "mat" + r : "mat" + c + "x" + r;
  }
  const std::string base = s.type == Type::Float ? "float" : s.type == Type::Int ? "int" : "bool";
  return s.width == 1 ? base : base + std::to_string(s.width);
}

Value make_value(std::span<const Reg> regs, Type type) {
  Value v;
  v.type = type;
  v.width = static_cast<int>(regs.size());
  for (int i = 0; i < v.width; ++i) v.set_component(i, regs[static_cast<std::size_t>(i)]);
  return v;
}

// --- conversions ---------------------------------------------------------------------------

Value convert(ProgramBuilder& b, Value v, Type to) {
  if (v.type == to || !v.is_number()) return v;
  for (int i = 0; i < v.width; ++i) {
    const Reg r = v.component(i);
    switch (to) {
      case Type::Float: break;
      case Type::Int:
        if (v.type != Type::Bool) v.set_component(i, b.emit(ProgramOp::Trunc, r));
        break;
      case Type::Bool: v.set_component(i, b.emit(ProgramOp::NotEqual, r, b.constant(0.0))); break;
    }
  }
  v.type = to;
  return v;
}

std::optional<Value> convert(ProgramBuilder& b, Value v, Shape to) {
  if (v.record != nullptr || to.record != nullptr)
    return v.record == to.record ? std::optional<Value>(std::move(v)) : std::nullopt;
  if (v.is_matrix() || to.is_matrix()) {
    const bool same = v.rows == to.rows && v.columns == to.columns;
    return same ? std::optional<Value>(std::move(v)) : std::nullopt;
  }
  if (v.width < to.width && v.width != 1) return std::nullopt;
  v = convert(b, v, to.type);
  Value out;
  out.type = to.type;
  out.width = to.width;
  for (int i = 0; i < to.width; ++i) out.set_component(i, v.component(v.width == 1 ? 0 : i));
  return out;
}

Value select(ProgramBuilder& b, Reg c, const Value& x, const Value& y) {
  if (!x.is_number()) {
    Value out = x;
    for (std::size_t k = 0; k < out.members.size(); ++k)
      out.members[k] = select(b, c, x.members[k], y.members[k]);
    return out;
  }
  Value out;
  out.type = x.type == y.type ? x.type : Type::Float;
  out.width = std::max(x.width, y.width);
  for (int i = 0; i < out.width; ++i) {
    out.set_component(i, b.emit(ProgramOp::Select, c, x.component(x.width == 1 ? 0 : i),
                                y.component(y.width == 1 ? 0 : i)));
  }
  return out;
}

Value filled(ProgramBuilder& b, const Value& v, Shape shape) {
  if (shape.is_matrix()) {
    std::vector<Value> rows(static_cast<std::size_t>(shape.rows),
                            *convert(b, v, Shape{Type::Float, shape.columns}));
    return make_matrix(shape, std::move(rows));
  }
  if (shape.record == nullptr) return *convert(b, v, shape);
  Value out;
  out.width = 0;
  out.record = shape.record;
  for (const StructMember& m : shape.record->members) out.members.push_back(filled(b, v, m.shape));
  return out;
}

std::size_t scalar_count(Shape shape) {
  if (shape.is_matrix()) return static_cast<std::size_t>(shape.rows * shape.columns);
  if (shape.record == nullptr) return static_cast<std::size_t>(shape.width);
  std::size_t n = 0;
  for (const StructMember& m : shape.record->members) n += scalar_count(m.shape);
  return n;
}

void scalar_components(const Value& v, std::vector<Value>& out) {
  for (const Value& m : v.members) scalar_components(m, out);
  for (int i = 0; i < v.width; ++i) out.push_back({v.component(i), v.type});
}

std::optional<Value> from_components(ProgramBuilder& b, Shape shape, std::span<const Value> parts,
                                     std::size_t& at) {
  if (shape.is_matrix()) {
    std::vector<Value> rows;
    for (int i = 0; i < shape.rows; ++i) {
      std::optional<Value> row = from_components(b, Shape{Type::Float, shape.columns}, parts, at);
      if (!row) return std::nullopt;
      rows.push_back(std::move(*row));
    }
    return make_matrix(shape, std::move(rows));
  }
  if (shape.record != nullptr) {
    Value out;
    out.width = 0;
    out.record = shape.record;
    for (const StructMember& m : shape.record->members) {
      std::optional<Value> v = from_components(b, m.shape, parts, at);
      if (!v) return std::nullopt;
      out.members.push_back(std::move(*v));
    }
    return out;
  }
  if (parts.size() - at < static_cast<std::size_t>(shape.width)) return std::nullopt;
  std::vector<Reg> regs;
  for (int i = 0; i < shape.width; ++i) regs.push_back(convert(b, parts[at++], shape.type).reg);
  return make_value(regs, shape.type);
}

// --- the functions -------------------------------------------------------------------------

namespace {

using Args = std::span<const Value>;

Value f(Reg r) { return {r, Type::Float}; }

// 1 / sqrt(a), 1 / a: as expr/op.hpp defines rsqrt and rcp.
Value rsqrt(ProgramBuilder& b, Args a) {
  return f(b.emit(ProgramOp::Div, b.constant(1.0), b.emit(Op::Sqrt, a[0].reg)));
}
Value rcp(ProgramBuilder& b, Args a) {
  return f(b.emit(ProgramOp::Div, b.constant(1.0), a[0].reg));
}
// fma(a, b, c) = a * b + c, rounded twice (as expr/op.hpp's Fma).
Value fma(ProgramBuilder& b, Args a) {
  return f(b.emit(ProgramOp::Add, b.emit(ProgramOp::Mul, a[0].reg, a[1].reg), a[2].reg));
}
Value select3(ProgramBuilder& b, Args a) { return select(b, a[0].reg, a[1], a[2]); }
// clamp(x, lo, hi) = min(max(x, lo), hi), as GLSL defines it (a NaN x gives lo).
Value clamp(ProgramBuilder& b, Args a) {
  const bool ints = a[0].type == Type::Int && a[1].type == Type::Int && a[2].type == Type::Int;
  return {b.emit(ProgramOp::Min, b.emit(ProgramOp::Max, a[0].reg, a[1].reg), a[2].reg),
          ints ? Type::Int : Type::Float};
}
Value saturate(ProgramBuilder& b, Args a) {
  const Value args[] = {a[0], f(b.constant(0.0)), f(b.constant(1.0))};
  return f(clamp(b, args).reg);
}
// GLSL mix(x, y, a) = x (1 - a) + y a; HLSL lerp(x, y, s) = x + s (y - x).
Value mix(ProgramBuilder& b, Args a) {
  const Reg one_minus = b.emit(ProgramOp::Sub, b.constant(1.0), a[2].reg);
  return f(b.emit(ProgramOp::Add, b.emit(ProgramOp::Mul, a[0].reg, one_minus),
                  b.emit(ProgramOp::Mul, a[1].reg, a[2].reg)));
}
Value lerp(ProgramBuilder& b, Args a) {
  const Reg d = b.emit(ProgramOp::Sub, a[1].reg, a[0].reg);
  return f(b.emit(ProgramOp::Add, a[0].reg, b.emit(ProgramOp::Mul, a[2].reg, d)));
}
// step(edge, x) = x < edge ? 0 : 1.
Value step(ProgramBuilder& b, Args a) {
  return f(b.emit(ProgramOp::Select, b.emit(ProgramOp::Less, a[1].reg, a[0].reg), b.constant(0.0),
                  b.constant(1.0)));
}
// smoothstep(e0, e1, x): t = clamp((x - e0) / (e1 - e0), 0, 1), t t (3 - 2 t).
Value smoothstep(ProgramBuilder& b, Args a) {
  const Reg q = b.emit(ProgramOp::Div, b.emit(ProgramOp::Sub, a[2].reg, a[0].reg),
                       b.emit(ProgramOp::Sub, a[1].reg, a[0].reg));
  const Value qv[] = {f(q)};
  const Reg t = saturate(b, qv).reg;
  const Reg poly =
      b.emit(ProgramOp::Sub, b.constant(3.0), b.emit(ProgramOp::Mul, b.constant(2.0), t));
  return f(b.emit(ProgramOp::Mul, b.emit(ProgramOp::Mul, t, t), poly));
}
// fract(x) = x - floor(x); GLSL mod(x, y) = x - y floor(x / y).
Value fract(ProgramBuilder& b, Args a) {
  return f(b.emit(ProgramOp::Sub, a[0].reg, b.emit(ProgramOp::Floor, a[0].reg)));
}
Value glsl_mod(ProgramBuilder& b, Args a) {
  const Reg q = b.emit(ProgramOp::Floor, b.emit(ProgramOp::Div, a[0].reg, a[1].reg));
  return f(b.emit(ProgramOp::Sub, a[0].reg, b.emit(ProgramOp::Mul, a[1].reg, q)));
}
Value radians(ProgramBuilder& b, Args a) {
  return f(b.emit(ProgramOp::Mul, a[0].reg, b.constant(std::numbers::pi / 180.0)));
}
Value degrees(ProgramBuilder& b, Args a) {
  return f(b.emit(ProgramOp::Mul, a[0].reg, b.constant(180.0 / std::numbers::pi)));
}

// The geometric functions: whole vectors of one width (a scalar is a vector of one).
Reg dot_regs(ProgramBuilder& b, const Value& x, const Value& y) {
  Reg sum = b.emit(ProgramOp::Mul, x.reg, y.reg);
  for (int i = 1; i < x.width; ++i)
    sum = b.emit(ProgramOp::Add, sum, b.emit(ProgramOp::Mul, x.component(i), y.component(i)));
  return sum;
}
Value dot(ProgramBuilder& b, Args a) { return f(dot_regs(b, a[0], a[1])); }
Value length(ProgramBuilder& b, Args a) {
  // A scalar's length is its absolute value (the operator by its formula name).
  if (a[0].width == 1) return f(b.emit(op_from_name("abs"), a[0].reg));
  return f(b.emit(Op::Sqrt, dot_regs(b, a[0], a[0])));
}
Value distance(ProgramBuilder& b, Args a) {
  Value d = a[0];
  for (int i = 0; i < d.width; ++i)
    d.set_component(i, b.emit(ProgramOp::Sub, a[0].component(i), a[1].component(i)));
  const Value dv[] = {d};
  return length(b, dv);
}
// v * rsqrt(dot(v, v)), as the shading languages compute it.
Value normalize(ProgramBuilder& b, Args a) {
  const Value dv[] = {f(dot_regs(b, a[0], a[0]))};
  const Reg k = rsqrt(b, dv).reg;
  Value out = a[0];
  out.type = Type::Float;
  for (int i = 0; i < out.width; ++i)
    out.set_component(i, b.emit(ProgramOp::Mul, a[0].component(i), k));
  return out;
}
// cross(x, y) of two 3-vectors (the caller checks the width).
Value cross(ProgramBuilder& b, Args a) {
  const Value& x = a[0];
  const Value& y = a[1];
  Reg r[3];
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    r[i] = b.emit(ProgramOp::Sub, b.emit(ProgramOp::Mul, x.component(j), y.component(k)),
                  b.emit(ProgramOp::Mul, x.component(k), y.component(j)));
  }
  return make_value(r, Type::Float);
}
// reflect(i, n) = i - 2 dot(n, i) n.
Value reflect(ProgramBuilder& b, Args a) {
  const Reg k = b.emit(ProgramOp::Mul, b.constant(2.0), dot_regs(b, a[1], a[0]));
  Value out = a[0];
  out.type = Type::Float;
  for (int i = 0; i < out.width; ++i) {
    out.set_component(
        i, b.emit(ProgramOp::Sub, a[0].component(i), b.emit(ProgramOp::Mul, k, a[1].component(i))));
  }
  return out;
}

constexpr unsigned kF = kFormulaLibrary, kS = kShaderLibrary, kFS = kF | kS;
constexpr ProgramOp kExpanded = ProgramOp::Count_;
constexpr ProgramOp kOperator = ProgramOp::Operator;

// Formulas: C's math library and the approximation's functions (expr/parse.hpp). Shaders: GLSL's
// and HLSL's built-ins, for scalars and (component by component, or whole where geometric)
// vectors.
const LibraryFunction kFunctions[] = {
    {"abs", 1, kFS, kOperator, nullptr, true},
    {"fabs", 1, kF, kOperator, nullptr, false, "abs"},
    {"sign", 1, kFS, ProgramOp::Sign, nullptr, true},
    {"sqrt", 1, kFS, kOperator, nullptr, false},
    {"rsqrt", 1, kFS, kExpanded, rsqrt, false},
    {"inversesqrt", 1, kFS, kExpanded, rsqrt, false},
    {"rcp", 1, kFS, kExpanded, rcp, false},
    {"cbrt", 1, kF, ProgramOp::Cbrt, nullptr, false},
    {"exp", 1, kFS, kOperator, nullptr, false},
    {"exp2", 1, kFS, kOperator, nullptr, false},
    {"expm1", 1, kF, ProgramOp::Expm1, nullptr, false},
    {"log", 1, kFS, kOperator, nullptr, false},
    {"log2", 1, kFS, kOperator, nullptr, false},
    {"log10", 1, kFS, ProgramOp::Log10, nullptr, false},
    {"log1p", 1, kF, ProgramOp::Log1p, nullptr, false},
    {"sin", 1, kFS, kOperator, nullptr, false},
    {"cos", 1, kFS, kOperator, nullptr, false},
    {"tan", 1, kFS, ProgramOp::Tan, nullptr, false},
    {"asin", 1, kFS, kOperator, nullptr, false},
    {"acos", 1, kFS, kOperator, nullptr, false},
    {"atan", 1, kFS, kOperator, nullptr, false},
    {"atan", 2, kS, kOperator, nullptr, false, "atan2"},  // GLSL's atan(y, x)
    {"atan2", 2, kFS, kOperator, nullptr, false},
    {"sinh", 1, kFS, ProgramOp::Sinh, nullptr, false},
    {"cosh", 1, kFS, ProgramOp::Cosh, nullptr, false},
    {"tanh", 1, kFS, kOperator, nullptr, false},
    {"asinh", 1, kFS, ProgramOp::Asinh, nullptr, false},
    {"acosh", 1, kFS, ProgramOp::Acosh, nullptr, false},
    {"atanh", 1, kFS, ProgramOp::Atanh, nullptr, false},
    {"erf", 1, kF, kOperator, nullptr, false},
    {"erfc", 1, kF, ProgramOp::Erfc, nullptr, false},
    {"floor", 1, kFS, ProgramOp::Floor, nullptr, false},
    {"ceil", 1, kFS, ProgramOp::Ceil, nullptr, false},
    {"trunc", 1, kFS, ProgramOp::Trunc, nullptr, false},
    {"round", 1, kFS, ProgramOp::Round, nullptr, false},
    {"pow", 2, kFS, ProgramOp::Pow, nullptr, false},
    {"hypot", 2, kF, ProgramOp::Hypot, nullptr, false},
    {"fmod", 2, kFS, ProgramOp::Fmod, nullptr, false},
    {"fmin", 2, kF, ProgramOp::Min, nullptr, false},
    {"fmax", 2, kF, ProgramOp::Max, nullptr, false},
    {"min", 2, kFS, ProgramOp::Min, nullptr, true},
    {"max", 2, kFS, ProgramOp::Max, nullptr, true},
    {"copysign", 2, kF, kOperator, nullptr, false},
    {"clamp", 3, kFS, kExpanded, clamp, true},
    {"saturate", 1, kFS, kExpanded, saturate, false},
    {"fma", 3, kFS, kExpanded, fma, false},
    {"mad", 3, kS, kExpanded, fma, false},
    {"select", 3, kF, kExpanded, select3, false},
    {"mix", 3, kS, kExpanded, mix, false},
    {"lerp", 3, kS, kExpanded, lerp, false},
    {"step", 2, kS, kExpanded, step, false},
    {"smoothstep", 3, kS, kExpanded, smoothstep, false},
    {"fract", 1, kS, kExpanded, fract, false},
    {"frac", 1, kS, kExpanded, fract, false},
    {"mod", 2, kS, kExpanded, glsl_mod, false},
    {"radians", 1, kS, kExpanded, radians, false},
    {"degrees", 1, kS, kExpanded, degrees, false},
    {"dot", 2, kS, kExpanded, dot, false, {}, true},
    {"length", 1, kS, kExpanded, length, false, {}, true},
    {"distance", 2, kS, kExpanded, distance, false, {}, true},
    {"normalize", 1, kS, kExpanded, normalize, false, {}, true},
    {"cross", 2, kS, kExpanded, cross, false, {}, true},
    {"reflect", 2, kS, kExpanded, reflect, false, {}, true},
};

}  // namespace

Op library_operator(const LibraryFunction& fn) {
  return op_from_name(fn.operator_name.empty() ? fn.name : fn.operator_name);
}

std::vector<const LibraryFunction*> find_library_function(std::string_view name, Library library) {
  std::vector<const LibraryFunction*> out;
  for (const LibraryFunction& fn : kFunctions)
    if (fn.name == name && (fn.libraries & library) != 0) out.push_back(&fn);
  return out;
}

std::string builtin_call_name(const BuiltinFunction& fn) {
  std::string s(fn.name);
  std::replace(s.begin(), s.end(), '-', '_');
  return s;
}

const BuiltinFunction* find_builtin_by_call_name(std::string_view name) {
  for (const BuiltinFunction& fn : builtin_functions())
    if (builtin_call_name(fn) == name) return &fn;
  return nullptr;
}

std::vector<std::string> library_function_names(Library library) {
  std::set<std::string> names;
  for (const LibraryFunction& fn : kFunctions)
    if ((fn.libraries & library) != 0) names.emplace(fn.name);
  if (library == kFormulaLibrary)
    for (const BuiltinFunction& fn : builtin_functions()) names.insert(builtin_call_name(fn));
  return {names.begin(), names.end()};
}

std::string closest_name(std::string_view name, std::span<const std::string> known) {
  // Levenshtein distance, one row at a time.
  auto distance = [](std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j) {
        const std::size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
        diagonal = up;
      }
    }
    return row[b.size()];
  };
  if (name.size() > 64) return "";
  // Close enough: at most one edit in three characters of the longer name.
  std::string best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const std::string& k : known) {
    const std::size_t d = distance(name, k);
    if (d >= 1 && 3 * d <= std::max(name.size(), k.size()) && d < best_distance) {
      best_distance = d;
      best = k;
    }
  }
  return best;
}

std::string join_names(std::span<const std::string> names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace shaderfit::reference_detail
