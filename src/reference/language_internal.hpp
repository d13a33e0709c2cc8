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

// A shader type: a scalar (width 1), a vector of `type`, a struct (`record`, width 0) or a
// matrix (`rows` x `columns` floats, width 0).
struct Shape {
  Type type = Type::Float;
  int width = 1;
  const StructType* record = nullptr;
  int rows = 0, columns = 0;  // a matrix's
  // A matrix of GLSL (mat3, mat2x3): its constructors fill columns, m[i] is a column and `*` is
  // the matrix product. HLSL's (float3x3) fill rows, m[i] is a row, `*` is component by
  // component and mul() the product.
  bool glsl = false;
  [[nodiscard]] bool is_matrix() const { return rows > 0; }
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

// A value: a scalar's register, a shader vector's, one register per component, a struct's
// members or a matrix's rows (vectors, structs and matrices are the shader dialect's; they exist
// only while a function is compiled, its result is a scalar). Structs and matrices have width 0,
// so that what takes numbers refuses them.
struct Value {
  Reg reg = 0;  // the scalar; a vector's first component
  Type type = Type::Float;
  int width = 1;                           // 2 to kMaxWidth: a vector; 0: a struct or a matrix
  std::array<Reg, kMaxWidth - 1> more{};  // a vector's other components
  const StructType* record = nullptr;     // a struct's type
  int rows = 0, columns = 0;              // a matrix's size
  bool glsl = false;                      // a GLSL matrix (see Shape)
  std::vector<Value> members;             // a struct's members in order, a matrix's rows

  [[nodiscard]] Reg component(int i) const { return i == 0 ? reg : more[i - 1]; }
  void set_component(int i, Reg r) { (i == 0 ? reg : more[i - 1]) = r; }
  [[nodiscard]] Shape shape() const { return {type, width, record, rows, columns, glsl}; }
  [[nodiscard]] bool is_number() const { return width > 0; }
  [[nodiscard]] bool is_matrix() const { return rows > 0; }
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

// "1 value", "2 values".
inline std::string counted(std::size_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

// The name among `known` closest to `name` by edit distance, when it is close enough to be
// worth suggesting ("" otherwise).
std::string closest_name(std::string_view name, std::span<const std::string> known);
// "a, b, c".
std::string join_names(std::span<const std::string> names);

// The scalar type a shader type name denotes (float, half, double, min16float; int, uint; bool).
std::optional<Type> scalar_type(std::string_view name);
// The scalar, vector or matrix type a shader type name denotes (the scalars above; vec2-vec4,
// ivec, uvec, bvec, dvec; float2-float4, half3, int2, bool4, ...; mat2-mat4, mat2x3, dmat3;
// float3x3, half2x4, ...); nullopt for others (a matrix of ints or bools too).
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
// scalar to a struct or a matrix, `(S)0`, and a vector's fill.
Value filled(ProgramBuilder& b, const Value& v, Shape shape);

// Matrices (language_matrix.cpp). The matrix of `shape` whose rows are `rows`.
Value make_matrix(Shape shape, std::vector<Value> rows);
// A matrix's column j, a vector of its rows' j-th components.
Value matrix_column(const Value& m, int j);
// m[i]: a GLSL matrix's column i, an HLSL matrix's row i.
Value matrix_subscript(const Value& m, int i);
// The matrix product a b of matrices and vectors (a vector on the left is a row, on the right a
// column; of two vectors, their dot product), as HLSL's mul() and GLSL's `*` compute it;
// nullopt where the sizes do not fit.
std::optional<Value> matrix_product(ProgramBuilder& b, const Value& x, const Value& y);
// A matrix's transpose.
Value transpose(const Value& m);
// Whether `name` is a shader built-in of matrices (mul, transpose; language_expression.cpp).
bool is_matrix_function(std::string_view name);
// A matrix constructor's value, from its arguments: GLSL's mat3(s) is s on the diagonal, mat3(m)
// the top left of m (or m within the identity); otherwise the arguments' components fill the
// matrix, a GLSL matrix's by columns, an HLSL one's by rows. nullopt for the wrong number.
std::optional<Value> construct_matrix(ProgramBuilder& b, Shape to, std::span<const Value> args);
// How many scalar components a value of `shape` has (a struct's members' in all).
std::size_t scalar_count(Shape shape);
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

  // `{ a, b, ... }` for `what`, a value of `shape`, from its '{' (HLSL's braces): the values'
  // scalar components fill the shape's in order (inner braces group nothing).
  Value initializer_list(Shape shape, const std::string& what);
  // An array's values, from the current token: `{ ... }` (the values' scalar components fill
  // the elements in order, as HLSL reads them: `float3 k[2] = {1, 2, 3, 4, 5, 6}`) or GLSL's
  // `type[N](a, b, ...)`. `size`: the declared size, or -1 where the values give it. An error
  // at `name` where they do not fill the elements exactly.
  std::vector<Value> array_values(Shape element, int size, const Token& name);
  // GLSL's struct constructor S(a, b, ...), after the name: one value per member, in order.
  Value construct_struct(const Token& name, const StructType& type);

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
  // "<what> of a S: a struct is not a number ...", for a struct or matrix `v` where a number
  // belongs.
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
  void initializer_parts(std::vector<Value>& parts);
  // a op b where either is a matrix: + - / component by component (a scalar with each), * too
  // for HLSL's, the product for GLSL's.
  Value matrix_binary(const Token& at, std::string_view op, const Value& a, const Value& b);
  Value matrix_function(const Token& name, std::span<const Value> args);
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
