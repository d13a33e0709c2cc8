#include "shaderfit/rational/condition.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <system_error>

#include "shaderfit/expr/forward.hpp"
#include "shaderfit/expr/jet.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/rational/target.hpp"

namespace shaderfit::rational {

namespace {

// A small cursor over the condition text that reports errors with 1-based columns.
struct Cursor {
  std::string_view text;
  std::size_t pos = 0;
  SourceLocation where;

  [[noreturn]] void fail(const std::string& message, std::size_t at) const {
    SourceLocation w = where;
    if (w.line == 0) w.line = 1;
    w.column = static_cast<int>(at) + 1;
    throw Error(message + " in condition '" + std::string(text) + "'", w);
  }
  void skip_space() {
    while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
  }
  bool accept(char c) {
    skip_space();
    if (pos < text.size() && text[pos] == c) {
      ++pos;
      return true;
    }
    return false;
  }
  void expect(char c, const char* what) {
    if (!accept(c)) fail(std::string("expected ") + what, pos);
  }
  std::string_view identifier() {
    skip_space();
    const std::size_t start = pos;
    while (pos < text.size() &&
           (std::isalnum(static_cast<unsigned char>(text[pos])) || text[pos] == '_'))
      ++pos;
    return text.substr(start, pos - start);
  }
  // The text up to the first of `stops` at parenthesis depth 0; fails if there is none.
  std::string_view until(std::string_view stops, const char* what) {
    const std::size_t start = pos;
    int depth = 0;
    for (; pos < text.size(); ++pos) {
      const char c = text[pos];
      if (depth == 0 && stops.find(c) != std::string_view::npos)
        return text.substr(start, pos - start);
      if (c == '(') ++depth;
      if (c == ')') --depth;
    }
    fail(std::string("expected ") + what, pos);
  }
};

// Parses a formula that is part of the condition, moving error columns to the whole text.
Expression parse_part(const Cursor& cur, std::string_view part, std::size_t offset,
                      const std::vector<std::string>& parameters) {
  ParseOptions opts;
  opts.parameters = parameters;
  try {
    Expression e = parse_formula(part, opts);
    if (!e.variables.empty()) {
      const std::string& name = e.variables.front();
      std::size_t at = part.find(name);
      cur.fail("unknown name '" + name + "'" +
                   (parameters.empty() ? std::string(" (no parameters are defined)")
                                       : " (not a parameter)"),
               offset + (at == std::string_view::npos ? 0 : at));
    }
    return e;
  } catch (const Error& e) {
    if (e.where().source != "formula") throw;
    cur.fail(e.message(), offset + static_cast<std::size_t>(std::max(e.where().column - 1, 0)));
  }
}

// A point or bound: a formula without names.
double parse_constant(const Cursor& cur, std::string_view part, std::size_t offset) {
  const Expression e = parse_part(cur, part, offset, {});
  const double v = evaluate_at(e, Jet(0.0), {}).value();
  if (!std::isfinite(v)) cur.fail("the point is not a finite number", offset);
  return v;
}

std::size_t trimmed_start(std::string_view s, std::size_t offset) {
  std::size_t i = 0;
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  return offset + i;
}

}  // namespace

SourceLocation Condition::point_location() const {
  SourceLocation w = where;
  if (point_column > 0) {
    if (w.line == 0) w.line = 1;
    w.column = point_column;
  }
  return w;
}

Condition Condition::derivative(double at, int order, double value) {
  Condition c;
  c.order = order;
  c.a = at;
  c.value.nodes = {Node::constant(value)};
  c.text = condition_text(c);
  return c;
}

Condition Condition::integral(double from, double to, double value) {
  Condition c;
  c.kind = Kind::Integral;
  c.a = from;
  c.b = to;
  c.value.nodes = {Node::constant(value)};
  c.text = condition_text(c);
  return c;
}

Condition Condition::derivative_of_reference(double at, int order) {
  Condition c = derivative(at, order, 0.0);
  c.from_reference = true;
  c.text = condition_text(c);
  return c;
}

Condition Condition::integral_of_reference(double from, double to) {
  Condition c = integral(from, to, 0.0);
  c.from_reference = true;
  c.text = condition_text(c);
  return c;
}

std::string condition_text(const Condition& c) {
  std::string lhs;
  if (c.is_integral()) {
    lhs = "int(" + format_number(c.a) + ", " + format_number(c.b) + ")";
  } else {
    lhs = c.order <= 3 ? "f" + std::string(static_cast<std::size_t>(c.order), '\'')
                       : "f^(" + std::to_string(c.order) + ")";
    lhs += "(" + format_number(c.a) + ")";
  }
  return lhs + " = " + (c.from_reference ? std::string("ref") : to_infix(c.value));
}

Condition parse_condition(std::string_view text, const std::vector<std::string>& parameters,
                          SourceLocation where) {
  Cursor cur{text, 0, std::move(where)};
  Condition c;
  c.text = std::string(text);
  c.where = cur.where;
  cur.skip_space();
  const std::size_t name_at = cur.pos;
  const std::string_view name = cur.identifier();
  if (name.empty()) cur.fail("expected f(...), f'(...), f^(k)(...) or int(a, b)", name_at);

  if (name == "int" || name == "integral") {
    c.kind = Condition::Kind::Integral;
    cur.expect('(', "'(' after int");
    const std::size_t a_at = cur.pos;
    const std::string_view a = cur.until(",", "',' between the bounds of the integral");
    cur.pos++;
    const std::size_t b_at = cur.pos;
    const std::string_view b = cur.until(")", "')' after the bounds of the integral");
    cur.pos++;
    c.point_column = static_cast<int>(trimmed_start(a, a_at)) + 1;
    c.a = parse_constant(cur, a, a_at);
    c.b = parse_constant(cur, b, b_at);
    if (!(c.a < c.b)) cur.fail("the integral's lower bound must be below its upper bound", a_at);
  } else {
    // Derivative order: primes, or ^(k) / ^k.
    cur.skip_space();
    while (cur.pos < text.size() && text[cur.pos] == '\'') {
      if (c.order == kMaxDerivativeOrder)
        cur.fail("more primes than the highest supported derivative order, " +
                     std::to_string(kMaxDerivativeOrder),
                 cur.pos);
      ++c.order;
      ++cur.pos;
    }
    if (c.order == 0 && cur.accept('^')) {
      const bool paren = cur.accept('(');
      cur.skip_space();
      const std::size_t k_at = cur.pos;
      if (cur.pos < text.size() && (text[cur.pos] == '-' || text[cur.pos] == '+')) ++cur.pos;
      while (cur.pos < text.size() && std::isdigit(static_cast<unsigned char>(text[cur.pos])))
        ++cur.pos;
      const std::string digits(text.substr(k_at, cur.pos - k_at));
      if (digits.empty() || digits == "-" || digits == "+")
        cur.fail("expected the derivative order, an integer", k_at);
      // Parsed as a long only up to the limit: "f^99999999999999999999(0)" is too high, not a
      // number the library cannot hold.
      long k = 0;
      const char* first = digits.data() + (digits[0] == '+' ? 1 : 0);
      const auto parsed = std::from_chars(first, digits.data() + digits.size(), k);
      if (parsed.ec == std::errc::result_out_of_range)
        k = digits[0] == '-' ? -1 : kMaxDerivativeOrder + 1;
      if (k < 0) cur.fail("the derivative order must be 0 or more, not " + digits, k_at);
      if (k > kMaxDerivativeOrder)
        cur.fail("derivative order " + digits + " is above the highest supported, " +
                     std::to_string(kMaxDerivativeOrder),
                 k_at);
      c.order = static_cast<int>(k);
      if (paren) cur.expect(')', "')' after the derivative order");
    }
    cur.expect('(', "'(' before the point");
    const std::size_t a_at = cur.pos;
    const std::string_view a = cur.until(")", "')' after the point");
    cur.pos++;
    c.point_column = static_cast<int>(trimmed_start(a, a_at)) + 1;
    c.a = parse_constant(cur, a, a_at);
  }

  cur.expect('=', "'='");
  const std::size_t v_at = cur.pos;
  const std::string_view v = text.substr(v_at);
  std::size_t s = 0, e = v.size();
  while (s < e && std::isspace(static_cast<unsigned char>(v[s]))) ++s;
  while (e > s && std::isspace(static_cast<unsigned char>(v[e - 1]))) --e;
  if (s == e) cur.fail("expected a value after '='", v_at + s);
  if (v.substr(s, e - s) == "ref" || v.substr(s, e - s) == "reference") {
    c.from_reference = true;
  } else {
    c.value = parse_part(cur, v, v_at, parameters);
  }
  return c;
}

}  // namespace shaderfit::rational
