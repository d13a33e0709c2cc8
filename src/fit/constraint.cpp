// Parsing constraints: split at the top-level '=', recognise f(...) and df/dv(...) on the left,
// and parse the pieces with the formula parser, shifting its error columns to the whole text.
#include "shaderfit/fit/constraint.hpp"

#include <algorithm>
#include <cctype>

#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {

namespace {

struct Piece {
  std::string_view text;
  int column = 1;  // 1-based column of text[0] in the constraint
};

Piece trim(Piece p) {
  while (!p.text.empty() && std::isspace(static_cast<unsigned char>(p.text.front()))) {
    p.text.remove_prefix(1);
    ++p.column;
  }
  while (!p.text.empty() && std::isspace(static_cast<unsigned char>(p.text.back())))
    p.text.remove_suffix(1);
  return p;
}

[[noreturn]] void fail(const std::string& message, const std::string& source, int column) {
  throw Error(message, SourceLocation{source, 1, column});
}

// The formula parser on a piece, with its error locations moved to the piece's place.
Expression parse_piece(Piece p, const ParseOptions& options, const std::string& source) {
  if (p.text.empty()) fail("expected an expression", source, p.column);
  try {
    return parse_formula(p.text, options);
  } catch (const Error& e) {
    const int column = e.where().column > 0 ? e.where().column + p.column - 1 : p.column;
    fail(e.message(), source, column);
  }
}

// Position of the '=' at parenthesis depth 0; npos when there is none.
std::size_t top_level_equals(std::string_view s) {
  int depth = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '(') ++depth;
    if (s[i] == ')') --depth;
    if (s[i] == '=' && depth == 0) return i;
  }
  return std::string_view::npos;
}

bool is_identifier(std::string_view s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

// "x = 0, roughness = 0.5": each name must be a formula variable, each value a constant
// expression (numbers, pi, arithmetic).
std::vector<std::pair<std::string, double>> parse_point(Piece p, const Expression& formula,
                                                        const std::string& source) {
  std::vector<std::pair<std::string, double>> point;
  std::size_t start = 0;
  while (start <= p.text.size()) {
    std::size_t end = p.text.find(',', start);
    if (end == std::string_view::npos) end = p.text.size();
    Piece item = trim({p.text.substr(start, end - start), p.column + static_cast<int>(start)});
    const std::size_t eq = item.text.find('=');
    if (item.text.empty() && point.empty() && end == p.text.size()) break;  // f()
    if (eq == std::string_view::npos)
      fail("expected 'variable = value' in the point", source, item.column);
    Piece name = trim({item.text.substr(0, eq), item.column});
    const std::string n(name.text);
    if (std::find(formula.variables.begin(), formula.variables.end(), n) == formula.variables.end())
      fail("'" + n + "' is not a variable of the formula", source, name.column);
    Piece value = trim({item.text.substr(eq + 1), item.column + static_cast<int>(eq) + 1});
    ParseOptions po;
    po.variables = {"__none__"};
    po.source = source;
    const Expression v = parse_piece(value, po, source);
    point.emplace_back(n, evaluate_scalar(v, std::vector<double>{0.0}));
    start = end + 1;
  }
  return point;
}

}  // namespace

Constraint parse_constraint(std::string_view text, const Expression& formula,
                            const std::string& source) {
  Constraint c;
  c.text = std::string(text);
  const std::size_t eq = top_level_equals(text);
  if (eq == std::string_view::npos)
    fail("a constraint needs '=': write e.g. 'C = 0' or 'f(x = 0) = f0'", source, 1);
  std::size_t rhs_start = eq + 1;
  if (rhs_start < text.size() && text[rhs_start] == '=') ++rhs_start;  // '=='
  Piece lhs = trim({text.substr(0, eq), 1});
  Piece rhs = trim({text.substr(rhs_start), static_cast<int>(rhs_start) + 1});

  // The left side: f(point), df/dv(point), or a relation between parameters.
  const std::size_t open = lhs.text.find('(');
  const std::string_view head =
      open == std::string_view::npos ? lhs.text : lhs.text.substr(0, open);
  std::string compact;
  for (char ch : head)
    if (!std::isspace(static_cast<unsigned char>(ch))) compact += ch;
  const bool call = open != std::string_view::npos && lhs.text.back() == ')';
  const bool value = call && compact == "f";
  const bool derivative = call && compact.size() > 4 && compact.rfind("df/d", 0) == 0 &&
                          is_identifier(compact.substr(4));
  if (value || derivative) {
    c.kind = value ? Constraint::Kind::value : Constraint::Kind::derivative;
    if (derivative) {
      c.variable = compact.substr(4);
      if (std::find(formula.variables.begin(), formula.variables.end(), c.variable) ==
          formula.variables.end())
        fail("cannot differentiate by '" + c.variable + "': not a variable of the formula", source,
             lhs.column);
    }
    Piece inside{lhs.text.substr(open + 1, lhs.text.size() - open - 2),
                 lhs.column + static_cast<int>(open) + 1};
    c.point = parse_point(inside, formula, source);
  } else {
    ParseOptions po;
    po.variables = formula.variables;
    po.parameters = formula.parameters;
    po.source = source;
    c.lhs = parse_piece(lhs, po, source);
    for (const Node& n : c.lhs.nodes) {
      if (n.op == Op::Var)
        fail("a relation between parameters cannot use the variable '" +
                 c.lhs.variables[static_cast<std::size_t>(n.index)] +
                 "' (constrain the formula's value with f(" +
                 c.lhs.variables[static_cast<std::size_t>(n.index)] + " = ...) = ...)",
             source, lhs.column);
    }
    bool has_parameter = false;
    for (const Node& n : c.lhs.nodes) has_parameter = has_parameter || n.op == Op::Param;
    if (!has_parameter) fail("the left-hand side names no parameter", source, lhs.column);
    c.lhs.variables.clear();
    c.lhs.parameter_values.assign(c.lhs.parameters.size(), 0.0);
  }

  ParseOptions po;
  po.variables = formula.variables;
  po.parameters = formula.parameters;
  po.source = source;
  c.rhs = parse_piece(rhs, po, source);
  for (const Node& n : c.rhs.nodes) {
    if (n.op == Op::Param)
      fail("the right-hand side cannot use the parameter '" +
               c.rhs.parameters[static_cast<std::size_t>(n.index)] + "'",
           source, rhs.column);
    if (n.op == Op::Var && c.kind == Constraint::Kind::parameters)
      fail("the right-hand side of a relation between parameters must be a number", source,
           rhs.column);
  }
  c.rhs.parameters.clear();
  c.rhs.parameter_values.clear();
  c.rhs.drop_unused_variables();
  return c;
}

}  // namespace shaderfit
