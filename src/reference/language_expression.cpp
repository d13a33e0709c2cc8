// The one expression parser of the reference language: recursive descent with C's precedence,
// emitting instructions as it goes (language_internal.hpp).
#include <cmath>
#include <limits>

#include "language_internal.hpp"

namespace shaderfit::reference::detail {

namespace {

// Binding strength of the binary operators; 0: not one.
int precedence(const Token& t) {
  if (t.kind != Token::Symbol) return 0;
  const std::string_view s = t.text;
  if (s == "||") return 1;
  if (s == "&&") return 2;
  if (s == "==" || s == "!=") return 3;
  if (s == "<" || s == "<=" || s == ">" || s == ">=") return 4;
  if (s == "+" || s == "-") return 5;
  if (s == "*" || s == "/" || s == "%") return 6;
  return 0;
}

bool is_bitwise(const Token& t) {
  return t.kind == Token::Symbol &&
         (t.text == "^" || t.text == "&" || t.text == "|" || t.text == "<<" || t.text == ">>");
}

Type arithmetic_type(Value a, Value b) {
  return a.type != Type::Float && b.type != Type::Float ? Type::Int : Type::Float;
}

}  // namespace

ExpressionParser::ExpressionParser(std::span<const Token> tokens, std::size_t position,
                                   ProgramBuilder& builder, Dialect dialect,
                                   const std::string& source, int& nesting)
    : tokens_(tokens),
      pos_(position),
      b_(builder),
      dialect_(dialect),
      source_(source),
      nesting_(nesting) {}

ExpressionParser::Nest::Nest(const ExpressionParser& p, const Token& at) : nesting_(p.nesting_) {
  if (nesting_ >= kMaxNesting) {
    const bool formula = p.dialect_ == Dialect::Formula;
    p.fail(std::string(formula ? "formula" : "code") + " nested more than " +
               std::to_string(kMaxNesting) + " levels deep (" +
               (formula ? "parentheses, calls, signs and ?:"
                        : "parentheses, calls, signs, ?:, blocks and inlined calls") +
               ")",
           at);
  }
  ++nesting_;
}

const Token& ExpressionParser::peek(std::size_t ahead) const {
  const std::size_t i = pos_ + ahead;
  return i < tokens_.size() ? tokens_[i] : tokens_.back();
}

const Token& ExpressionParser::next() {
  const Token& t = peek();
  if (pos_ + 1 < tokens_.size()) ++pos_;
  if (t.kind != Token::End) b_.at(t);
  return t;
}

bool ExpressionParser::accept(std::string_view symbol) {
  if (!peek().is(symbol)) return false;
  next();
  return true;
}

void ExpressionParser::expect(std::string_view symbol, const std::string& what) {
  if (!accept(symbol)) {
    fail("expected '" + std::string(symbol) + "' " + what + ", found " + describe(peek(), dialect_),
         peek());
  }
}

void ExpressionParser::fail(const std::string& message, const Token& at) const {
  fail_at(message, source_, at);
}

std::optional<Value> ExpressionParser::own_call(const Token&, std::span<const Value>) {
  return std::nullopt;
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
  const Type t = a.type == b.type ? a.type : Type::Float;
  return {b_.emit(ProgramOp::Select, c.reg, a.reg, b.reg), t};
}

Value ExpressionParser::binary(int min_precedence) {
  Value lhs = unary();
  while (true) {
    const Token& op = peek();
    if (dialect_ == Dialect::Shader && is_bitwise(op))
      fail("bitwise operators are not supported ('" + std::string(op.text) + "')", op);
    const int p = precedence(op);
    if (p == 0 || p < min_precedence) return lhs;
    next();
    const Value rhs = binary(p + 1);
    lhs = apply_binary(op.text, lhs, rhs);
  }
}

Value ExpressionParser::apply_binary(std::string_view s, Value a, Value b) {
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

// unary := ('-' | '+' | '!') unary | power
Value ExpressionParser::unary() {
  // Every nested operand passes through here: parentheses, call arguments and signs.
  const Nest nest(*this, peek());
  if (dialect_ == Dialect::Shader && (peek().is("++") || peek().is("--") || peek().is("~"))) {
    fail(std::string(peek().is("~") ? "bitwise operators are"
                                    : "increments inside expressions are") +
             " not supported ('" + std::string(peek().text) + "')",
         peek());
  }
  if (accept("-")) {
    // A sign right before a number literal (not the base of '^') nests no further, as in
    // expr/parse.hpp, so that every formula it reads is read here.
    if (peek().kind == Token::Number && !peek(1).is("^")) {
      const Token& t = next();
      const bool integral = t.integral && dialect_ == Dialect::Shader;
      if (dialect_ == Dialect::Shader) check_postfix();
      return {b_.constant(-t.number), integral ? Type::Int : Type::Float};
    }
    const Value v = unary();
    return {b_.emit(ProgramOp::Neg, v.reg), v.type == Type::Bool ? Type::Int : v.type};
  }
  if (accept("+")) return unary();
  if (accept("!")) return {b_.emit(ProgramOp::Not, unary().reg), Type::Bool};
  return power();
}

// power := primary ('^' exponent)*, left-associative (x^2^3 = (x^2)^3) as in expr/parse.hpp;
// an exponent that is one integer literal makes the exact integer power.
Value ExpressionParser::power() {
  Value base = primary();
  if (dialect_ == Dialect::Shader) return base;
  while (peek().is("^")) {
    const Token& caret = next();
    if (peek().kind == Token::End) fail("an exponent is missing after '^'", caret);
    const std::size_t begin = pos_;
    const Value e = exponent();
    if (const auto k = integer_literal(begin, pos_)) {
      base = {b_.emit(ProgramOp::IPow, std::span<const Reg>(&base.reg, 1), *k), Type::Float};
    } else {
      base = {b_.emit(ProgramOp::Pow, base.reg, e.reg), Type::Float};
    }
  }
  return base;
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
  if (end > begin && (tokens_[begin].is("-") || tokens_[begin].is("+"))) {
    sign = tokens_[begin].is("-") ? -1 : 1;
    ++begin;
  }
  if (end != begin + 1) return std::nullopt;
  const Token& t = tokens_[begin];
  if (t.kind != Token::Number || !t.integral) return std::nullopt;
  const double k = sign * t.number;
  if (!(std::abs(k) <= static_cast<double>(std::numeric_limits<std::int32_t>::max())))
    return std::nullopt;
  return static_cast<std::int32_t>(k);
}

Value ExpressionParser::primary() {
  const Token& t = peek();
  Value v;
  if (t.kind == Token::Number) {
    next();
    v = {b_.constant(t.number),
         t.integral && dialect_ == Dialect::Shader ? Type::Int : Type::Float};
  } else if (t.is("(") && dialect_ == Dialect::Shader && peek(1).kind == Token::Ident &&
             scalar_type(peek(1).text) && peek(2).is(")")) {
    // A C-style cast, (float)x.
    next();
    const Type to = *scalar_type(next().text);
    next();
    return convert(b_, unary(), to);
  } else if (t.is("(")) {
    next();
    if (peek().is(")")) fail("empty parentheses", t);
    v = expression();
    if (!peek().is(")")) {
      fail("expected ')' to close the '(' at " +
               (peek().line == t.line ? "column " + std::to_string(t.column)
                                      : std::to_string(t.line) + ":" + std::to_string(t.column)) +
               ", found " + describe(peek(), dialect_),
           peek());
    }
    next();
  } else if (t.kind == Token::Ident) {
    next();
    if (peek().is("(")) {
      v = call(t);
    } else {
      // A member or subscript of a name is the error, whatever the name is.
      if (dialect_ == Dialect::Shader) check_postfix();
      v = name(t);
    }
  } else if (t.kind == Token::End) {
    fail("unexpected " + describe(t, dialect_) + ": an operand is missing", t);
  } else {
    fail("unexpected " + describe(t, dialect_) + ": an operand is missing", t);
  }
  if (dialect_ == Dialect::Shader) check_postfix();
  return v;
}

Value ExpressionParser::call(const Token& name) {
  before_call(name);
  next();  // '('
  std::vector<Value> args;
  std::vector<std::optional<std::int32_t>> literals;
  if (!peek().is(")")) {
    while (true) {
      const std::size_t begin = pos_;
      args.push_back(expression());
      literals.push_back(integer_literal(begin, pos_));
      if (!accept(",")) break;
    }
  }
  if (!peek().is(")")) {
    fail("expected ',' or ')' in the arguments of " + std::string(name.text) + ", found " +
             describe(peek(), dialect_),
         peek());
  }
  next();
  if (const auto own = own_call(name, args)) return *own;
  const std::vector<const LibraryFunction*> found = find_library_function(
      name.text, dialect_ == Dialect::Formula ? kFormulaLibrary : kShaderLibrary);
  if (!found.empty()) {
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
    // pow(a, k) with an integer literal k is the exact integer power (as in expr/parse.hpp).
    if (fn->op == ProgramOp::Pow && literals[1]) {
      return {b_.emit(ProgramOp::IPow, std::span<const Reg>(&args[0].reg, 1), *literals[1]),
              Type::Float};
    }
    if (fn->expand != nullptr) return fn->expand(b_, args);
    std::vector<Reg> regs;
    bool ints = true;
    for (const Value& a : args) {
      regs.push_back(a.reg);
      ints = ints && a.type == Type::Int;
    }
    return {b_.emit(fn->op, regs), fn->keeps_int && ints ? Type::Int : Type::Float};
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

}  // namespace shaderfit::reference::detail
