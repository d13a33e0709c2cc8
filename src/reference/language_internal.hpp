// The reference language's parts, shared by its two front ends (language.cpp: formulas and
// definitions; language_shader.cpp: GLSL and HLSL functions): the program builder with constant
// folding and the function library (language_library.cpp), and the expression parser, which
// extends expr/grammar.hpp's formula grammar (language_expression.cpp; tokens: expr/lexer.hpp).
// Internal to src/reference/.
#pragma once

#include <cstddef>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/grammar.hpp"
#include "shaderfit/expr/lexer.hpp"
#include "shaderfit/expr/op.hpp"
#include "shaderfit/reference/builtin.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/reference/program.hpp"

namespace shaderfit::reference_detail {

using namespace shaderfit::reference;  // the area's public names

// Instructions in one program at most (a shader's inlined calls can multiply its size).
inline constexpr std::size_t kMaxInstructions = std::size_t{1} << 18;

// Formulas (the approximation's syntax and its extensions, `^` is a power) or shader code
// (C's symbols and comments, literal suffixes, preprocessor lines; `^` is C's exclusive or).
enum class Dialect { Formula, Shader };

// The lexer's settings for each dialect (expr/lexer.hpp).
const Syntax& syntax(Dialect dialect);

// "'x'", or "end of formula" / "end of file" for End.
inline std::string describe(const Token& t, Dialect dialect) {
  return shaderfit::describe(t, syntax(dialect));
}

// The tokens of `text` (expr/lexer.hpp's tokenize in the dialect's syntax).
inline std::vector<Token> tokenize(std::string_view text, Dialect dialect,
                                   const std::string& source, int line = 1, int column = 1) {
  return shaderfit::tokenize(text, syntax(dialect), source, line, column);
}

[[noreturn]] void fail_at(const std::string& message, const std::string& source, const Token& at);

using Reg = std::uint32_t;

// Appends instructions to a Program. Instructions whose operands are all constants are
// evaluated at once (by the one interpreter) and become constants; a select with a constant
// condition or equal operands is its operand; equal constants share one register.
class ProgramBuilder {
 public:
  ProgramBuilder(Program& program, std::string source);

  Reg constant(double v);
  Reg input(int index);
  Reg emit(ProgramOp op, std::span<const Reg> operands, std::int32_t index = 0);
  Reg emit(ProgramOp op, Reg a) { return emit(op, std::span<const Reg>(&a, 1)); }
  // An operator of expr/op.hpp (ProgramOp::Operator).
  Reg emit(Op op, std::span<const Reg> operands) {
    return emit(ProgramOp::Operator, operands, static_cast<std::int32_t>(op));
  }
  Reg emit(Op op, Reg a) { return emit(op, std::span<const Reg>(&a, 1)); }
  Reg emit(Op op, Reg a, Reg b) {
    const Reg r[] = {a, b};
    return emit(op, r);
  }
  Reg emit(ProgramOp op, Reg a, Reg b) {
    const Reg r[] = {a, b};
    return emit(op, r);
  }
  Reg emit(ProgramOp op, Reg a, Reg b, Reg c) {
    const Reg r[] = {a, b, c};
    return emit(op, r);
  }
  // The register's value when it is a constant.
  [[nodiscard]] std::optional<double> constant_value(Reg r) const;
  // Where an error about the program's size is located: the token being compiled.
  void at(const Token& t) {
    line_ = t.line;
    column_ = t.column;
  }
  [[nodiscard]] const Program& program() const { return program_; }
  // While shader code is compiled: x * 0 is 0 too, as shader compilers fold it (formulas keep
  // C's meaning, NaN for an infinite x).
  void fold_zero_products(bool on) { zero_products_ = on; }

 private:
  Reg append(const Instruction& in);

  Program& program_;
  std::string source_;
  int line_ = 0, column_ = 0;
  bool zero_products_ = false;
  std::unordered_map<std::uint64_t, Reg> constants_;  // by bit pattern
  Program fold_;                                      // scratch for constant folding
  std::vector<double> fold_registers_;
};

// Drops the instructions no output depends on (folded constants' operands, the untaken side of
// a constant condition) and renumbers the rest.
void remove_dead_code(Program& program);

// The types of shader values' components; formulas have only Float. Bool values are 0 or 1.
enum class Type : std::uint8_t { Float, Int, Bool };

// The components of a shader vector at most (vec4, float4).
inline constexpr int kMaxWidth = 4;

struct StructType;

// A shader type: a scalar (width 1), a vector of `type`, or a struct (`record`, width 0).
struct Shape {
  Type type = Type::Float;
  int width = 1;
  const StructType* record = nullptr;
};

// A shader struct: its members in order (scalars, vectors, structs).
struct StructMember {
  std::string name;
  Shape shape;
};
struct StructType {
  std::string name;
  std::vector<StructMember> members;
  // The member called `name`'s index, or -1.
  [[nodiscard]] int member(std::string_view name) const;
};

// A value: a scalar's register, a shader vector's, one register per component, or a struct's
// members (vectors and structs are the shader dialect's; they exist only while a function is
// compiled, its result is a scalar). A struct has width 0, so that what takes numbers refuses it.
struct Value {
  Reg reg = 0;  // the scalar; a vector's first component
  Type type = Type::Float;
  int width = 1;                           // 2 to kMaxWidth: a vector; 0: a struct
  std::array<Reg, kMaxWidth - 1> more{};  // a vector's other components
  const StructType* record = nullptr;     // a struct's type
  std::vector<Value> members;             // a struct's members, in its type's order

  [[nodiscard]] Reg component(int i) const { return i == 0 ? reg : more[i - 1]; }
  void set_component(int i, Reg r) { (i == 0 ? reg : more[i - 1]) = r; }
  [[nodiscard]] Shape shape() const { return {type, width, record}; }
};

// The value whose components are `regs` (a scalar for one).
Value make_value(std::span<const Reg> regs, Type type);

// Where a library function is offered.
enum Library : unsigned { kFormulaLibrary = 1u, kShaderLibrary = 2u };

struct LibraryFunction {
  std::string_view name;
  int arity;
  unsigned libraries;
  ProgramOp op;  // the instruction, when `expand` is null
  Value (*expand)(ProgramBuilder&, std::span<const Value>);
  bool keeps_int;  // Int arguments give an Int (abs, sign, min, max, clamp)
  // ProgramOp::Operator: the operator's formula name (expr/op.hpp), when not `name` itself.
  std::string_view operator_name = {};
  // Takes vectors whole (dot, length, normalize, ...): `expand` gets them, of one width. The
  // others get scalars, and a call with vector arguments applies them component by component.
  bool geometric = false;
};

// The operator (expr/op.hpp) that a ProgramOp::Operator entry computes.
Op library_operator(const LibraryFunction& fn);

// The entries named `name` offered in `library` (an overloaded name has one per arity).
std::vector<const LibraryFunction*> find_library_function(std::string_view name, Library library);
// The built-in reference called `name` in formulas (its name with '_' for '-'), or nullptr.
const BuiltinFunction* find_builtin_by_call_name(std::string_view name);
std::string builtin_call_name(const BuiltinFunction& f);
// Every name a library offers, sorted (formulas: with the built-in references).
std::vector<std::string> library_function_names(Library library);

// The name among `known` closest to `name` by edit distance, when it is close enough to be
// worth suggesting ("" otherwise).
std::string closest_name(std::string_view name, std::span<const std::string> known);
// "a, b, c".
std::string join_names(std::span<const std::string> names);

// The scalar type a shader type name denotes (float, half, double, min16float; int, uint; bool).
std::optional<Type> scalar_type(std::string_view name);
// The scalar or vector type a shader type name denotes (the scalars above; vec2-vec4, ivec,
// uvec, bvec, dvec; float2-float4, half3, int2, bool4, ...); nullopt for others (matrices too).
std::optional<Shape> shader_type(std::string_view name);
// "float", "float3", "int2", "bool" (HLSL's spelling, for messages).
std::string shape_name(Shape s);

// A value's components converted to a type (shader declarations, parameters, returns): Float to
// Int truncates, anything to Bool compares with 0. The width is kept.
Value convert(ProgramBuilder& b, Value v, Type to);
// A value converted to a shape: its components' type as above; a scalar fills a vector, and a
// vector gives up its last components to a narrower shape (as HLSL's implicit conversions do).
// nullopt where a vector would have to widen.
std::optional<Value> convert(ProgramBuilder& b, Value v, Shape to);
// c ? a : b component by component (member by member), for a scalar condition; a and b have one
// shape, or one is a scalar and the other a vector.
Value select(ProgramBuilder& b, Reg c, const Value& a, const Value& b2);

// A value of `shape` whose every component is the scalar `v` (converted): HLSL's cast of a
// scalar to a struct, `(S)0`, and a vector's fill.
Value filled(ProgramBuilder& b, const Value& v, Shape shape);
// A value's scalar components in order, a struct's members' in turn.
void scalar_components(const Value& v, std::vector<Value>& out);
// The value of `shape` made of the scalars `parts[at]`, `parts[at + 1]`, ... (converted), `at`
// moved past them; nullopt where too few are left.
std::optional<Value> from_components(ProgramBuilder& b, Shape shape, std::span<const Value> parts,
                                     std::size_t& at);

// expr/grammar.hpp's formula grammar over a token range, extended to the reference language:
// C's operators and precedence (?: || && == != < <= > >= + - * / %, unary - + !), the formula's
// `^` with any exponent, C casts and types in shaders, and the function library; it emits
// instructions as it goes. The front ends resolve names and calls of their own (variables,
// definitions, locals, the shader's functions) through the virtual functions.
// The binding strength of C's binary operators that the reference language reads (|| 1, && 2,
// == != 3, < <= > >= 4, + - and * / % as the formula grammar's); 0 for any other token. The
// shader expressions and the preprocessor's #if both read them so.
int c_binary_precedence(const Token& t);

// Whether `member` is a swizzle: 1 to 4 letters of one of xyzw, rgba, stpq; its component
// indices.
bool is_swizzle(std::string_view member);
std::vector<int> swizzle_components(std::string_view member);

class ExpressionParser : public ExpressionGrammar<Value> {
 public:
  ExpressionParser(std::span<const Token> tokens, std::size_t position, ProgramBuilder& builder,
                   Dialect dialect, const std::string& source, int& nesting);

  // expression := binary ('?' expression ':' expression)?
  Value expression() override;

  ProgramBuilder& builder() { return b_; }
  [[nodiscard]] Dialect dialect() const { return dialect_; }

 protected:
  // The type a name stands for in casts, `(float3)x`: shader_type's; shaders add their structs.
  virtual std::optional<Shape> named_type(std::string_view name) { return shader_type(name); }
  // Called at a call's name before its arguments are read (shader: matrix constructors and
  // texture functions are errors at the name).
  virtual void before_call(const Token& /*name*/) {}
  // A message for a call of a name nobody knows.
  virtual std::string unknown_function(const Token& name);

  // a op b for a binary operator's symbol ("+", "<=", "&&", ...), with C's types (integer
  // division truncates); arithmetic applies to vectors component by component (a scalar with
  // each component), other operators of vectors are an error at `at`.
  Value apply_binary(const Token& at, std::string_view op, Value a, Value b);
  // The shader's swizzle `.member` of v (is_swizzle(member)); an error for a component v lacks.
  Value swizzle(const Value& v, const Token& member);
  // After a subscript's '[' (`open`, just read): its index up to the ']', which must be a
  // constant from 0 to size - 1; else the error "a subscript of <of> must be ..." + `why`.
  int constant_subscript(const Token& open, int size, const std::string& of,
                         std::string_view why = {});
  // The index of the member of `type` that `member` names; an error naming its members else.
  int member_of(const StructType& type, const Token& member);
  // "<what> of a S: a struct is not a number ...", for a struct value `v` where a number belongs.
  static std::string not_a_number(const std::string& what, const Value& v);

  // The grammar's hooks.
  int precedence(const Token& t) override;
  Value binary_op(const Token& op, Value a, Value b) override;
  std::optional<Value> prefix() override;
  Value negate(Value v) override;
  Value literal(const Token& number, bool negative) override;
  Value power_of(Value base, const Token& caret) override;
  std::optional<Value> special_primary() override;
  Value call(const Token& name) override;
  Value postfix(Value v) override;
  void consumed(const Token& t) override;
  std::string nesting_message() const override;

 private:
  Value exponent();
  Value scalar_binary(std::string_view op, Value a, Value b);
  Value construct(const Token& name, Shape to, std::span<const Value> args);
  Value apply_library(const LibraryFunction& fn, std::span<const Value> args,
                      std::span<const std::optional<std::int32_t>> literals);
  // The integer written by tokens [begin, end) when they are one integer literal with at most
  // one sign, in the int32 range.
  [[nodiscard]] std::optional<std::int32_t> integer_literal(std::size_t begin,
                                                            std::size_t end) const;

  ProgramBuilder& b_;
  Dialect dialect_;
};

// The shader front end (language_shader.cpp): text.function of text.shader_source compiled into
// the builder's program, whose inputs become the function's parameters (in text.variables'
// order when given).
struct ShaderFunction {
  std::string name;
  std::vector<Reg> inputs;  // the Input register of each program input
  Reg result = 0;
};
ShaderFunction compile_shader_function(const ReferenceText& text, ProgramBuilder& builder,
                                       Program& program);

}  // namespace shaderfit::reference_detail
