// The one expression grammar of shaderfit's formulas, over expr/lexer.hpp's tokens: precedence
// climbing over binary operators, unary signs, `^`, number literals, parentheses, names and calls.
// The approximation's parser (expr/parse.hpp) emits Expression nodes through it; the reference
// language (reference/language.hpp) extends it with its operators (comparisons, && || !, ?:, %),
// its `^` and its calls, and builds its statements on it.
//
//   expression := binary                         (an extension may add more: c ? a : b)
//   binary     := unary (op unary)*              (op and its binding strength: precedence())
//   unary      := '-' number | '-' unary | '+' unary | prefix() | power
//   power      := primary ('^' exponent)*        (left-associative; exponent: power_of())
//   primary    := number | '(' expression ')' | name | name '(' arguments ')'
//
// A '-' right before a number literal that is not the base of '^' makes a negative literal
// (-2^2 = -(2^2)). Each operand nests one level (parentheses, call arguments and signs), at most
// kMaxFormulaNesting, so that no input exhausts the stack. Hooks emit values as the parse goes,
// so that operands come before their operator.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/lexer.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {

template <class Value>
class ExpressionGrammar {
 public:
  // Binding strengths of the formula's binary operators; an extension's bind less (1 ..
  // kAdditive - 1) or as much as these.
  static constexpr int kAdditive = 5;        // + -
  static constexpr int kMultiplicative = 6;  // * /

  // The binding strength of + - * /: kAdditive for expr/op.hpp's precedence 1 (the sums), one
  // more per level above; 0 for any other token.
  static int formula_precedence(const Token& t) {
    if (t.kind != Token::Symbol) return 0;
    const Op op = op_from_name(t.text);
    if (op == Op::Count_ || !op_info(op).infix) return 0;
    return kAdditive - 1 + shaderfit::precedence(op);
  }

  // Errors are located at `source`, at the token's line and column; `nesting` counts the levels
  // in progress (shared by the parsers of one text); `caret_is_power`: `^` is power().
  ExpressionGrammar(TokenStream tokens, const Syntax& syntax, const std::string& source,
                    int& nesting, bool caret_is_power)
      : tokens_(std::move(tokens)),
        syntax_(syntax),
        source_(source),
        nesting_(nesting),
        caret_is_power_(caret_is_power) {}
  virtual ~ExpressionGrammar() = default;
  ExpressionGrammar(const ExpressionGrammar&) = delete;
  ExpressionGrammar& operator=(const ExpressionGrammar&) = delete;

  // What parentheses and call arguments hold: binary(), and whatever the language adds.
  virtual Value expression() = 0;

  [[nodiscard]] const Token& peek(std::size_t ahead = 0) const { return tokens_.peek(ahead); }
  const Token& next() {
    const Token& t = tokens_.next();
    consumed(t);
    return t;
  }
  bool accept(std::string_view symbol) {
    if (!peek().is(symbol)) return false;
    next();
    return true;
  }
  void expect(std::string_view symbol, const std::string& what) {
    if (!accept(symbol)) {
      fail("expected '" + std::string(symbol) + "' " + what + ", found " + describe(peek()),
           peek());
    }
  }
  [[nodiscard]] std::size_t position() const { return tokens_.position(); }
  void seek(std::size_t position) { tokens_.seek(position); }
  [[nodiscard]] const Token& token_at(std::size_t position) const { return tokens_.at(position); }
  [[noreturn]] void fail(const std::string& message, const Token& at) const {
    throw Error(message, SourceLocation{source_, at.line, at.column});
  }
  [[nodiscard]] std::string describe(const Token& t) const {
    return shaderfit::describe(t, syntax_);
  }
  [[nodiscard]] const std::string& source() const { return source_; }

  // One more level of nesting for as long as it lives (kMaxFormulaNesting); an error at `at`
  // beyond.
  class Nest {
   public:
    Nest(const ExpressionGrammar& g, const Token& at) : nesting_(g.nesting_) {
      if (nesting_ >= kMaxFormulaNesting) g.fail(g.nesting_message(), at);
      ++nesting_;
    }
    ~Nest() { --nesting_; }
    Nest(const Nest&) = delete;
    Nest& operator=(const Nest&) = delete;

   private:
    int& nesting_;
  };

 protected:
  // --- hooks ---------------------------------------------------------------------------------
  // The binding strength of a binary operator; 0: not one.
  virtual int precedence(const Token& t) { return formula_precedence(t); }
  virtual Value binary_op(const Token& op, Value a, Value b) = 0;
  // A unary operator of the language's own before `-` and `+` are tried (the current token).
  virtual std::optional<Value> prefix() { return std::nullopt; }
  virtual Value negate(Value v) = 0;
  // A number literal, just read; `negative`: a '-' came right before it (then what follows is
  // the hook's to check_postfix(); primary() checks after the other operands).
  virtual Value literal(const Token& number, bool negative) = 0;
  // base ^ exponent, after the '^' (`caret`): reads the exponent.
  virtual Value power_of(Value base, const Token& caret) = 0;
  // A primary of the language's own, tried first (a C cast); nullopt: none here.
  virtual std::optional<Value> special_primary() { return std::nullopt; }
  // A name that is not called, just read.
  virtual Value name(const Token& name) = 0;
  // A call, the current token its '(' (arguments() reads them).
  virtual Value call(const Token& name) = 0;
  // After an operand (a name before it is resolved): what may not follow one is an error here.
  virtual void check_postfix() {}
  // An operand's postfix operators of the language's own (a shader's swizzles), then
  // check_postfix().
  virtual Value postfix(Value v) {
    check_postfix();
    return v;
  }
  // Every token read (for locating errors of what is emitted).
  virtual void consumed(const Token& /*t*/) {}
  virtual std::string nesting_message() const {
    return "formula nested more than " + std::to_string(kMaxFormulaNesting) +
           " levels deep (parentheses, calls and signs)";
  }

  // --- the grammar -----------------------------------------------------------------------------
  Value binary(int min_precedence = 1) {
    Value lhs = unary();
    while (true) {
      const Token& op = peek();
      const int p = precedence(op);
      if (p == 0 || p < min_precedence) return lhs;
      next();
      const Value rhs = binary(p + 1);
      lhs = binary_op(op, lhs, rhs);
    }
  }

  Value unary() {
    // Every nested operand passes through here: parentheses, call arguments and signs.
    const Nest nest(*this, peek());
    if (std::optional<Value> v = prefix()) return *v;
    if (accept("-")) {
      if (peek().kind == Token::Number && !peek(1).is("^")) {
        const Token& t = next();
        return literal(t, true);
      }
      return negate(unary());
    }
    if (accept("+")) return unary();
    return power();
  }

  Value power() {
    Value base = primary();
    if (!caret_is_power_) return base;
    while (peek().is("^")) {
      const Token& caret = next();
      base = power_of(base, caret);
    }
    return base;
  }

  Value primary() {
    if (std::optional<Value> v = special_primary()) return *v;
    const Token& t = peek();
    Value v;
    if (t.kind == Token::Number) {
      next();
      v = literal(t, false);
    } else if (t.is("(")) {
      next();
      if (peek().is(")")) fail("empty parentheses", t);
      v = expression();
      if (!peek().is(")")) {
        fail("expected ')' to close the '(' at " +
                 (peek().line == t.line ? "column " + std::to_string(t.column)
                                        : std::to_string(t.line) + ":" + std::to_string(t.column)) +
                 ", found " + describe(peek()),
             peek());
      }
      next();
    } else if (t.kind == Token::Ident) {
      next();
      if (peek().is("(")) {
        v = call(t);
      } else {
        check_postfix();  // a member or subscript of a name is the error, whatever the name is
        v = name(t);
      }
    } else {
      fail("unexpected " + describe(t) + ": an operand is missing", t);
    }
    return postfix(v);
  }

  // A call's arguments from its '(', each read by `argument(index)`, up to the ')', which is left
  // for the caller. Returns how many.
  template <class ReadArgument>
  int arguments(const Token& name, ReadArgument&& argument) {
    next();  // '('
    int count = 0;
    if (!peek().is(")")) {
      while (true) {
        argument(count);
        ++count;
        if (!accept(",")) break;
      }
    }
    if (!peek().is(")")) {
      fail("expected ',' or ')' in the arguments of " + std::string(name.text) + ", found " +
               describe(peek()),
           peek());
    }
    return count;
  }

 private:
  TokenStream tokens_;
  const Syntax& syntax_;
  const std::string& source_;
  int& nesting_;
  bool caret_is_power_;
};

}  // namespace shaderfit
