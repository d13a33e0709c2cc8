// The reference language's expression parser: expr/grammar.hpp's grammar extended with C's
// operators and types, the general `^` and the function library, emitting instructions as it goes
// (language_internal.hpp); and the lexer's settings for its two dialects.
#include <algorithm>
#include <cmath>
#include <limits>

#include "language_internal.hpp"

namespace shaderfit::reference_detail {

using namespace shaderfit::reference;  // the area's public names

namespace {

// Longest first, so that "<=" is one token and "<" another.
constexpr std::string_view kFormulaSymbols[] = {"<=", ">=", "==", "!=", "&&", "||", "+",
                                                "-",  "*",  "/",  "^",  "(",  ")",  ",",
                                                "<",  ">",  "!",  "?",  ":",  "="};
constexpr std::string_view kShaderSymbols[] = {
    "<<=", ">>=", "<=", ">=", "==", "!=", "&&", "||", "++", "--", "+=", "-=",
    "*=",  "/=",  "%=", "&=", "|=", "^=", "<<", ">>", "->", "::", "+",  "-",
    "*",   "/",   "%",  "^",  "&",  "|",  "~",  "(",  ")",  "[",  "]",  "{",
    "}",   ",",   ";",  ".",  "<",  ">",  "!",  "?",  ":",  "="};

bool is_bitwise(const Token& t) {
  return t.kind == Token::Symbol &&
         (t.text == "^" || t.text == "&" || t.text == "|" || t.text == "<<" || t.text == ">>");
}

Type arithmetic_type(Value a, Value b) {
  return a.type != Type::Float && b.type != Type::Float ? Type::Int : Type::Float;
}

// Component i of v, a scalar standing for each component of a vector.
Value part(const Value& v, int i) { return {v.component(v.width == 1 ? 0 : i), v.type}; }

// A swizzle's component index for one letter (x y z w, r g b a, s t p q); -1 for others.
int swizzle_index(char c, std::string_view set) {
  const auto k = set.find(c);
  return k == std::string_view::npos ? -1 : static_cast<int>(k);
}
constexpr std::string_view kSwizzleSets[] = {"xyzw", "rgba", "stpq"};

}  // namespace

bool is_swizzle(std::string_view member) {
  if (member.empty() || member.size() > static_cast<std::size_t>(kMaxWidth)) return false;
  for (const std::string_view set : kSwizzleSets) {
    bool all = true;
    for (const char c : member) all = all && swizzle_index(c, set) >= 0;
    if (all) return true;
  }
  return false;
}

std::vector<int> swizzle_components(std::string_view member) {
  std::vector<int> out;
  for (const std::string_view set : kSwizzleSets) {
    out.clear();
    for (const char c : member) out.push_back(swizzle_index(c, set));
    if (std::find(out.begin(), out.end(), -1) == out.end()) return out;
  }
  return {};
}

const Syntax& syntax(Dialect dialect) {
  static const Syntax formula{kFormulaSymbols};
  static const Syntax shader{kShaderSymbols, true, true, true, "end of file"};
  return dialect == Dialect::Formula ? formula : shader;
}

void fail_at(const std::string& message, const std::string& source, const Token& at) {
  throw Error(message, SourceLocation{source, at.line, at.column});
}

ExpressionParser::ExpressionParser(std::span<const Token> tokens, std::size_t position,
                                   ProgramBuilder& builder, Dialect dialect,
                                   const std::string& source, int& nesting)
    : ExpressionGrammar(TokenStream(tokens, position), syntax(dialect), source, nesting,
                        dialect == Dialect::Formula),
      b_(builder),
      dialect_(dialect) {}

std::string ExpressionParser::nesting_message() const {
  const bool formula = dialect_ == Dialect::Formula;
  return std::string(formula ? "formula" : "code") + " nested more than " +
         std::to_string(kMaxFormulaNesting) + " levels deep (" +
         (formula ? "parentheses, calls, signs and ?:"
                  : "parentheses, calls, signs, ?:, blocks and inlined calls") +
         ")";
}

void ExpressionParser::consumed(const Token& t) {
  if (t.kind != Token::End) b_.at(t);
}


std::string ExpressionParser::unknown_function(const Token& name) {
  const std::vector<std::string> known =
      library_function_names(dialect_ == Dialect::Formula ? kFormulaLibrary : kShaderLibrary);
  const std::string near = closest_name(name.text, known);
  if (!near.empty())
    return "unknown function '" + std::string(name.text) + "' (did you mean " + near + "?)";
  return "unknown function '" + std::string(name.text) + "' (known: " + join_names(known) + ")";
}

Value ExpressionParser::expression() {
  const Value c = binary(1);
  if (!peek().is("?")) return c;
  const Token& question = next();
  const Nest nest(*this, question);
  const Value a = expression();
  expect(":", "after the first branch of '?' at column " + std::to_string(question.column));
  const Value b = expression();
  if (c.width != 1) fail("the condition of '?' is a " + shape_name(c.shape()) + ", not a scalar", question);
  if ((!a.is_number() || !b.is_number()) &&
      (a.record != b.record || a.rows != b.rows || a.columns != b.columns)) {
    fail("the branches of '?' have different types (" + shape_name(a.shape()) + " and " +
             shape_name(b.shape()) + ")",
         question);
  }
  if (a.width != 1 && b.width != 1 && a.width != b.width) {
    fail("the branches of '?' have different sizes (" + shape_name(a.shape()) + " and " +
             shape_name(b.shape()) + ")",
         question);
  }
  return select(b_, c.reg, a, b);
}

// The formula's + - * / and C's other binary operators; in shaders, bitwise operators are an
// error at the operator.
int ExpressionParser::precedence(const Token& t) {
  if (dialect_ == Dialect::Shader && is_bitwise(t))
    fail("bitwise operators are not supported ('" + std::string(t.text) + "')", t);
  return c_binary_precedence(t);
}

int c_binary_precedence(const Token& t) {
  if (t.kind != Token::Symbol) return 0;
  const std::string_view s = t.text;
  if (s == "||") return 1;
  if (s == "&&") return 2;
  if (s == "==" || s == "!=") return 3;
  if (s == "<" || s == "<=" || s == ">" || s == ">=") return 4;
  if (s == "%") return ExpressionGrammar<Value>::kMultiplicative;
  return ExpressionGrammar<Value>::formula_precedence(t);
}

Value ExpressionParser::binary_op(const Token& op, Value a, Value b) {
  return apply_binary(op, op.text, a, b);
}

Value ExpressionParser::apply_binary(const Token& at, std::string_view s, Value a, Value b) {
  for (const Value* v : {&a, &b})
    if (v->record != nullptr) fail(not_a_number("'" + std::string(s) + "'", *v), at);
  if (a.is_matrix() || b.is_matrix()) return matrix_binary(at, s, a, b);
  if (a.width == 1 && b.width == 1) return scalar_binary(s, a, b);
  const bool arithmetic = s == "+" || s == "-" || s == "*" || s == "/" || s == "%";
  if (!arithmetic) {
    fail("'" + std::string(s) + "' of vectors is not supported (compare or combine their components)",
         at);
  }
  if (a.width != 1 && b.width != 1 && a.width != b.width) {
    fail("'" + std::string(s) + "' of vectors of different sizes (" + shape_name(a.shape()) +
             " and " + shape_name(b.shape()) + ")",
         at);
  }
  Value out;
  out.width = std::max(a.width, b.width);
  for (int i = 0; i < out.width; ++i) {
    const Value r = scalar_binary(s, part(a, i), part(b, i));
    out.set_component(i, r.reg);
    out.type = r.type;
  }
  return out;
}

Value ExpressionParser::scalar_binary(std::string_view s, Value a, Value b) {
  auto bin = [&](ProgramOp o) { return b_.emit(o, a.reg, b.reg); };
  if (s == "||") return {bin(ProgramOp::Or), Type::Bool};
  if (s == "&&") return {bin(ProgramOp::And), Type::Bool};
  if (s == "==") return {bin(ProgramOp::Equal), Type::Bool};
  if (s == "!=") return {bin(ProgramOp::NotEqual), Type::Bool};
  if (s == "<") return {bin(ProgramOp::Less), Type::Bool};
  if (s == "<=") return {bin(ProgramOp::LessEqual), Type::Bool};
  if (s == ">") return {bin(ProgramOp::Greater), Type::Bool};
  if (s == ">=") return {bin(ProgramOp::GreaterEqual), Type::Bool};
  const Type t = arithmetic_type(a, b);
  if (s == "+") return {bin(ProgramOp::Add), t};
  if (s == "-") return {bin(ProgramOp::Sub), t};
  if (s == "*") return {bin(ProgramOp::Mul), t};
  if (s == "%") return {bin(ProgramOp::Fmod), t};
  // Integer division truncates, as in C.
  const Reg q = bin(ProgramOp::Div);
  return {t == Type::Int ? b_.emit(ProgramOp::Trunc, q) : q, t};
}

// '!' and, in shaders, the increments and '~' the subset leaves out.
std::optional<Value> ExpressionParser::prefix() {
  if (dialect_ == Dialect::Shader && (peek().is("++") || peek().is("--") || peek().is("~"))) {
    fail(std::string(peek().is("~") ? "bitwise operators are"
                                    : "increments inside expressions are") +
             " not supported ('" + std::string(peek().text) + "')",
         peek());
  }
  if (peek().is("!")) {
    const Token& bang = next();
    const Value v = unary();
    if (!v.is_number()) fail(not_a_number("'!'", v), bang);
    if (v.width != 1) fail("'!' of a vector is not supported (negate its components)", bang);
    return Value{b_.emit(ProgramOp::Not, v.reg), Type::Bool};
  }
  return std::nullopt;
}

Value ExpressionParser::negate(Value v) {
  if (v.record != nullptr) fail(not_a_number("'-'", v), token_at(position() - 1));
  for (Value& row : v.members) row = negate(row);
  for (int i = 0; i < v.width; ++i) v.set_component(i, b_.emit(ProgramOp::Neg, v.component(i)));
  if (v.type == Type::Bool) v.type = Type::Int;
  return v;
}

// In shaders, an integer literal is an int.
Value ExpressionParser::literal(const Token& t, bool negative) {
  const bool integral = t.integral && dialect_ == Dialect::Shader;
  if (negative) check_postfix();
  return {b_.constant(negative ? -t.number : t.number), integral ? Type::Int : Type::Float};
}

// After '^' (formulas): any exponent; one that is one integer literal makes the exact integer
// power.
Value ExpressionParser::power_of(Value base, const Token& caret) {
  if (peek().kind == Token::End) fail("an exponent is missing after '^'", caret);
  const std::size_t begin = position();
  const Value e = exponent();
  if (const auto k = integer_literal(begin, position()))
    return {b_.emit(ProgramOp::IPow, std::span<const Reg>(&base.reg, 1), *k), Type::Float};
  return {b_.emit(ProgramOp::Pow, base.reg, e.reg), Type::Float};
}

// exponent := ('-' | '+')* primary; the signs are counted, not nested (negation is exact, so
// an even count leaves the operand as it is).
Value ExpressionParser::exponent() {
  bool negative = false;
  while (peek().is("-") || peek().is("+")) negative = next().is("-") != negative;
  const Value v = primary();
  return negative ? Value{b_.emit(ProgramOp::Neg, v.reg), Type::Float} : v;
}

std::optional<std::int32_t> ExpressionParser::integer_literal(std::size_t begin,
                                                              std::size_t end) const {
  double sign = 1;
  if (end > begin && (token_at(begin).is("-") || token_at(begin).is("+"))) {
    sign = token_at(begin).is("-") ? -1 : 1;
    ++begin;
  }
  if (end != begin + 1) return std::nullopt;
  const Token& t = token_at(begin);
  if (t.kind != Token::Number || !t.integral) return std::nullopt;
  const double k = sign * t.number;
  if (!(std::abs(k) <= static_cast<double>(std::numeric_limits<std::int32_t>::max())))
    return std::nullopt;
  return static_cast<std::int32_t>(k);
}

// A C-style cast in shaders, (float)x, (float3)x.
std::optional<Value> ExpressionParser::special_primary() {
  if (!(peek().is("(") && dialect_ == Dialect::Shader && peek(1).kind == Token::Ident &&
        peek(2).is(")")))
    return std::nullopt;
  const std::optional<Shape> type_named = named_type(peek(1).text);
  if (!type_named) return std::nullopt;
  next();
  const Token& type = next();
  next();
  const Shape to = *type_named;
  const Value v = unary();
  // HLSL: a scalar cast to a struct or a matrix gives every member its value, (S)0.
  if ((to.record != nullptr || to.is_matrix()) && v.width == 1) return filled(b_, v, to);
  const std::optional<Value> out = convert(b_, v, to);
  if (!out) fail("cannot cast a " + shape_name(v.shape()) + " to " + std::string(type.text), type);
  return *out;
}

// Shaders: a swizzle (.x, .xy, .rgb, .zyx, ...) or a constant subscript ([0]) of a vector or a
// scalar; formulas have none.
Value ExpressionParser::postfix(Value v) {
  while (dialect_ == Dialect::Shader) {
    if (v.record != nullptr && peek().is(".") && peek(1).kind == Token::Ident) {
      next();
      v = Value(v.members[static_cast<std::size_t>(member_of(*v.record, next()))]);
    } else if (v.record != nullptr && peek().is("[")) {
      fail("a subscript of a " + v.record->name + ": a struct has members, not components",
           peek());
    } else if (v.is_matrix() && peek().is("[")) {
      const Token& open = next();
      const int size = v.glsl ? v.columns : v.rows;
      v = matrix_subscript(v, constant_subscript(open, size, "a " + shape_name(v.shape())));
    } else if (v.is_matrix() && peek().is(".")) {
      fail("a member of a " + shape_name(v.shape()) + ": a matrix's elements are read as m[i][j]",
           peek());
    } else if (peek().is(".") && peek(1).kind == Token::Ident) {
      next();
      const Token& member = next();
      if (!is_swizzle(member.text)) {
        fail("'." + std::string(member.text) + "' of a " + shape_name(v.shape()) +
                 ": only structs have members",
             member);
      }
      v = swizzle(v, member);
    } else if (peek().is("[")) {
      const Token& open = next();
      if (v.width == 1) fail("a subscript of a scalar: arrays are not supported", open);
      v = part(v, constant_subscript(open, v.width, "a " + shape_name(v.shape())));
    } else {
      break;
    }
  }
  check_postfix();
  return v;
}

int ExpressionParser::member_of(const StructType& type, const Token& member) {
  const int k = type.member(member.text);
  if (k < 0) {
    std::vector<std::string> names;
    for (const StructMember& m : type.members) names.push_back(m.name);
    fail("'" + type.name + "' has no member '" + std::string(member.text) + "' (its members: " +
             join_names(names) + ")",
         member);
  }
  return k;
}

std::string ExpressionParser::not_a_number(const std::string& what, const Value& v) {
  if (v.record != nullptr)
    return what + " of a " + v.record->name + ": a struct is not a number (use its members)";
  return what + " of a " + shape_name(v.shape()) + ": a matrix is not a number (use m[i][j])";
}

Value ExpressionParser::matrix_binary(const Token& at, std::string_view op, const Value& a,
                                      const Value& b) {
  const Value& m = a.is_matrix() ? a : b;
  const std::string sizes = shape_name(a.shape()) + " and a " + shape_name(b.shape());
  if (op == "*" && m.glsl && a.width != 1 && b.width != 1) {
    if (std::optional<Value> r = matrix_product(b_, a, b)) return *r;
    fail("'*' of a " + sizes + ": their sizes do not fit", at);
  }
  if (op != "+" && op != "-" && op != "*" && op != "/")
    fail("'" + std::string(op) + "' of matrices is not supported", at);
  if (a.is_matrix() && b.is_matrix() && (a.rows != b.rows || a.columns != b.columns))
    fail("'" + std::string(op) + "' of a " + sizes + ": their sizes differ", at);
  if ((!a.is_matrix() && a.width != 1) || (!b.is_matrix() && b.width != 1)) {
    fail("'" + std::string(op) + "' of a " + sizes + " (" +
             (m.glsl ? "a matrix takes vectors only in a product" : "mul() is the product") + ")",
         at);
  }
  std::vector<Value> rows;
  for (std::size_t i = 0; i < m.members.size(); ++i)
    rows.push_back(apply_binary(at, op, a.is_matrix() ? a.members[i] : a,
                                b.is_matrix() ? b.members[i] : b));
  return make_matrix(m.shape(), std::move(rows));
}

int ExpressionParser::constant_subscript(const Token& open, int size, const std::string& of,
                                         std::string_view why) {
  const Value k = expression();
  expect("]", "to close the subscript at column " + std::to_string(open.column));
  const auto c = k.width == 1 ? b_.constant_value(k.reg) : std::nullopt;
  if (!c || *c != std::trunc(*c) || *c < 0 || *c >= size) {
    fail("a subscript of " + of + " must be a constant from 0 to " + std::to_string(size - 1) +
             std::string(why),
         open);
  }
  return static_cast<int>(*c);
}

Value ExpressionParser::swizzle(const Value& v, const Token& member) {
  const std::vector<int> picked = swizzle_components(member.text);
  std::vector<Reg> regs;
  for (std::size_t k = 0; k < picked.size(); ++k) {
    if (picked[k] >= v.width) {
      fail("'." + std::string(member.text) + "' of a " + shape_name(v.shape()) + ": it has no '" +
               member.text[k] + "'",
           member);
    }
    regs.push_back(v.component(picked[k]));
  }
  return make_value(regs, v.type);
}

Value ExpressionParser::initializer_list(Shape shape, const std::string& what) {
  const Token& open = peek();
  std::vector<Value> parts;
  initializer_parts(parts);
  std::size_t at = 0;
  std::optional<Value> v = from_components(b_, shape, parts, at);
  if (!v || at != parts.size()) {
    fail("the values in braces for " + what + " have " + counted(parts.size(), "component") +
             ", and a " + shape_name(shape) + " has " + std::to_string(scalar_count(shape)),
         open);
  }
  return *v;
}

std::vector<Value> ExpressionParser::array_values(Shape element, int size, const Token& name) {
  const std::string of = "'" + std::string(name.text) + "'";
  const Token& at = peek();
  std::vector<Value> parts;
  if (at.is("{")) {
    initializer_parts(parts);
  } else if (at.kind == Token::Ident && shader_type(at.text) && peek(1).is("[")) {
    next();
    next();
    while (!peek().is("]") && peek().kind != Token::End) next();
    expect("]", "in the array's type");
    const Token& open = peek();
    if (!open.is("(")) fail("expected '(' after the array's type, found " + describe(open), open);
    arguments(open, [&](int) { scalar_components(expression(), parts); });
    next();
  } else {
    fail("expected '{' or an array constructor for the values of " + of + ", found " +
             describe(at),
         at);
  }
  const std::size_t n = scalar_count(element);
  if (size < 0 && parts.size() % n == 0 && !parts.empty())
    size = static_cast<int>(parts.size() / n);
  if (size < 0 || parts.size() != static_cast<std::size_t>(size) * n) {
    const std::string elements =
        size < 0 ? "whole elements" : counted(static_cast<std::size_t>(size), "element");
    fail("the values of " + of + " have " + counted(parts.size(), "component") + ", and " +
             elements + " of " + shape_name(element) + " take " +
             (size < 0 ? "a multiple of " + std::to_string(n) : std::to_string(size * n)),
         at);
  }
  std::vector<Value> out;
  std::size_t k = 0;
  for (int i = 0; i < size; ++i) out.push_back(*from_components(b_, element, parts, k));
  return out;
}

// `{ value (, value)* [,] }`, each value an expression or braces again: their scalars in order.
void ExpressionParser::initializer_parts(std::vector<Value>& parts) {
  const Token& open = next();
  while (!peek().is("}")) {
    if (peek().kind == Token::End) fail("'{' is not closed", open);
    if (peek().is("{")) {
      initializer_parts(parts);
    } else {
      scalar_components(expression(), parts);
    }
    if (!accept(",")) break;
  }
  expect("}", "after the values in braces");
}

// A shader's type constructor: float(x) converts; float3(x) fills every component with a scalar;
// float3(a, b.xy) takes the components of its arguments in order, as many as the type has.
Value ExpressionParser::construct(const Token& name, Shape to, std::span<const Value> args) {
  const std::string type(name.text);
  if (args.empty()) fail(type + "(...) needs a value", name);
  if (to.is_matrix()) {
    for (const Value& a : args)
      if (a.record != nullptr) fail(not_a_number(type + "(...)", a), name);
    if (std::optional<Value> m = construct_matrix(b_, to, args)) return *m;
    std::vector<Value> parts;
    for (const Value& a : args) scalar_components(a, parts);
    fail(type + "(...) is given " + counted(parts.size(), "component") + ", and has " +
             std::to_string(to.rows * to.columns),
         name);
  }
  for (const Value& a : args)
    if (!a.is_number()) fail(not_a_number(type + "(...)", a), name);
  if (args.size() == 1 && (args[0].width == 1 || args[0].width >= to.width)) {
    return *convert(b_, args[0], to);
  }
  std::vector<Reg> regs;
  for (const Value& a : args)
    for (int i = 0; i < a.width; ++i) regs.push_back(convert(b_, part(a, i), to.type).reg);
  if (regs.size() != static_cast<std::size_t>(to.width)) {
    fail(type + "(...) is given " + std::to_string(regs.size()) + " components, and has " +
             std::to_string(to.width),
         name);
  }
  return make_value(regs, to.type);
}

Value ExpressionParser::construct_struct(const Token& name, const StructType& type) {
  std::vector<Value> args;
  arguments(name, [&](int) { args.push_back(expression()); });
  next();
  if (args.size() != type.members.size()) {
    fail(type.name + "(...) is given " + counted(args.size(), "value") + ", and has " +
             counted(type.members.size(), "member"),
         name);
  }
  Value out = filled(b_, Value{b_.constant(0.0)}, Shape{Type::Float, 0, &type});
  for (std::size_t k = 0; k < args.size(); ++k) {
    const StructMember& m = type.members[k];
    std::optional<Value> v = convert(b_, args[k], m.shape);
    if (!v) {
      fail("cannot give a " + shape_name(args[k].shape()) + " to the member '" + m.name +
               "' of " + type.name + ", a " + shape_name(m.shape),
           name);
    }
    out.members[k] = std::move(*v);
  }
  return out;
}

bool is_matrix_function(std::string_view name) { return name == "mul" || name == "transpose"; }

// HLSL's mul(a, b), the product of matrices, vectors and scalars; transpose(m).
Value ExpressionParser::matrix_function(const Token& name, std::span<const Value> args) {
  const std::size_t want = name.text == "mul" ? 2 : 1;
  if (args.size() != want) {
    fail(std::string(name.text) + " takes " + counted(want, "argument") + ", got " +
             std::to_string(args.size()),
         name);
  }
  for (const Value& a : args)
    if (a.record != nullptr) fail(not_a_number(std::string(name.text), a), name);
  if (name.text == "transpose") {
    if (!args[0].is_matrix()) fail("transpose of a " + shape_name(args[0].shape()), name);
    return transpose(args[0]);
  }
  if (args[0].width == 1 || args[1].width == 1) return apply_binary(name, "*", args[0], args[1]);
  if (std::optional<Value> r = matrix_product(b_, args[0], args[1])) return *r;
  fail("mul of a " + shape_name(args[0].shape()) + " and a " + shape_name(args[1].shape()) +
           ": their sizes do not fit",
       name);
}

// A library function of one set of arguments: scalars, or a geometric one's vectors.
Value ExpressionParser::apply_library(const LibraryFunction& fn, std::span<const Value> args,
                                      std::span<const std::optional<std::int32_t>> literals) {
  // pow(a, k) with an integer literal k is the exact integer power (as in expr/parse.hpp).
  if (fn.op == ProgramOp::Pow && literals[1]) {
    return {b_.emit(ProgramOp::IPow, std::span<const Reg>(&args[0].reg, 1), *literals[1]),
            Type::Float};
  }
  if (fn.expand != nullptr) return fn.expand(b_, args);
  std::vector<Reg> regs;
  bool ints = true;
  for (const Value& a : args) {
    regs.push_back(a.reg);
    ints = ints && a.type == Type::Int;
  }
  const Reg r = fn.op == ProgramOp::Operator ? b_.emit(library_operator(fn), regs)
                                             : b_.emit(fn.op, regs);
  return {r, fn.keeps_int && ints ? Type::Int : Type::Float};
}

Value ExpressionParser::call(const Token& name) {
  before_call(name);
  std::vector<Value> args;
  std::vector<std::optional<std::int32_t>> literals;
  arguments(name, [&](int) {
    const std::size_t begin = position();
    args.push_back(expression());
    literals.push_back(integer_literal(begin, position()));
  });
  next();
  if (dialect_ == Dialect::Shader) {
    if (const auto to = shader_type(name.text)) return construct(name, *to, args);
    if (is_matrix_function(name.text)) return matrix_function(name, args);
  }
  const std::vector<const LibraryFunction*> found = find_library_function(
      name.text, dialect_ == Dialect::Formula ? kFormulaLibrary : kShaderLibrary);
  if (!found.empty()) {
    for (const Value& a : args)
      if (!a.is_number()) fail(not_a_number(std::string(name.text), a), name);
    const LibraryFunction* fn = nullptr;
    for (const LibraryFunction* c : found)
      if (c->arity == static_cast<int>(args.size())) fn = c;
    if (fn == nullptr) {
      std::string want;
      for (const LibraryFunction* c : found)
        want += (want.empty() ? "" : " or ") + std::to_string(c->arity);
      fail(std::string(name.text) + " takes " + want +
               (found.size() == 1 && found[0]->arity == 1 ? " argument" : " arguments") + ", got " +
               std::to_string(args.size()),
           name);
    }
    int width = 1;
    for (const Value& a : args) width = std::max(width, a.width);
    for (const Value& a : args) {
      if (a.width != width && (fn->geometric || a.width != 1)) {
        fail("the arguments of " + std::string(name.text) + " have different sizes (" +
                 shape_name(a.shape()) + " and " + shape_name(Shape{Type::Float, width}) + ")",
             name);
      }
    }
    if (fn->name == "cross" && width != 3)
      fail("cross takes two 3-component vectors, got " + shape_name(args[0].shape()), name);
    if (width == 1 || fn->geometric) return apply_library(*fn, args, literals);
    // A vector call of a scalar function: component by component.
    Value out;
    out.width = width;
    std::vector<Value> parts(args.size());
    for (int i = 0; i < width; ++i) {
      for (std::size_t k = 0; k < args.size(); ++k) parts[k] = part(args[k], i);
      const Value r = apply_library(*fn, parts, literals);
      out.set_component(i, r.reg);
      out.type = r.type;
    }
    return out;
  }
  if (dialect_ == Dialect::Formula) {
    if (const BuiltinFunction* fn = find_builtin_by_call_name(name.text)) {
      if (args.size() != fn->arguments.size()) {
        fail(std::string(name.text) + " takes " + std::to_string(fn->arguments.size()) +
                 " arguments, got " + std::to_string(args.size()),
             name);
      }
      std::vector<Reg> regs;
      for (const Value& a : args) regs.push_back(a.reg);
      return {b_.emit(ProgramOp::Builtin, regs, static_cast<std::int32_t>(fn->id)), Type::Float};
    }
  }
  fail(unknown_function(name), name);
}

}  // namespace shaderfit::reference_detail
