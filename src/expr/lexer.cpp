// The one lexer (expr/lexer.hpp): formulas, and with a Syntax's C options, shader sources.
#include "shaderfit/expr/lexer.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_'; }
bool is_ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; }

// The length of a backslash-newline (C's line splice, "\\\n" or "\\\r\n") at text[pos], or 0.
std::size_t splice_length(std::string_view text, std::size_t pos) {
  if (text[pos] != '\\') return 0;
  if (pos + 1 < text.size() && text[pos + 1] == '\n') return 2;
  if (pos + 2 < text.size() && text[pos + 1] == '\r' && text[pos + 2] == '\n') return 3;
  return 0;
}

// Longest first, so that "<=" is one token and "<" another.
constexpr std::string_view kFormulaSymbols[] = {"<=", ">=", "+", "-", "*", "/", "^",
                                                "(",  ")",  ",", "<", ">", "?", ":"};

}  // namespace

const Syntax& formula_syntax() {
  static const Syntax syntax{kFormulaSymbols, /*count_lines=*/false};
  return syntax;
}

std::string describe(const Token& t, const Syntax& syntax) {
  if (t.kind == Token::End) return std::string(syntax.end_name);
  if (t.kind == Token::Directive) return "'#" + std::string(t.text) + "'";
  return "'" + std::string(t.text) + "'";
}

Lexer::Lexer(std::string_view text, const Syntax& syntax, const std::string& source, int line,
             int column)
    : text_(text), syntax_(syntax), source_(source), line_(line), column_(column) {}

Token Lexer::next() {
  skip_blanks();
  Token t;
  t.line = line_;
  t.column = column_;
  if (pos_ >= text_.size()) {
    t.kind = Token::End;
    return t;
  }
  const char c = text_[pos_];
  if (syntax_.c_comments && c == '#' && line_start_) {
    directive(t);
  } else if (is_digit(c) || (c == '.' && pos_ + 1 < text_.size() && is_digit(text_[pos_ + 1]))) {
    number(t);
  } else if (is_ident_start(c)) {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && is_ident_char(text_[pos_])) advance();
    t.kind = Token::Ident;
    t.text = text_.substr(start, pos_ - start);
  } else {
    symbol(t);
  }
  line_start_ = false;
  return t;
}

void Lexer::fail(const std::string& message, int line, int column) const {
  throw Error(message, SourceLocation{source_, line, column});
}

void Lexer::advance() {
  if (text_[pos_] == '\n' && syntax_.count_lines) {
    ++line_;
    column_ = 1;
  } else {
    ++column_;
  }
  ++pos_;
}

// Skips blanks and comments, noting whether the next token starts its line.
void Lexer::skip_blanks() {
  while (pos_ < text_.size()) {
    const char c = text_[pos_];
    if (c == '\n') {
      line_start_ = true;
      advance();
    } else if (const std::size_t n = syntax_.c_comments ? splice_length(text_, pos_) : 0; n != 0) {
      for (std::size_t k = 0; k < n; ++k) advance();  // the next line continues this one
    } else if (std::isspace(static_cast<unsigned char>(c)) != 0) {
      advance();
    } else if (syntax_.c_comments && c == '/' && pos_ + 1 < text_.size() &&
               text_[pos_ + 1] == '/') {
      while (pos_ < text_.size() && text_[pos_] != '\n') advance();
    } else if (syntax_.c_comments && c == '/' && pos_ + 1 < text_.size() &&
               text_[pos_ + 1] == '*') {
      const int line = line_, column = column_;
      advance();
      advance();
      while (pos_ + 1 < text_.size() && !(text_[pos_] == '*' && text_[pos_ + 1] == '/')) advance();
      if (pos_ + 1 >= text_.size()) fail("comment not closed: '*/' is missing", line, column);
      advance();
      advance();
    } else {
      break;
    }
  }
}

// '#' to the end of the line (a backslash before the newline, or a comment that goes on to the next
// line, continues it); the token's text is what follows '#', comments included.
void Lexer::directive(Token& t) {
  advance();  // '#'
  const std::size_t start = pos_;
  while (pos_ < text_.size() && text_[pos_] != '\n') {
    const bool more = pos_ + 1 < text_.size();
    if (more && text_[pos_] == '/' && text_[pos_ + 1] == '/') {
      while (pos_ < text_.size() && text_[pos_] != '\n') advance();
    } else if (more && text_[pos_] == '/' && text_[pos_ + 1] == '*') {
      skip_block_comment();  // unclosed: reading the line's tokens reports it
    } else {
      for (std::size_t k = std::max<std::size_t>(splice_length(text_, pos_), 1); k > 0; --k)
        advance();
    }
  }
  t.kind = Token::Directive;
  t.text = text_.substr(start, pos_ - start);
}

// From "/*" past its "*/", or to the end when it has none.
void Lexer::skip_block_comment() {
  advance();
  advance();
  while (pos_ < text_.size() &&
         !(text_[pos_] == '*' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/'))
    advance();
  for (int k = 0; k < 2 && pos_ < text_.size(); ++k) advance();
}

void Lexer::skip_to_directive() {
  bool line_start = false;  // the caller has just read a directive: its newline is ahead
  while (pos_ < text_.size()) {
    const char c = text_[pos_];
    const bool more = pos_ + 1 < text_.size();
    if (c == '\n') {
      line_start = true;
      advance();
    } else if (c == '#' && line_start) {
      break;
    } else if (const std::size_t n = splice_length(text_, pos_); n != 0) {
      for (std::size_t k = 0; k < n; ++k) advance();
    } else if (more && c == '/' && text_[pos_ + 1] == '/') {
      while (pos_ < text_.size() && text_[pos_] != '\n') advance();
    } else if (more && c == '/' && text_[pos_ + 1] == '*') {
      skip_block_comment();
    } else {
      if (std::isspace(static_cast<unsigned char>(c)) == 0) line_start = false;
      advance();
    }
  }
  line_start_ = true;
}

void Lexer::number(Token& t) {
  const std::size_t start = pos_;
  const int column = column_;
  t.kind = Token::Number;
  t.integral = true;
  if (syntax_.c_literals && text_[pos_] == '0' && pos_ + 1 < text_.size() &&
      (text_[pos_ + 1] == 'x' || text_[pos_ + 1] == 'X')) {
    advance();
    advance();
    integer(t, start, 16, column);
    return;
  }
  while (pos_ < text_.size() && is_digit(text_[pos_])) advance();
  if (pos_ < text_.size() && text_[pos_] == '.') {
    t.integral = false;
    advance();
    while (pos_ < text_.size() && is_digit(text_[pos_])) advance();
  }
  if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
    std::size_t p = pos_ + 1;
    if (p < text_.size() && (text_[p] == '+' || text_[p] == '-')) ++p;
    if (p < text_.size() && is_digit(text_[p])) {
      t.integral = false;
      while (pos_ < p) advance();
      while (pos_ < text_.size() && is_digit(text_[pos_])) advance();
    } else {
      fail("malformed number: exponent has no digits", line_, column);
    }
  }
  const std::size_t digits_end = pos_;
  t.text = text_.substr(start, digits_end - start);
  if (syntax_.c_literals && t.integral && t.text.size() > 1 && t.text[0] == '0') {
    pos_ = start;  // GLSL and HLSL read a leading zero as octal
    column_ = column;
    integer(t, start, 8, column);
    return;
  }
  const char* b = text_.data() + start;
  const char* e = text_.data() + digits_end;
  const auto [ptr, ec] = std::from_chars(b, e, t.number);
  if (ec == std::errc::result_out_of_range)
    fail("number out of range: '" + std::string(t.text) + "'", line_, column);
  if (ec != std::errc() || ptr != e)
    fail("malformed number '" + std::string(t.text) + "'", line_, column);
  if (syntax_.c_literals) suffix(t);
  if (pos_ < text_.size() && is_ident_char(text_[pos_])) {
    fail("unexpected '" + std::string(1, text_[pos_]) + "' after the number " + std::string(t.text),
         line_, column_);
  }
  t.text = text_.substr(start, pos_ - start);
}

// Digits in `base` from pos_, then a u/U suffix.
void Lexer::integer(Token& t, std::size_t start, int base, int column) {
  const std::size_t digits = pos_;
  while (pos_ < text_.size() && std::isxdigit(static_cast<unsigned char>(text_[pos_])) != 0 &&
         (base == 16 || is_digit(text_[pos_])))
    advance();
  unsigned long long v = 0;
  const auto [ptr, ec] = std::from_chars(text_.data() + digits, text_.data() + pos_, v, base);
  if (ec != std::errc() || ptr != text_.data() + pos_) {
    fail("malformed integer '" + std::string(text_.substr(start, pos_ - start)) + "'", line_,
         column);
  }
  t.number = static_cast<double>(v);
  t.integral = true;
  if (pos_ < text_.size() && (text_[pos_] == 'u' || text_[pos_] == 'U')) advance();
  if (pos_ < text_.size() && is_ident_char(text_[pos_])) {
    fail("unexpected '" + std::string(1, text_[pos_]) + "' after the number " +
             std::string(text_.substr(start, pos_ - start)),
         line_, column_);
  }
  t.text = text_.substr(start, pos_ - start);
}

// Literal suffixes: f F h H lf LF (a float), u U (an unsigned integer).
void Lexer::suffix(Token& t) {
  if (pos_ >= text_.size()) return;
  const char c = text_[pos_];
  if (c == 'f' || c == 'F' || c == 'h' || c == 'H') {
    advance();
    t.integral = false;
  } else if ((c == 'l' || c == 'L') && pos_ + 1 < text_.size() &&
             (text_[pos_ + 1] == 'f' || text_[pos_ + 1] == 'F')) {
    advance();
    advance();
    t.integral = false;
  } else if ((c == 'u' || c == 'U') && t.integral) {
    advance();
  }
}

void Lexer::symbol(Token& t) {
  const std::string_view rest = text_.substr(pos_);
  for (const std::string_view s : syntax_.symbols) {
    if (rest.substr(0, s.size()) == s) {
      t.kind = Token::Symbol;
      t.text = rest.substr(0, s.size());
      for (std::size_t i = 0; i < s.size(); ++i) advance();
      return;
    }
  }
  const unsigned char uc = static_cast<unsigned char>(text_[pos_]);
  if (uc < 0x20 || uc >= 0x7f) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "0x%02X", uc);
    fail(std::string("unexpected character ") + buf, line_, column_);
  }
  fail(std::string("unexpected character '") + text_[pos_] + "'", line_, column_);
}

std::vector<Token> tokenize(std::string_view text, const Syntax& syntax, const std::string& source,
                            int line, int column) {
  Lexer lexer(text, syntax, source, line, column);
  std::vector<Token> out;
  do {
    out.push_back(lexer.next());
  } while (out.back().kind != Token::End);
  return out;
}

TokenStream::TokenStream(std::span<const Token> tokens, std::size_t position)
    : tokens_(tokens), pos_(position) {}

TokenStream::TokenStream(Lexer& lexer) : lexer_(&lexer) {}

const Token& TokenStream::peek(std::size_t ahead) const {
  const std::size_t i = pos_ + ahead;
  if (lexer_ == nullptr) return i < tokens_.size() ? tokens_[i] : tokens_.back();
  while (read_.size() <= i && (read_.empty() || read_.back().kind != Token::End))
    read_.push_back(lexer_->next());
  return i < read_.size() ? read_[i] : read_.back();
}

const Token& TokenStream::next() {
  const Token& t = peek();
  const bool last = lexer_ == nullptr ? pos_ + 1 >= tokens_.size() : t.kind == Token::End;
  if (!last) ++pos_;
  return t;
}

const Token& TokenStream::at(std::size_t position) const {
  return lexer_ == nullptr ? tokens_[position] : read_[position];
}

}  // namespace shaderfit
