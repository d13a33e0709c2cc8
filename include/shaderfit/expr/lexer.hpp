// The one lexer of shaderfit's formula syntax and of the languages that extend it (the reference
// language's formulas and its GLSL/HLSL subset, reference/language.hpp): numbers, identifiers,
// the symbols a Syntax lists, and, where the Syntax asks for them, C's comments, preprocessor
// lines and integer literals. The grammar over these tokens is expr/grammar.hpp.
//
//   Lexer lexer("r0 + (1 - r0) * x^5", formula_syntax(), "formula");
//   Token t = lexer.next();  // Ident "r0" at 1:1
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace shaderfit {

struct Token {
  enum Kind : std::uint8_t { Number, Ident, Symbol, Directive, End };
  Kind kind = End;
  bool integral = false;  // a number written without '.', exponent or float suffix
  std::string_view text;  // Directive: the line after '#'
  double number = 0;
  int line = 1, column = 1;

  [[nodiscard]] bool is(std::string_view symbol) const { return kind == Symbol && text == symbol; }
  [[nodiscard]] bool is_word(std::string_view word) const { return kind == Ident && text == word; }
};

// What a language's text is made of, beyond numbers ([0-9]*.?[0-9]*([eE][+-]?[0-9]+)?) and
// identifiers ([A-Za-z_][A-Za-z0-9_]*).
struct Syntax {
  // The symbols, longest first where one begins another ("<=" before "<").
  std::span<const std::string_view> symbols;
  // Whether a newline starts a new line; false: the text is one line of its source, whose columns
  // count from the text's start whatever it holds.
  bool count_lines = true;
  // C's comments, a backslash before a newline joining the two lines, and preprocessor lines (a
  // '#' first on its line, to the line's end, a comment or a joined line continuing it) as
  // Directive tokens.
  bool c_comments = false;
  // C's hexadecimal (0x1F) and octal (017) integers and literal suffixes (f F h H lf LF u U).
  bool c_literals = false;
  // How messages name the End token.
  std::string_view end_name = "end of formula";
};

// The approximation's formulas (expr/parse.hpp): + - * / ^ ( ) , and the comparisons of select.
const Syntax& formula_syntax();

// "'x'", "'#define'", or the syntax's end_name for End.
std::string describe(const Token& t, const Syntax& syntax);

// Tokens one at a time, on demand; after the text, End for ever. `line` and `column` are the
// position of text[0]. Throws Error at the offending character for a malformed number, an
// unclosed comment or a character outside the syntax. The text, the syntax and the source must
// outlive the lexer and its tokens.
class Lexer {
 public:
  Lexer(std::string_view text, const Syntax& syntax, const std::string& source, int line = 1,
        int column = 1);

  Token next();
  // A preprocessor's skipped group, called after a Directive token: moves past the text, not
  // reading it as tokens, to the next line whose first token is a directive (which next() returns)
  // or to the end. The text may hold anything; a '#' in a comment does not start a line.
  void skip_to_directive();

 private:
  [[noreturn]] void fail(const std::string& message, int line, int column) const;
  void advance();
  void skip_blanks();
  void directive(Token& t);
  void skip_block_comment();
  void number(Token& t);
  void integer(Token& t, std::size_t start, int base, int column);
  void suffix(Token& t);
  void symbol(Token& t);

  std::string_view text_;
  const Syntax& syntax_;
  const std::string& source_;
  std::size_t pos_ = 0;
  int line_, column_;
  bool line_start_ = true;  // only blanks since the last newline: a '#' starts a directive
};

// Every token of `text`, ending with one End token (Lexer's errors, all at once).
std::vector<Token> tokenize(std::string_view text, const Syntax& syntax, const std::string& source,
                            int line = 1, int column = 1);

// A parser's view of tokens: a complete range (tokens of a whole file, shared by several parsers
// that seek in it), or a Lexer read only as far as the parser looks, so that its errors come in
// the order of the text. References to tokens stay valid for the stream's life.
class TokenStream {
 public:
  // `tokens` ends with the token a parse stops at (End, or ';' of a declaration).
  TokenStream(std::span<const Token> tokens, std::size_t position);
  explicit TokenStream(Lexer& lexer);

  // The token `ahead` after the current one; past the end, the last token.
  [[nodiscard]] const Token& peek(std::size_t ahead = 0) const;
  // The current token; moves past it unless it is the last.
  const Token& next();
  [[nodiscard]] std::size_t position() const { return pos_; }
  void seek(std::size_t position) { pos_ = position; }
  // The token at a position already read.
  [[nodiscard]] const Token& at(std::size_t position) const;

 private:
  std::span<const Token> tokens_;
  Lexer* lexer_ = nullptr;
  mutable std::deque<Token> read_;  // from lexer_
  std::size_t pos_ = 0;
};

}  // namespace shaderfit
