// Recursive-descent parser that emits postfix nodes as it goes: operands are parsed (and so
// emitted) before their operator, which is exactly postfix order.
#include "shaderfit/expr/parse.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <set>
#include <string>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

namespace {

struct Token {
  enum Kind { Number, Ident, Symbol, End } kind = End;
  std::string_view text;
  double number = 0.0;
  bool integral = false;  // the literal has no '.' and no exponent part
  int column = 1;         // 1-based
};

class Parser {
 public:
  Parser(std::string_view text, const ParseOptions& opts) : text_(text), opts_(opts) {
    expr_.variables = opts.variables;
    expr_.parameters = opts.parameters;
    expr_.parameter_values = opts.parameter_values;
    expr_.parameter_values.resize(expr_.parameters.size(), 0.0);
    advance();
  }

  Expression run() {
    if (tok_.kind == Token::End) fail("empty formula", tok_.column);
    parse_sum();
    if (tok_.kind != Token::End) fail("unexpected '" + std::string(tok_.text) + "'", tok_.column);
    if (opts_.literals_as_parameters) free_literals();
    expr_.update_lengths();
    return std::move(expr_);
  }

 private:
  [[noreturn]] void fail(const std::string& msg, int column) const {
    throw Error(msg, SourceLocation{opts_.source, opts_.line, column});
  }

  // --- lexer -------------------------------------------------------------------------------
  void advance() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    tok_ = Token{};
    tok_.column = static_cast<int>(pos_) + 1;
    if (pos_ >= text_.size()) {
      tok_.kind = Token::End;
      tok_.text = "end of formula";
      return;
    }
    const char c = text_[pos_];
    const std::size_t start = pos_;
    if (std::isdigit(static_cast<unsigned char>(c)) ||
        (c == '.' && pos_ + 1 < text_.size() &&
         std::isdigit(static_cast<unsigned char>(text_[pos_ + 1])))) {
      bool integral = true;
      while (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_]))) ++pos_;
      if (pos_ < text_.size() && text_[pos_] == '.') {
        integral = false;
        ++pos_;
        while (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_]))) ++pos_;
      }
      if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
        std::size_t p = pos_ + 1;
        if (p < text_.size() && (text_[p] == '+' || text_[p] == '-')) ++p;
        if (p < text_.size() && std::isdigit(static_cast<unsigned char>(text_[p]))) {
          integral = false;
          pos_ = p;
          while (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_])))
            ++pos_;
        } else {
          fail("malformed number: exponent has no digits", static_cast<int>(start) + 1);
        }
      }
      tok_.kind = Token::Number;
      tok_.text = text_.substr(start, pos_ - start);
      tok_.integral = integral;
      const char* b = text_.data() + start;
      const char* e = text_.data() + pos_;
      auto [ptr, ec] = std::from_chars(b, e, tok_.number);
      if (ec == std::errc::result_out_of_range) {
        fail("number out of range: '" + std::string(tok_.text) + "'", tok_.column);
      }
      if (ec != std::errc() || ptr != e) {
        fail("malformed number '" + std::string(tok_.text) + "'", tok_.column);
      }
      if (pos_ < text_.size() &&
          (std::isalpha(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_')) {
        fail("unexpected '" + std::string(1, text_[pos_]) + "' after the number " +
                 std::string(tok_.text),
             static_cast<int>(pos_) + 1);
      }
      return;
    }
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      while (pos_ < text_.size() &&
             (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_'))
        ++pos_;
      tok_.kind = Token::Ident;
      tok_.text = text_.substr(start, pos_ - start);
      return;
    }
    if (c == '<' || c == '>') {  // comparisons: < <= > >=
      pos_ += pos_ + 1 < text_.size() && text_[pos_ + 1] == '=' ? 2 : 1;
      tok_.kind = Token::Symbol;
      tok_.text = text_.substr(start, pos_ - start);
      return;
    }
    static constexpr std::string_view kSymbols = "+-*/^(),";
    if (kSymbols.find(c) != std::string_view::npos) {
      ++pos_;
      tok_.kind = Token::Symbol;
      tok_.text = text_.substr(start, 1);
      return;
    }
    const unsigned char uc = static_cast<unsigned char>(c);
    if (uc < 0x20 || uc >= 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "0x%02X", uc);
      fail(std::string("unexpected character ") + buf, tok_.column);
    }
    fail(std::string("unexpected character '") + c + "'", tok_.column);
  }

  bool is_symbol(char c) const { return tok_.kind == Token::Symbol && tok_.text[0] == c; }
  bool is_comparison() const { return is_symbol('<') || is_symbol('>'); }

  void expect(char c, const std::string& what) {
    if (!is_symbol(c)) {
      fail("expected '" + std::string(1, c) + "' " + what + ", found " + describe(tok_),
           tok_.column);
    }
    advance();
  }

  static std::string describe(const Token& t) {
    if (t.kind == Token::End) return "end of formula";
    return "'" + std::string(t.text) + "'";
  }

  // --- grammar -----------------------------------------------------------------------------
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
           tok_.column);
    }
    depths_.push_back(depth);
    expr_.nodes.push_back(n);
  }
  void drop_last_leaf() {
    depths_.pop_back();
    expr_.nodes.pop_back();
  }

  // A sum where a comparison may not follow: comparisons only appear in select's condition.
  void parse_sum() {
    parse_terms();
    if (is_comparison()) {
      fail("a comparison ('" + std::string(tok_.text) +
               "') is only allowed as the first argument of select",
           tok_.column);
    }
  }

  // sum := product (('+' | '-') product)*
  void parse_terms() {
    parse_product();
    while (is_symbol('+') || is_symbol('-')) {
      const Op op = is_symbol('+') ? Op::Add : Op::Sub;
      advance();
      parse_product();
      emit(Node::op_node(op));
    }
  }

  // product := unary (('*' | '/') unary)*
  void parse_product() {
    parse_unary();
    while (is_symbol('*') || is_symbol('/')) {
      const Op op = is_symbol('*') ? Op::Mul : Op::Div;
      advance();
      parse_unary();
      emit(Node::op_node(op));
    }
  }

  // unary := '-' unary | '+' unary | power; '-' right before a number literal that is not the
  // base of '^' makes a negative constant.
  void parse_unary() {
    // Every nested operand passes through here: parentheses, call arguments and signs.
    if (nesting_ >= kMaxFormulaNesting) {
      fail("formula nested more than " + std::to_string(kMaxFormulaNesting) +
               " levels deep (parentheses, calls and signs)",
           tok_.column);
    }
    ++nesting_;
    struct Leave {
      int& n;
      ~Leave() { --n; }
    } leave{nesting_};
    if (is_symbol('-')) {
      advance();
      if (tok_.kind == Token::Number && !next_is_caret()) {
        const double v = tok_.number;
        advance();
        emit(Node::constant(-v));
        return;
      }
      parse_unary();
      emit(Node::op_node(Op::Neg));
      return;
    }
    if (is_symbol('+')) {
      advance();
      parse_unary();
      return;
    }
    parse_power();
  }

  bool next_is_caret() const {
    std::size_t p = pos_;
    while (p < text_.size() && std::isspace(static_cast<unsigned char>(text_[p]))) ++p;
    return p < text_.size() && text_[p] == '^';
  }

  // power := primary ('^' integer)*   (left-associative: x^2^3 = (x^2)^3)
  void parse_power() {
    parse_primary();
    while (is_symbol('^')) {
      const int caret_col = tok_.column;
      advance();
      int sign = 1;
      int col = tok_.column;
      if (is_symbol('-') || is_symbol('+')) {
        sign = is_symbol('-') ? -1 : 1;
        advance();
      }
      if (tok_.kind != Token::Number || !tok_.integral) {
        fail(
            "the exponent after '^' must be an integer literal from -16 to 16 (use pow(a, b) or "
            "exp2 for others), found " +
                describe(tok_),
            tok_.kind == Token::End ? caret_col : tok_.column);
      }
      emit_ipow(sign * tok_.number, col);
      advance();
    }
  }

  void emit_ipow(double k, int column) {
    if (k < kMinIntegerPower || k > kMaxIntegerPower || k == 0 || k == 1) {
      fail("integer exponent " + format_int(k) + " is out of range (allowed: -16..-1 and 2..16)",
           column);
    }
    emit(Node::ipow(static_cast<int>(k)));
  }

  static std::string format_int(double k) {
    if (std::abs(k) < 1e15) return std::to_string(static_cast<long long>(k));
    return "beyond 1e15";
  }

  void parse_primary() {
    if (tok_.kind == Token::Number) {
      emit(Node::constant(tok_.number));
      advance();
      return;
    }
    if (is_symbol('(')) {
      const int col = tok_.column;
      advance();
      if (is_symbol(')')) fail("empty parentheses", col);
      parse_sum();
      if (!is_symbol(')')) {
        fail("expected ')' to close the '(' at column " + std::to_string(col) + ", found " +
                 describe(tok_),
             tok_.column);
      }
      advance();
      return;
    }
    if (tok_.kind == Token::Ident) {
      const Token name = tok_;
      advance();
      if (is_symbol('(')) {
        parse_call(name);
      } else {
        emit_name(name);
      }
      return;
    }
    if (tok_.kind == Token::End)
      fail("unexpected end of formula: an operand is missing", tok_.column);
    fail("unexpected " + describe(tok_) + ": an operand is missing", tok_.column);
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

  void parse_call(const Token& name) {
    const std::string s(name.text);
    Op op = op_from_name(s);
    if (s == "inversesqrt") op = Op::Rsqrt;  // GLSL spelling
    if (op == Op::Count_ || op_info(op).infix) fail("unknown function '" + s + "'", name.column);
    advance();  // '('
    if (op == Op::Select) {
      parse_select(name);
      return;
    }
    const int want = arity(op);
    int got = 0;
    std::size_t second_start = 0;
    std::size_t second_text_begin = 0;
    if (!is_symbol(')')) {
      while (true) {
        if (got == 1) {
          second_start = expr_.nodes.size();
          second_text_begin = static_cast<std::size_t>(tok_.column - 1);
        }
        parse_sum();
        ++got;
        if (is_symbol(',')) {
          advance();
          continue;
        }
        break;
      }
    }
    if (!is_symbol(')')) {
      fail("expected ',' or ')' in the arguments of " + s + ", found " + describe(tok_),
           tok_.column);
    }
    if (op == Op::Atan && got == 2) op = Op::Atan2;  // GLSL spelling: atan(y, x)
    if (got != arity(op)) {
      fail(s + " takes " + std::to_string(want) + (want == 1 ? " argument" : " arguments") +
               ", got " + std::to_string(got),
           name.column);
    }
    const std::size_t close = static_cast<std::size_t>(tok_.column - 1);
    advance();  // ')'
    // pow(a, k) with an integer literal k ("5", "-2"; not "5.0") in range is the integer power.
    if (op == Op::Pow && expr_.nodes.size() == second_start + 1 &&
        expr_.nodes.back().op == Op::Const &&
        is_integer_literal(text_.substr(second_text_begin, close - second_text_begin))) {
      const double k = expr_.nodes.back().value;
      if (k >= kMinIntegerPower && k <= kMaxIntegerPower && k != 0 && k != 1) {
        drop_last_leaf();
        emit(Node::ipow(static_cast<int>(k)));
        return;
      }
    }
    emit(Node::op_node(op));
  }

  // select(X cmp Y, b, c), after the '('. The condition becomes the one operand a of
  // select(a, b, c) = a >= 0 ? b : c: X >= Y is a = X - Y; X <= Y is a = Y - X; X > Y and X < Y
  // are the negations of Y >= X and X >= Y, so they take those differences with b and c swapped.
  // A literal zero on the right of the difference is dropped (a = P, not P - 0) and one on its
  // left makes a negation (a = -Q, not 0 - Q). (Differences agree with the comparisons except
  // where the difference is NaN: equal infinities, and NaN operands, where > and < take b.)
  void parse_select(const Token& name) {
    const std::size_t x_begin = expr_.nodes.size();
    const int x_column = tok_.column;
    if (is_symbol(')')) fail("select takes 3 arguments, got 0", name.column);
    parse_terms();
    if (!is_comparison()) {
      fail(
          "the first argument of select must be a comparison (X >= Y, X > Y, X <= Y or X < Y), "
          "found " +
              describe(tok_) + " after it",
          is_symbol(',') || is_symbol(')') ? x_column : tok_.column);
    }
    const std::string cmp(tok_.text);
    advance();
    const std::size_t y_begin = expr_.nodes.size();
    parse_sum();
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
    std::size_t b_begin = 0, c_begin = 0;
    for (std::size_t* begin : {&b_begin, &c_begin}) {
      if (!is_symbol(',')) {
        fail("expected ',' and two more arguments of select, found " + describe(tok_), tok_.column);
      }
      advance();
      *begin = expr_.nodes.size();
      parse_sum();
    }
    if (!is_symbol(')')) {
      fail("expected ')' after the 3 arguments of select, found " + describe(tok_), tok_.column);
    }
    advance();
    if (swap) swap_last_two(b_begin, c_begin);
    emit(Node::op_node(Op::Select));
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
  std::size_t pos_ = 0;
  Token tok_;
  Expression expr_;
  std::vector<std::size_t> exact_;   // the nodes of named constants (pi)
  std::vector<std::size_t> depths_;  // per subtree on the postfix stack: its depth
  int nesting_ = 0;                  // parse_unary calls in progress
};

}  // namespace

Expression parse_formula(std::string_view text, const ParseOptions& options) {
  return Parser(text, options).run();
}

}  // namespace shaderfit
