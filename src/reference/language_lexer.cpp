// Tokens of the reference language: formulas as expr/parse.hpp reads them, and shader sources
// (comments, literal suffixes, hexadecimal and octal integers, preprocessor lines).
#include <cctype>
#include <charconv>
#include <cstdio>

#include "language_internal.hpp"

namespace shaderfit::reference::detail {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_'; }
bool is_ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; }

// Longest first, so that "<=" is one token and "<" another.
constexpr std::string_view kFormulaSymbols[] = {"<=", ">=", "==", "!=", "&&", "||", "+",
                                                "-",  "*",  "/",  "^",  "(",  ")",  ",",
                                                "<",  ">",  "!",  "?",  ":",  "="};
constexpr std::string_view kShaderSymbols[] = {
    "<<=", ">>=", "<=", ">=", "==", "!=", "&&", "||", "++", "--", "+=", "-=",
    "*=",  "/=",  "%=", "&=", "|=", "^=", "<<", ">>", "->", "::", "+",  "-",
    "*",   "/",   "%",  "^",  "&",  "|",  "~",  "(",  ")",  "[",  "]",  "{",
    "}",   ",",   ";",  ".",  "<",  ">",  "!",  "?",  ":",  "="};

class Lexer {
 public:
  Lexer(std::string_view text, Dialect dialect, const std::string& source, int line, int column)
      : text_(text), dialect_(dialect), source_(source), line_(line), column_(column) {}

  std::vector<Token> run() {
    std::vector<Token> out;
    bool line_start = true;  // only blanks since the last newline: a '#' starts a directive
    while (true) {
      line_start = skip_blanks(line_start);
      Token t;
      t.line = line_;
      t.column = column_;
      if (pos_ >= text_.size()) {
        t.kind = Token::End;
        out.push_back(t);
        return out;
      }
      const char c = text_[pos_];
      if (dialect_ == Dialect::Shader && c == '#' && line_start) {
        directive(t);
      } else if (is_digit(c) ||
                 (c == '.' && pos_ + 1 < text_.size() && is_digit(text_[pos_ + 1]))) {
        number(t);
      } else if (is_ident_start(c)) {
        const std::size_t start = pos_;
        while (pos_ < text_.size() && is_ident_char(text_[pos_])) advance();
        t.kind = Token::Ident;
        t.text = text_.substr(start, pos_ - start);
      } else {
        symbol(t);
      }
      line_start = false;
      out.push_back(t);
    }
  }

 private:
  [[noreturn]] void fail(const std::string& message, int line, int column) const {
    throw Error(message, SourceLocation{source_, line, column});
  }

  void advance() {
    if (text_[pos_] == '\n') {
      ++line_;
      column_ = 1;
    } else {
      ++column_;
    }
    ++pos_;
  }

  // Skips blanks and (shader) comments; returns whether the next token starts its line.
  bool skip_blanks(bool line_start) {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        line_start = true;
        advance();
      } else if (std::isspace(static_cast<unsigned char>(c)) != 0) {
        advance();
      } else if (dialect_ == Dialect::Shader && c == '/' && pos_ + 1 < text_.size() &&
                 text_[pos_ + 1] == '/') {
        while (pos_ < text_.size() && text_[pos_] != '\n') advance();
      } else if (dialect_ == Dialect::Shader && c == '/' && pos_ + 1 < text_.size() &&
                 text_[pos_ + 1] == '*') {
        const int line = line_, column = column_;
        advance();
        advance();
        while (pos_ + 1 < text_.size() && !(text_[pos_] == '*' && text_[pos_ + 1] == '/'))
          advance();
        if (pos_ + 1 >= text_.size()) fail("comment not closed: '*/' is missing", line, column);
        advance();
        advance();
      } else {
        break;
      }
    }
    return line_start;
  }

  // '#' to the end of the line (a backslash before the newline continues it); the token's text
  // is what follows '#'.
  void directive(Token& t) {
    advance();  // '#'
    const std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') {
      if (text_[pos_] == '\\' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '\n') advance();
      advance();
    }
    t.kind = Token::Directive;
    t.text = text_.substr(start, pos_ - start);
  }

  void number(Token& t) {
    const std::size_t start = pos_;
    const int column = column_;
    t.kind = Token::Number;
    t.integral = true;
    if (dialect_ == Dialect::Shader && text_[pos_] == '0' && pos_ + 1 < text_.size() &&
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
    if (dialect_ == Dialect::Shader && t.integral && t.text.size() > 1 && t.text[0] == '0') {
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
    if (dialect_ == Dialect::Shader) suffix(t);
    if (pos_ < text_.size() && is_ident_char(text_[pos_])) {
      fail("unexpected '" + std::string(1, text_[pos_]) + "' after the number " +
               std::string(t.text),
           line_, column_);
    }
    t.text = text_.substr(start, pos_ - start);
  }

  // Digits in `base` from pos_, then a u/U suffix.
  void integer(Token& t, std::size_t start, int base, int column) {
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

  // Shader literal suffixes: f F h H lf LF (a float), u U (an unsigned integer).
  void suffix(Token& t) {
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

  void symbol(Token& t) {
    const std::span<const std::string_view> symbols =
        dialect_ == Dialect::Formula ? std::span<const std::string_view>(kFormulaSymbols)
                                     : std::span<const std::string_view>(kShaderSymbols);
    const std::string_view rest = text_.substr(pos_);
    for (const std::string_view s : symbols) {
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

  std::string_view text_;
  Dialect dialect_;
  const std::string& source_;
  std::size_t pos_ = 0;
  int line_, column_;
};

}  // namespace

std::string describe(const Token& t, Dialect dialect) {
  if (t.kind == Token::End) return dialect == Dialect::Formula ? "end of formula" : "end of file";
  if (t.kind == Token::Directive) return "'#" + std::string(t.text) + "'";
  return "'" + std::string(t.text) + "'";
}

std::vector<Token> tokenize(std::string_view text, Dialect dialect, const std::string& source,
                            int line, int column) {
  return Lexer(text, dialect, source, line, column).run();
}

void fail_at(const std::string& message, const std::string& source, const Token& at) {
  throw Error(message, SourceLocation{source, at.line, at.column});
}

}  // namespace shaderfit::reference::detail
