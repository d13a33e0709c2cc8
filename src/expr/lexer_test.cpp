#include "shaderfit/expr/lexer.hpp"

#include <gtest/gtest.h>

#include <string>

#include "shaderfit/core/error.hpp"

namespace shaderfit {
namespace {

constexpr std::string_view kCSymbols[] = {"<=", "+", "-", "(", ")", ";", "<"};
const Syntax kC{kCSymbols, true, true, true, "end of file"};

TEST(Lexer, FormulaTokensAndColumnsFromTheTextStart) {
  const std::string source = "formula";
  const std::vector<Token> t = tokenize("x <=\n 2.5e1", formula_syntax(), source, 4);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_TRUE(t[0].is_word("x"));
  EXPECT_TRUE(t[1].is("<="));
  EXPECT_EQ(t[2].kind, Token::Number);
  EXPECT_EQ(t[2].number, 25.0);
  EXPECT_FALSE(t[2].integral);
  // A formula is one line of its source: the newline does not start another.
  EXPECT_EQ(t[2].line, 4);
  EXPECT_EQ(t[2].column, 7);
  EXPECT_EQ(t[3].kind, Token::End);
  EXPECT_EQ(describe(t[3], formula_syntax()), "end of formula");
}

TEST(Lexer, CSyntaxCountsLinesAndReadsCommentsLiteralsAndDirectives) {
  const std::string source = "a.glsl";
  const std::vector<Token> t =
      tokenize("#define K 1\n/* c */ 0x1F 017 1.5f // end\n  2u", kC, source);
  ASSERT_EQ(t.size(), 6u);
  EXPECT_EQ(t[0].kind, Token::Directive);
  EXPECT_EQ(t[0].text, "define K 1");
  EXPECT_EQ(t[1].number, 31.0);
  EXPECT_EQ(t[2].number, 15.0);
  EXPECT_FALSE(t[3].integral);
  EXPECT_EQ(t[3].text, "1.5f");
  EXPECT_EQ(t[4].line, 3);
  EXPECT_EQ(t[4].column, 3);
  EXPECT_TRUE(t[4].integral);
  EXPECT_EQ(describe(t[5], kC), "end of file");
}

TEST(Lexer, ErrorsAreLocated) {
  const std::string source = "f";
  try {
    tokenize("x +\n  $", kC, source);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "f:2:3: unexpected character '$'");
  }
  EXPECT_THROW(tokenize("1e+", formula_syntax(), source), Error);
  EXPECT_THROW(tokenize("/* open", kC, source), Error);
  EXPECT_THROW(tokenize("0x1F", formula_syntax(), source), Error);  // 'x' after the number 0
}

// A stream over a lexer reads no further than it is asked to, so that errors come in the text's
// order.
TEST(TokenStream, ReadsTheLexerOnDemand) {
  const std::string source = "formula";
  Lexer lexer("x + $", formula_syntax(), source);
  TokenStream s(lexer);
  EXPECT_TRUE(s.next().is_word("x"));
  EXPECT_TRUE(s.peek().is("+"));
  EXPECT_THROW((void)s.peek(1), Error);
}

TEST(TokenStream, StopsAtTheLastTokenOfARange) {
  const std::string source = "f";
  const std::vector<Token> t = tokenize("a ;", kC, source);
  TokenStream s(std::span<const Token>(t).first(2), 0);
  EXPECT_TRUE(s.next().is_word("a"));
  EXPECT_TRUE(s.next().is(";"));
  EXPECT_TRUE(s.next().is(";"));
  EXPECT_EQ(s.position(), 1u);
}

}  // namespace
}  // namespace shaderfit
