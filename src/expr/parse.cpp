// The approximation's parser: expr/grammar.hpp's grammar emitting postfix nodes as it goes
// (operands are parsed, and so emitted, before their operator, which is exactly postfix order).
#include "shaderfit/expr/parse.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <set>
#include <string>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/grammar.hpp"
#include "shaderfit/expr/lexer.hpp"

namespace shaderfit {

namespace {

// The lexer and the nesting count, made before the grammar that reads them.
struct ParserState {
  Lexer lexer;
  int nesting = 0;
};

// The grammar's values are the index of the subtree's first node.
class Parser : private ParserState, public ExpressionGrammar<std::size_t> {
 public:
  Parser(std::string_view text, const ParseOptions& opts)
      : ParserState{Lexer(text, formula_syntax(), opts.source, opts.line)},
        ExpressionGrammar(TokenStream(lexer), formula_syntax(), opts.source, nesting, true),
        text_(text),
        opts_(opts) {
    expr_.variables = opts.variables;
    expr_.parameters = opts.parameters;
    expr_.parameter_values = opts.parameter_values;
    expr_.parameter_values.resize(expr_.parameters.size(), 0.0);
  }

  Expression run() {
    if (peek().kind == Token::End) fail("empty formula", peek().column);
    expression();
    if (peek().is(":")) fail("unexpected ':' without a '?' before it", peek().column);
    if (peek().kind != Token::End)
      fail("unexpected '" + std::string(peek().text) + "'", peek().column);
    if (opts_.literals_as_parameters) free_literals();
    expr_.update_lengths();
    return std::move(expr_);
  }

  // A sum, or C's conditional X cmp Y ? b : c (the same as select(X cmp Y, b, c)); a comparison
  // appears only there and in select's condition.
  std::size_t expression() override {
    const std::size_t x_begin = expr_.nodes.size();
    const std::size_t v = binary();
    if (pending_ && pending_->begin >= x_begin) {
      // (X cmp Y) ? b : c: a parenthesized comparison is a condition where '?' follows it.
      const bool whole = pending_->begin == x_begin && pending_->end == expr_.nodes.size();
      if (whole && peek().is("?")) {
        const bool swap = pending_->swap;
        pending_.reset();
        return branches(x_begin, swap);
      }
      if (whole && peek().is(")")) return x_begin;  // parenthesized again: '?' may follow
      comparison_outside_a_condition(pending_->cmp, pending_->column, "");
    }
    if (is_comparison()) return conditional(x_begin);
    if (peek().is("?")) {
      fail("the condition before '?' must be a comparison (X >= Y, X > Y, X <= Y or X < Y)",
           peek().column);
    }
    return v;
  }

 private:
  using ExpressionGrammar::fail;
  [[noreturn]] void fail(const std::string& msg, int column) const {
    throw Error(msg, SourceLocation{opts_.source, opts_.line, column});
  }

  bool is_comparison() const {
    const Token& t = peek();
    return t.is("<") || t.is("<=") || t.is(">") || t.is(">=");
  }

  // Appends a node, tracking the depth of the subtree it closes (kMaxFormulaDepth).
  void emit(Node n) {
    std::size_t depth = 1;
    for (int i = 0; i < n.arity; ++i) {
      depth = std::max(depth, depths_.back() + 1);
      depths_.pop_back();
    }
    if (depth > static_cast<std::size_t>(kMaxFormulaDepth)) {
      fail("formula too deep: more than " + std::to_string(kMaxFormulaDepth) +
               " operations applied one to another",
           peek().column);
    }
    depths_.push_back(depth);
    expr_.nodes.push_back(n);
  }
  void drop_last_leaf() {
    depths_.pop_back();
    expr_.nodes.pop_back();
  }

  // --- the grammar's hooks -------------------------------------------------------------------
  std::size_t binary_op(const Token& op, std::size_t a, std::size_t /*b*/) override {
    emit(Node::op_node(op_from_name(op.text)));  // + - * /, the grammar's binary operators
    return a;
  }

  std::size_t negate(std::size_t v) override {
    emit(Node::op_node(Op::Neg));
    return v;
  }

  std::size_t literal(const Token& number, bool negative) override {
    emit(Node::constant(negative ? -number.number : number.number));
    return expr_.nodes.size() - 1;
  }

  std::size_t name(const Token& t) override {
    emit_name(t);
    return expr_.nodes.size() - 1;
  }

  // '^' takes an integer literal from -16 to 16 with at most one sign: x^4, x^-2; x^1 is x and
  // x^0 is 1, as a person may write them.
  std::size_t power_of(std::size_t base, const Token& caret) override {
    int sign = 1;
    const int col = peek().column;
    if (peek().is("-") || peek().is("+")) sign = next().is("-") ? -1 : 1;
    const Token& k = peek();
    if (k.kind != Token::Number || !k.integral) {
      fail(
          "the exponent after '^' must be an integer literal from -16 to 16 (use pow(a, b) or "
          "exp2 for others), found " +
              describe(k),
          k.kind == Token::End ? caret.column : k.column);
    }
    const double power = sign * k.number;
    if (power < kMinIntegerPower || power > kMaxIntegerPower)
      fail("integer exponent " + format_int(power) + " is out of range (allowed: -16..16)", col);
    next();
    if (power == 0) {  // the base's nodes give way to the constant
      expr_.nodes.resize(base);
      depths_.resize(depths_.size() - 1);
      emit(Node::constant(1.0));
    } else if (power != 1) {
      emit(Node::ipow(static_cast<int>(power)));
    }
    return base;
  }

  static std::string format_int(double k) {
    if (std::abs(k) < 1e15) return std::to_string(static_cast<long long>(k));
    return "beyond 1e15";
  }

  void emit_name(const Token& name) {
    const std::string s(name.text);
    auto find = [&](const std::vector<std::string>& v) {
      return static_cast<int>(std::find(v.begin(), v.end(), s) - v.begin());
    };
    if (int p = find(expr_.parameters); p < static_cast<int>(expr_.parameters.size())) {
      emit(Node::parameter(p));
      return;
    }
    int v = find(expr_.variables);
    if (v < static_cast<int>(expr_.variables.size())) {
      emit(Node::variable(v));
      return;
    }
    if (s == "pi") {
      exact_.push_back(expr_.nodes.size());
      emit(Node::constant(std::numbers::pi));
      return;
    }
    if (op_from_name(s) != Op::Count_) {
      fail("function '" + s + "' needs arguments in parentheses", name.column);
    }
    if (!opts_.variables.empty()) {
      std::string known;
      for (const auto& k : opts_.variables) known += (known.empty() ? "" : ", ") + k;
      fail("unknown variable '" + s + "' (known: " + known + ")", name.column);
    }
    if (expr_.variables.size() >= 32767) fail("too many variables", name.column);
    expr_.variables.push_back(s);
    emit(Node::variable(v));
  }

  std::size_t call(const Token& name) override {
    const std::size_t first = expr_.nodes.size();
    const std::string s(name.text);
    Op op = op_from_name(s);
    if (s == "inversesqrt") op = Op::Rsqrt;  // GLSL spelling
    if (op == Op::Count_ || op_info(op).infix) fail("unknown function '" + s + "'", name.column);
    if (op == Op::Select) {
      next();  // '('
      parse_select(name);
      return first;
    }
    const int want = arity(op);
    std::size_t second_start = 0;
    std::size_t second_text_begin = 0;
    const int got = arguments(name, [&](int index) {
      if (index == 1) {
        second_start = expr_.nodes.size();
        second_text_begin = static_cast<std::size_t>(peek().column - 1);
      }
      expression();
    });
    if (op == Op::Atan && got == 2) op = Op::Atan2;  // GLSL spelling: atan(y, x)
    if (got != arity(op)) {
      fail(s + " takes " + std::to_string(want) + (want == 1 ? " argument" : " arguments") +
               ", got " + std::to_string(got),
           name.column);
    }
    const std::size_t close = static_cast<std::size_t>(peek().column - 1);
    next();  // ')'
    // pow(a, k) with an integer literal k ("5", "-2"; not "5.0") in range is the integer power.
    if (op == Op::Pow && expr_.nodes.size() == second_start + 1 &&
        expr_.nodes.back().op == Op::Const &&
        is_integer_literal(text_.substr(second_text_begin, close - second_text_begin))) {
      const double k = expr_.nodes.back().value;
      if (k >= kMinIntegerPower && k <= kMaxIntegerPower && k != 0 && k != 1) {
        drop_last_leaf();
        emit(Node::ipow(static_cast<int>(k)));
        return first;
      }
    }
    emit(Node::op_node(op));
    return first;
  }

  // select(X cmp Y, b, c), after the '('. The condition becomes the one operand a of
  // select(a, b, c) = a >= 0 ? b : c: X >= Y is a = X - Y; X <= Y is a = Y - X; X > Y and X < Y
  // are the negations of Y >= X and X >= Y, so they take those differences with b and c swapped.
  // A literal zero on the right of the difference is dropped (a = P, not P - 0) and one on its
  // left makes a negation (a = -Q, not 0 - Q). (Differences agree with the comparisons except
  // where the difference is NaN: equal infinities, and NaN operands, where > and < take b.)
  void parse_select(const Token& name) {
    const std::size_t x_begin = expr_.nodes.size();
    const int x_column = peek().column;
    if (peek().is(")")) fail("select takes 3 arguments, got 0", name.column);
    binary();
    bool swap = false;
    if (pending_ && pending_->begin == x_begin && pending_->end == expr_.nodes.size()) {
      swap = pending_->swap;  // select((X cmp Y), b, c)
      pending_.reset();
    } else {
      if (pending_ && pending_->begin >= x_begin)  // select((X cmp Y) + 1, ...)
        comparison_outside_a_condition(pending_->cmp, pending_->column, "");
      if (!is_comparison()) {
        fail(
            "the first argument of select must be a comparison (X >= Y, X > Y, X <= Y or X < Y), "
            "found " +
                describe(peek()) + " after it",
            peek().is(",") || peek().is(")") ? x_column : peek().column);
      }
      const std::string cmp(next().text);
      const std::size_t y_begin = expr_.nodes.size();
      expression();
      swap = condition(x_begin, y_begin, cmp);
    }
    std::size_t b_begin = 0, c_begin = 0;
    for (std::size_t* begin : {&b_begin, &c_begin}) {
      if (!peek().is(",")) {
        fail("expected ',' and two more arguments of select, found " + describe(peek()),
             peek().column);
      }
      next();
      *begin = expr_.nodes.size();
      expression();
    }
    if (!peek().is(")")) {
      fail("expected ')' after the 3 arguments of select, found " + describe(peek()),
           peek().column);
    }
    next();
    if (swap) swap_last_two(b_begin, c_begin);
    emit(Node::op_node(Op::Select));
  }

  // X cmp Y ? b : c, after X (which begins at node x_begin); the branches are expressions, so
  // that b ? c : d nests to the right as in C.
  std::size_t conditional(std::size_t x_begin) {
    const int cmp_column = peek().column;
    const std::string cmp(next().text);
    const std::size_t y_begin = expr_.nodes.size();
    binary();
    if (is_comparison()) fail("comparisons do not chain: expected '?'", peek().column);
    if (!peek().is("?")) {
      if (peek().is(")") && nesting > 0) {  // (X cmp Y): the '?' may follow the ')'
        pending_ = PendingCondition{x_begin, 0, condition(x_begin, y_begin, cmp), cmp_column, cmp};
        pending_->end = expr_.nodes.size();
        return x_begin;
      }
      comparison_outside_a_condition(cmp, cmp_column, describe(peek()));
    }
    return branches(x_begin, condition(x_begin, y_begin, cmp));
  }

  // `found`: what stands where the '?' would be, or empty where that is not the point.
  [[noreturn]] void comparison_outside_a_condition(const std::string& cmp, int column,
                                                   const std::string& found) const {
    fail("a comparison ('" + cmp + "') is only allowed in a condition: select(X " + cmp +
             " Y, b, c) or X " + cmp + " Y ? b : c" +
             (found.empty() ? std::string() : " (found " + found + " where '?' would be)"),
         column);
  }

  // '? b : c' of a condition whose difference begins at node x_begin; emits the select.
  std::size_t branches(std::size_t x_begin, bool swap) {
    const Token question = next();
    const Nest nest(*this, question);
    const std::size_t b_begin = expr_.nodes.size();
    expression();
    if (!peek().is(":")) {
      fail("expected ':' after the first branch of '?' at column " +
               std::to_string(question.column) + ", found " + describe(peek()),
           peek().column);
    }
    next();
    const std::size_t c_begin = expr_.nodes.size();
    expression();
    if (swap) swap_last_two(b_begin, c_begin);
    emit(Node::op_node(Op::Select));
    return x_begin;
  }

  // A parenthesized comparison waiting for the '?' after its ')': its difference, emitted as
  // nodes [begin, end), and whether the branches swap (condition).
  struct PendingCondition {
    std::size_t begin = 0, end = 0;
    bool swap = false;
    int column = 0;
    std::string cmp;
  };
  std::optional<PendingCondition> pending_;

  // The condition X cmp Y, its two sides parsed (beginning at nodes x_begin and y_begin), as the
  // operand a of select(a, b, c): returns whether b and c are to be swapped.
  bool condition(std::size_t x_begin, std::size_t y_begin, const std::string& cmp) {
    // The condition as P >= Q, negated when `swap`.
    const bool y_first = cmp == "<=" || cmp == ">";
    const bool swap = cmp == ">" || cmp == "<";
    const std::size_t end = expr_.nodes.size();
    if (y_first) swap_last_two(x_begin, y_begin);
    const std::size_t q_begin = y_first ? x_begin + (end - y_begin) : y_begin;
    if (q_begin + 1 == end && is_zero_leaf(q_begin)) {
      drop_last_leaf();
    } else if (is_zero_leaf(x_begin) && q_begin == x_begin + 1) {
      drop_node(x_begin);
      emit(Node::op_node(Op::Neg));
    } else {
      emit(Node::op_node(Op::Sub));
    }
    return swap;
  }

  bool is_zero_leaf(std::size_t i) const {
    const Node& n = expr_.nodes[i];
    return n.op == Op::Const && n.value == 0.0 &&
           std::find(exact_.begin(), exact_.end(), i) == exact_.end();
  }

  // Swaps the last two subtrees on the postfix stack, which begin at nodes `first` and `second`.
  void swap_last_two(std::size_t first, std::size_t second) {
    const std::size_t end = expr_.nodes.size();
    std::rotate(expr_.nodes.begin() + static_cast<std::ptrdiff_t>(first),
                expr_.nodes.begin() + static_cast<std::ptrdiff_t>(second), expr_.nodes.end());
    for (std::size_t& i : exact_) {
      if (i >= second)
        i -= second - first;
      else if (i >= first)
        i += end - second;
    }
    std::swap(depths_[depths_.size() - 1], depths_[depths_.size() - 2]);
  }

  // Removes the leaf at node i, the second subtree from the top of the postfix stack.
  void drop_node(std::size_t i) {
    expr_.nodes.erase(expr_.nodes.begin() + static_cast<std::ptrdiff_t>(i));
    for (std::size_t& k : exact_)
      if (k > i) --k;
    depths_.erase(depths_.end() - 2);
  }

  // ParseOptions::literals_as_parameters: every Const leaf but the named constants becomes a
  // new parameter, named p0, p1, ... (skipping names already taken), starting at its value.
  void free_literals() {
    std::vector<char> exact(expr_.nodes.size(), 0);
    for (std::size_t i : exact_) exact[i] = 1;
    std::set<std::string> taken(expr_.variables.begin(), expr_.variables.end());
    taken.insert(expr_.parameters.begin(), expr_.parameters.end());
    std::size_t next = 0;
    for (std::size_t i = 0; i < expr_.nodes.size(); ++i) {
      Node& n = expr_.nodes[i];
      if (n.op != Op::Const || exact[i] != 0) continue;
      if (expr_.parameters.size() >= 32767) fail("too many number literals", 1);
      std::string name;
      do {
        name = "p" + std::to_string(next++);
      } while (taken.count(name) != 0);
      expr_.parameters.push_back(name);
      expr_.parameter_values.push_back(n.value);
      n = Node::parameter(static_cast<int>(expr_.parameters.size() - 1));
    }
  }

  static bool is_integer_literal(std::string_view t) {
    while (!t.empty() && std::isspace(static_cast<unsigned char>(t.front()))) t.remove_prefix(1);
    while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back()))) t.remove_suffix(1);
    if (!t.empty() && (t.front() == '-' || t.front() == '+')) t.remove_prefix(1);
    return !t.empty() &&
           std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; });
  }

  std::string_view text_;
  const ParseOptions& opts_;
  Expression expr_;
  std::vector<std::size_t> exact_;   // the nodes of named constants (pi)
  std::vector<std::size_t> depths_;  // per subtree on the postfix stack: its depth
};

}  // namespace

Expression parse_formula(std::string_view text, const ParseOptions& options) {
  return Parser(text, options).run();
}

}  // namespace shaderfit
