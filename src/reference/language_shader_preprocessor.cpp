// The shader preprocessor (language_shader_preprocessor.hpp): one pass over the lexer's tokens,
// each directive acted on where it stands, macros expanded where they are used.
#include "language_shader_preprocessor.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <map>
#include <utility>

namespace shaderfit::reference_detail {

namespace {

// Macro calls inside each other's arguments or expansions, and parentheses and signs in #if.
constexpr int kMaxMacroNesting = 256;
// Tokens all expansions of a source may make (a macro whose expansion doubles at every level
// stops here).
constexpr std::size_t kMaxMacroTokens = std::size_t{1} << 18;

struct Macro {
  Token name;  // in its #define
  bool function_like = false;
  std::vector<std::string_view> parameters;
  std::vector<Token> body;     // the replacement, without an End
  std::optional<Error> error;  // why the definition cannot be read, raised where it is expanded
};

using Macros = std::map<std::string, Macro, std::less<>>;

struct Conditional {
  Token at;                // its #if, #ifdef or #ifndef
  std::string word;        // "if", "ifdef" or "ifndef"
  bool taken = false;      // one of its groups is read
  bool seen_else = false;  // its #else has come
};

// A directive's name ("define", "if", ...; "" for none) and where its operands start in t.text.
std::pair<std::string_view, std::size_t> directive_word(const Token& t) {
  const std::string_view text = t.text;
  std::size_t p = 0;
  while (p < text.size() && (text[p] == ' ' || text[p] == '\t')) ++p;
  std::size_t q = p;
  while (q < text.size() &&
         (std::isalnum(static_cast<unsigned char>(text[q])) != 0 || text[q] == '_'))
    ++q;
  return {text.substr(p, q - p), q};
}

// The rest of a directive's text from `at`, on one line and without its outer blanks (for
// messages).
std::string directive_rest(const Token& t, std::size_t at) {
  std::string out;
  for (const char c : t.text.substr(at)) {
    const bool blank = c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\\';
    if (!blank) {
      out += c;
    } else if (!out.empty() && out.back() != ' ') {
      out += ' ';
    }
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// A token as a directive's messages name it: its text, or "the end of the line".
std::string shown(const Token& t) {
  return t.kind == Token::End ? "the end of the line" : "'" + std::string(t.text) + "'";
}

// An #if or #elif expression, macros expanded: C's integer arithmetic with ! * / % + - < > <= >=
// == != && || (the operand not evaluated when && and || do not need it), unary - and +,
// parentheses, `defined NAME` and `defined(NAME)`; `true` is 1 and other names are 0, as in C.
class IfExpression {
 public:
  IfExpression(std::span<const Token> tokens, const Macros& macros, const std::string& path,
               std::string_view word)
      : tokens_(tokens), macros_(macros), path_(path), word_("#" + std::string(word)) {}

  std::int64_t value() {
    const std::int64_t v = binary(1);
    if (peek().kind != Token::End) {
      if (is_c_operator(peek())) unsupported_operator(peek());
      fail("unexpected " + shown(peek()) + " in " + word_, peek());
    }
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& message, const Token& at) const {
    fail_at(message, path_, at);
  }
  const Token& peek() const { return tokens_[pos_]; }
  const Token& next() { return tokens_[pos_ + 1 < tokens_.size() ? pos_++ : pos_]; }

  static int precedence(const Token& t) { return c_binary_precedence(t); }
  // C's operators that #if leaves out here (bitwise ones, ?:, assignments, ...).
  static bool is_c_operator(const Token& t) {
    return t.kind == Token::Symbol && !t.is("(") && !t.is(")") && !t.is(",");
  }
  [[noreturn]] void unsupported_operator(const Token& t) const {
    fail("operator " + shown(t) + " is not supported in " + word_ +
             " (its operators: ! * / % + - < > <= >= == != && || and parentheses)",
         t);
  }

  // Operators of at least `min`'s precedence, left to right.
  std::int64_t binary(int min) {
    std::int64_t a = unary();
    while (true) {
      const Token& op = peek();
      const int p = precedence(op);
      if (p == 0 || p < min) return a;
      next();
      const bool unneeded = (op.is("&&") && a == 0) || (op.is("||") && a != 0);
      skipping_ += unneeded ? 1 : 0;
      const std::int64_t b = binary(p + 1);
      skipping_ -= unneeded ? 1 : 0;
      a = apply(op, a, b);
    }
  }

  std::int64_t apply(const Token& op, std::int64_t a, std::int64_t b) const {
    // + - * wrap around as unsigned arithmetic does, so that no input is undefined behaviour.
    const auto ua = static_cast<std::uint64_t>(a), ub = static_cast<std::uint64_t>(b);
    const std::string_view s = op.text;
    if (s == "||") return a != 0 || b != 0 ? 1 : 0;
    if (s == "&&") return a != 0 && b != 0 ? 1 : 0;
    if (s == "==") return a == b ? 1 : 0;
    if (s == "!=") return a != b ? 1 : 0;
    if (s == "<") return a < b ? 1 : 0;
    if (s == ">") return a > b ? 1 : 0;
    if (s == "<=") return a <= b ? 1 : 0;
    if (s == ">=") return a >= b ? 1 : 0;
    if (s == "+") return static_cast<std::int64_t>(ua + ub);
    if (s == "-") return static_cast<std::int64_t>(ua - ub);
    if (s == "*") return static_cast<std::int64_t>(ua * ub);
    if (b == 0) {
      if (skipping_ > 0) return 0;
      fail("division by zero in " + word_, op);
    }
    if (b == -1) return s == "/" ? static_cast<std::int64_t>(0 - ua) : 0;
    return s == "/" ? a / b : a % b;
  }

  std::int64_t unary() {
    if (++depth_ > kMaxMacroNesting) {
      fail(word_ + " nested more than " + std::to_string(kMaxMacroNesting) + " levels deep",
           peek());
    }
    const std::int64_t v = operand();
    --depth_;
    return v;
  }

  std::int64_t operand() {
    const Token& t = next();
    if (t.is("!")) return unary() == 0 ? 1 : 0;
    if (t.is("-")) return static_cast<std::int64_t>(0 - static_cast<std::uint64_t>(unary()));
    if (t.is("+")) return unary();
    if (t.is("(")) {
      const std::int64_t v = binary(1);
      if (!peek().is(")")) {
        if (is_c_operator(peek())) unsupported_operator(peek());
        fail("expected ')' in " + word_ + ", found " + shown(peek()), peek());
      }
      next();
      return v;
    }
    if (t.kind == Token::Number) {
      if (!t.integral) fail(word_ + " takes integers, not " + shown(t), t);
      if (t.number >= 9.2e18) fail("integer " + shown(t) + " is too large for " + word_, t);
      return static_cast<std::int64_t>(t.number);
    }
    if (t.is_word("defined")) {
      const bool parenthesized = peek().is("(");
      if (parenthesized) next();
      const Token& name = next();
      if (name.kind != Token::Ident) fail("defined needs a macro name, found " + shown(name), name);
      if (parenthesized && !next().is(")"))
        fail("expected ')' after defined(" + std::string(name.text), name);
      return macros_.contains(name.text) ? 1 : 0;
    }
    if (t.kind == Token::Ident) return t.is_word("true") ? 1 : 0;
    if (t.kind == Token::End) fail("expected a value in " + word_ + ", found " + shown(t), t);
    if (is_c_operator(t)) unsupported_operator(t);
    fail("unexpected " + shown(t) + " in " + word_, t);
  }

  std::span<const Token> tokens_;  // ending with End
  const Macros& macros_;
  const std::string& path_;
  std::string word_;  // "#if" or "#elif"
  std::size_t pos_ = 0;
  int depth_ = 0;
  int skipping_ = 0;  // inside operands that && and || do not need
};

class Preprocessor {
 public:
  Preprocessor(std::string_view source, const std::string& path)
      : path_(path), lexer_(source, syntax(Dialect::Shader), path) {}

  PreprocessedSource run() {
    while (true) {
      const Token t = read();
      if (t.kind == Token::Directive) {
        directive(t);
        continue;
      }
      if (t.kind == Token::End) {
        if (!conditionals_.empty()) {
          const Conditional& c = conditionals_.back();
          fail("#" + c.word + " is not closed: its #endif is missing", c.at);
        }
        out_.tokens.push_back(t);
        return std::move(out_);
      }
      const Macro* m = t.kind == Token::Ident ? find(t.text) : nullptr;
      if (m != nullptr && m->function_like) {
        call_in_code(t);
      } else if (m != nullptr) {
        expand(std::span<const Token>(&t, 1), false, out_.tokens);
      } else if (t.is_word("typedef")) {
        typedef_declaration(t);
      } else {
        out_.tokens.push_back(t);
      }
    }
  }

 private:
  [[noreturn]] void fail(const std::string& message, const Token& at) const {
    fail_at(message, path_, at);
  }

  Token read() {
    if (!pending_) return lexer_.next();
    const Token t = *pending_;
    pending_.reset();
    return t;
  }

  const Macro* find(std::string_view name) const {
    const auto it = macros_.find(name);
    return it == macros_.end() ? nullptr : &it->second;
  }

  // A directive's operands, from `at` in its text, at their own lines and columns ('#' is at
  // t.column), ending with End.
  std::vector<Token> operands(const Token& t, std::size_t at) const {
    return tokenize(t.text.substr(at), Dialect::Shader, path_, t.line,
                    t.column + 1 + static_cast<int>(at));
  }

  // typedef TYPE NAME; of a type the subset has (`typedef float real;`, `typedef half3
  // real3;`): NAME stands for TYPE from here on, as an object-like macro would. Other typedefs
  // (of structs) stay in the code, where the file reads them as what they are.
  void typedef_declaration(const Token& t) {
    std::vector<Token> tokens{t};
    while (true) {
      const Token u = read();
      if (u.kind == Token::End || u.kind == Token::Directive) {
        pending_ = u;
        break;
      }
      tokens.push_back(u);
      if (u.is(";")) break;
    }
    const bool plain = tokens.size() >= 4 && tokens.back().is(";") &&
                       tokens[tokens.size() - 2].kind == Token::Ident &&
                       std::all_of(tokens.begin() + 1, tokens.end() - 2,
                                   [](const Token& u) { return u.kind == Token::Ident; }) &&
                       !tokens[1].is_word("struct");
    if (!plain) {
      expand(tokens, false, out_.tokens);
      return;
    }
    Macro m;
    m.name = tokens[tokens.size() - 2];
    m.body.assign(tokens.begin() + 1, tokens.end() - 2);
    macros_.insert_or_assign(std::string(m.name.text), std::move(m));
  }

  void directive(const Token& t) {
    const auto [word, at] = directive_word(t);
    if (word == "if" || word == "ifdef" || word == "ifndef") {
      const bool taken = condition(t, word, at);
      conditionals_.push_back({t, std::string(word), taken, false});
      if (!taken) skip();
      return;
    }
    if (word == "elif" || word == "else" || word == "endif") {
      if (conditionals_.empty()) fail("#" + std::string(word) + " without #if", t);
      Conditional& c = conditionals_.back();
      if (word == "endif") {
        conditionals_.pop_back();
        return;
      }
      if (c.seen_else) fail("#" + std::string(word) + " after #else", t);
      c.seen_else = word == "else";
      skip();  // the group read so far was the one taken
      return;
    }
    if (word.empty() || word == "version" || word == "extension" || word == "pragma") return;
    if (word == "define") return define(t, at);
    if (word == "undef") {
      const std::vector<Token> name = operands(t, at);
      if (name[0].kind != Token::Ident) fail("#undef needs a macro name", name[0]);
      macros_.erase(std::string(name[0].text));
      return;
    }
    if (word == "error") fail("#error " + directive_rest(t, at), t);
    if (word == "include") {
      fail("#include is not supported (" + directive_rest(t, at) +
               "): the reference is read from its one file; the reference subset is listed in "
               "docs/reference.md",
           t);
    }
    fail("preprocessor directive #" + std::string(word) +
             " is not supported (only #define, #undef, #if, #ifdef, #ifndef, #elif, #else, "
             "#endif, #error, #version, #extension and #pragma); the reference subset is listed "
             "in docs/reference.md",
         t);
  }

  // Whether the group after #if, #ifdef, #ifndef or #elif `t` is read.
  bool condition(const Token& t, std::string_view word, std::size_t at) {
    const std::vector<Token> tokens = operands(t, at);
    if (word == "ifdef" || word == "ifndef") {
      if (tokens[0].kind != Token::Ident)
        fail("#" + std::string(word) + " needs a macro name, found " + shown(tokens[0]), tokens[0]);
      return (find(tokens[0].text) != nullptr) == (word == "ifdef");
    }
    std::vector<Token> expanded;
    expand(std::span<const Token>(tokens).first(tokens.size() - 1), true, expanded);
    expanded.push_back(tokens.back());
    return IfExpression(expanded, macros_, path_, word).value() != 0;
  }

  // Skips the groups not taken, unread, to the one that is (an #elif whose condition holds, or an
  // #else, when no group was taken before) or to the #endif.
  void skip() {
    int depth = 0;  // conditionals opened inside the skipped text
    while (true) {
      lexer_.skip_to_directive();
      const Token t = lexer_.next();
      if (t.kind == Token::End) {
        pending_ = t;  // run() reports the open conditional
        return;
      }
      const auto [word, at] = directive_word(t);
      if (word == "if" || word == "ifdef" || word == "ifndef") {
        ++depth;
        continue;
      }
      if (depth > 0) {
        if (word == "endif") --depth;
        continue;
      }
      Conditional& c = conditionals_.back();
      if (word == "endif") {
        conditionals_.pop_back();
        return;
      }
      if (word != "elif" && word != "else") continue;
      if (c.seen_else) fail("#" + std::string(word) + " after #else", t);
      c.seen_else = word == "else";
      if (!c.taken && (word == "else" || condition(t, word, at))) {
        c.taken = true;
        return;
      }
    }
  }

  // #define NAME value, #define NAME, #define NAME(parameters) body. A definition that cannot
  // be read (a character outside the language, # or ##) is an error only where it is used.
  void define(const Token& t, std::size_t at) {
    const std::string_view text = t.text.substr(at);
    Lexer lexer(text, syntax(Dialect::Shader), path_, t.line, t.column + 1 + static_cast<int>(at));
    Macro m;
    m.name = lexer.next();
    if (m.name.kind != Token::Ident) fail("#define needs a macro name", m.name);
    // A '(' right after the name makes a function-like macro; after a blank, it is the value's.
    const auto after =
        static_cast<std::size_t>(m.name.text.data() + m.name.text.size() - text.data());
    m.function_like = after < text.size() && text[after] == '(';
    try {
      std::vector<Token> rest;
      do {
        rest.push_back(lexer.next());
      } while (rest.back().kind != Token::End);
      const std::size_t body = m.function_like ? parameters(m, rest) : 0;
      m.body.assign(rest.begin() + static_cast<std::ptrdiff_t>(body), rest.end() - 1);
    } catch (const Error& e) {
      m.error = e;
    }
    macros_.insert_or_assign(std::string(m.name.text), std::move(m));
  }

  // A function-like macro's parameters from `rest`, the tokens after its name ('(' first);
  // returns where its body starts.
  std::size_t parameters(Macro& m, const std::vector<Token>& rest) const {
    std::size_t i = 1;
    if (rest[i].is(")")) return i + 1;
    while (true) {
      const Token& p = rest[i];
      if (p.is("."))
        fail("variadic macros are not supported (" + std::string(m.name.text) +
                 "(...)); the reference subset is listed in docs/reference.md",
             p);
      if (p.kind != Token::Ident) fail("expected a macro parameter name, found " + shown(p), p);
      if (std::find(m.parameters.begin(), m.parameters.end(), p.text) != m.parameters.end())
        fail("macro parameter '" + std::string(p.text) + "' is named twice", p);
      m.parameters.push_back(p.text);
      const Token& after = rest[++i];
      if (after.is(")")) return i + 1;
      if (!after.is(","))
        fail("expected ',' or ')' after a macro parameter, found " + shown(after), after);
      ++i;
    }
  }

  // A function-like macro's name in the code: its call, arguments read to the ')', expanded; a
  // name without '(' after it stays a name.
  void call_in_code(const Token& name) {
    const Token open = read();
    if (!open.is("(")) {
      out_.tokens.push_back(name);
      pending_ = open;
      return;
    }
    std::vector<Token> call{name, open};
    for (int depth = 1; depth > 0;) {
      const Token t = read();
      if (t.kind == Token::End) {
        fail("the arguments of macro '" + std::string(name.text) +
                 "' are not closed: ')' is missing",
             open);
      }
      if (t.kind == Token::Directive) {
        fail("a preprocessor line inside the arguments of macro '" + std::string(name.text) + "'",
             t);
      }
      if (t.is("(")) ++depth;
      if (t.is(")")) --depth;
      call.push_back(t);
    }
    expand(call, false, out_.tokens);
  }

  // Appends `in` to `out` with its macros expanded (in an #if line, the operand of `defined`
  // excepted). A macro is not expanded inside its own expansion.
  void expand(std::span<const Token> in, bool in_if, std::vector<Token>& out) {
    for (std::size_t i = 0; i < in.size(); ++i) {
      const Token& t = in[i];
      if (in_if && t.is_word("defined")) {
        const std::size_t n = i + 1 < in.size() && in[i + 1].is("(") ? 4 : 2;
        for (std::size_t k = 0; k < n && i + k < in.size(); ++k) out.push_back(in[i + k]);
        i += n - 1;
        continue;
      }
      const Macro* m = t.kind == Token::Ident ? find(t.text) : nullptr;
      if (m == nullptr ||
          std::find(active_.begin(), active_.end(), t.text) != active_.end()) {
        out.push_back(t);
        continue;
      }
      if (!m->function_like) {
        call(*m, t, {}, in_if, out);
        continue;
      }
      if (i + 1 >= in.size() || !in[i + 1].is("(")) {
        out.push_back(t);
        continue;
      }
      // The arguments: split at the commas outside parentheses.
      std::vector<std::span<const Token>> args;
      std::size_t begin = i + 2, k = i + 2;
      for (int depth = 0;; ++k) {
        if (k >= in.size()) {
          fail(
              "the arguments of macro '" + std::string(t.text) + "' are not closed: ')' is missing",
              in[i + 1]);
        }
        if (in[k].is("(")) ++depth;
        if (in[k].is(")") && depth-- == 0) break;
        if (in[k].is(",") && depth == 0) {
          args.push_back(in.subspan(begin, k - begin));
          begin = k + 1;
        }
      }
      args.push_back(in.subspan(begin, k - begin));
      call(*m, t, args, in_if, out);
      i = k;
    }
  }

  // The expansion of `m` called at `use`: each parameter replaced by its argument, expanded, then
  // the result expanded again with `m` itself left as it is.
  void call(const Macro& m, const Token& use, std::span<const std::span<const Token>> args,
            bool in_if, std::vector<Token>& out) {
    if (m.error) throw *m.error;
    if (m.function_like) {
      const bool none = m.parameters.empty() && args.size() == 1 && args[0].empty();
      const std::size_t given = none ? 0 : args.size();
      if (given != m.parameters.size()) {
        fail("macro '" + std::string(m.name.text) + "' takes " +
                 std::to_string(m.parameters.size()) +
                 (m.parameters.size() == 1 ? " argument" : " arguments") + ", got " +
                 std::to_string(given),
             use);
      }
    }
    if (depth_ >= kMaxMacroNesting) {
      fail("macros nested more than " + std::to_string(kMaxMacroNesting) + " levels deep", use);
    }
    ++depth_;
    std::vector<std::vector<Token>> expanded(m.function_like ? m.parameters.size() : 0);
    for (std::size_t k = 0; k < expanded.size(); ++k) expand(args[k], in_if, expanded[k]);
    std::vector<Token> replaced;
    for (const Token& b : m.body) {
      const auto p = b.kind == Token::Ident
                         ? std::find(m.parameters.begin(), m.parameters.end(), b.text)
                         : m.parameters.end();
      if (p == m.parameters.end()) {
        replaced.push_back(b);
      } else {
        const std::vector<Token>& a = expanded[static_cast<std::size_t>(p - m.parameters.begin())];
        replaced.insert(replaced.end(), a.begin(), a.end());
      }
    }
    made_ += replaced.size();
    if (made_ > kMaxMacroTokens) {
      fail("macro expansions make more than " + std::to_string(kMaxMacroTokens) + " tokens", use);
    }
    active_.push_back(m.name.text);
    expand(replaced, in_if, out);
    active_.pop_back();
    --depth_;
  }

  const std::string& path_;
  Lexer lexer_;
  std::optional<Token> pending_;  // a token read ahead, the next to read
  Macros macros_;
  std::vector<Conditional> conditionals_;  // the open ones, innermost last
  std::vector<std::string_view> active_;   // the macros being expanded, innermost last
  int depth_ = 0;
  std::size_t made_ = 0;  // tokens made by expansions so far
  PreprocessedSource out_;
};

}  // namespace

PreprocessedSource preprocess(std::string_view source, const std::string& path) {
  if (source.starts_with("\xEF\xBB\xBF")) source.remove_prefix(3);  // UTF-8 byte-order mark
  return Preprocessor(source, path).run();
}

}  // namespace shaderfit::reference_detail
