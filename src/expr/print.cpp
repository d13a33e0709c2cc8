#include "shaderfit/expr/print.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

PrintOptions PrintOptions::for_people(int digits) {
  if (digits < 0 || digits > 17)
    throw Error("significant digits must be 1 to 17 (or 0: as many as float32 needs)",
                SourceLocation{"PrintOptions::digits"});
  return {.substitute_parameters = true,
          .numbers = digits > 0 ? NumberText::Digits : NumberText::Float32,
          .digits = digits};
}

std::string format_number(double v) { return format_number(v, PrintOptions{}); }

std::string format_number(double v, const PrintOptions& options) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::to_chars_result r{};
  const auto f = static_cast<float>(v);
  if (options.numbers == NumberText::Float32 && std::isfinite(f))
    r = std::to_chars(buf, buf + sizeof buf, f);  // shortest text that strtof reads back as f
  else if (options.numbers == NumberText::Digits && options.digits > 0)
    r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general,
                      std::min(options.digits, 17));
  else  // Exact; and a float32 text for a value beyond float's range would read "inf"
    r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

namespace {

// Precedence levels for infix printing; higher binds tighter.
enum Prec { kSum = 1, kProduct = 2, kUnary = 3, kPower = 4, kAtom = 5 };

class InfixPrinter {
 public:
  InfixPrinter(const Expression& e, const PrintOptions& o) : e_(e), o_(o) {}

  std::string print(std::size_t i) { return text(i); }

 private:
  Prec prec(std::size_t i) const {
    const Node& n = e_.nodes[i];
    switch (n.op) {
      case Op::Add:
      case Op::Sub: return kSum;
      case Op::Mul:
      case Op::Div: return kProduct;
      case Op::Neg: return kUnary;
      case Op::IPow: return kPower;
      case Op::Const: return std::signbit(n.value) ? kUnary : kAtom;  // "-2" reads as unary
      case Op::Param:
        return (o_.substitute_parameters && std::signbit(param_value(n))) ? kUnary : kAtom;
      default: return kAtom;
    }
  }

  double param_value(const Node& n) const {
    const auto k = static_cast<std::size_t>(n.index);
    return k < e_.parameter_values.size() ? e_.parameter_values[k] : 0.0;
  }

  std::string wrap(std::size_t i, bool paren) { return paren ? "(" + text(i) + ")" : text(i); }

  bool is_literal(std::size_t k) const {
    const Node& n = e_.nodes[k];
    return n.op == Op::Const || (n.op == Op::Param && o_.substitute_parameters);
  }
  double literal_value(std::size_t k) const {
    const Node& n = e_.nodes[k];
    return n.op == Op::Const ? n.value : param_value(n);
  }
  bool negative_literal(std::size_t k) const {
    if (!is_literal(k)) return false;
    const double v = literal_value(k);
    return !std::isnan(v) && std::signbit(v);
  }

  // A product of something by a negative literal is written literal first, so that no text
  // shows `x * -c` and in a sum its sign joins the sum's (`a - c * x`): the same value bit for
  // bit (multiplication commutes), and it reads back as written. A product of two literals
  // keeps its order.
  void order_factors(std::size_t i, std::size_t* c) const {
    if (e_.nodes[i].op == Op::Mul && negative_literal(c[1]) && !is_literal(c[0]))
      std::swap(c[0], c[1]);
  }

  std::string number(double v) const { return format_number(v, o_); }

  // A term as a sign and a text that does not start with '-': a negative literal, a Neg node, or
  // a product or quotient whose left operand is one of these gives its sign to the sum around it
  // (a - -c * x is printed a + c * x: -(c * x) == (-c) * x bit for bit).
  struct Signed {
    bool negative = false;
    std::string body;
  };
  Signed signed_text(std::size_t i) {
    const Node& n = e_.nodes[i];
    std::size_t c[2] = {0, 0};
    if (n.arity == 1 || n.arity == 2) e_.child_indices(i, std::span<std::size_t>(c, n.arity));
    if (n.arity == 2) order_factors(i, c);
    const bool literal = n.op == Op::Const || (n.op == Op::Param && o_.substitute_parameters);
    if (literal) {
      const double v = n.op == Op::Const ? n.value : param_value(n);
      if (!std::isnan(v)) return {std::signbit(v), number(std::fabs(v))};
    }
    if (n.op == Op::Neg) {
      if (prec(c[0]) < kProduct) return {true, "(" + text(c[0]) + ")"};
      Signed s = signed_text(c[0]);
      s.negative = !s.negative;
      return s;
    }
    if ((n.op == Op::Mul || n.op == Op::Div) && prec(c[0]) >= kProduct) {
      Signed s = signed_text(c[0]);
      s.body = binary(i, c, std::move(s.body));
      return s;
    }
    return {false, text(i)};
  }

  // A binary operator's text with its left operand's text given. The left operand keeps equal
  // precedence bare (left-associative); the right one does not. A negative literal or a Neg
  // node on the right of a product is fine bare ("a * -2"): the parser reads "-2" as one literal.
  std::string binary(std::size_t i, const std::size_t* c, std::string left) {
    const Node& n = e_.nodes[i];
    const Prec p = prec(i);
    const Prec rp = prec(c[1]);
    if (p == kSum && rp > kSum) {  // a - -c is printed a + c
      const Signed s = signed_text(c[1]);
      const bool minus = (n.op == Op::Sub) != s.negative;
      return left + (minus ? " - " : " + ") + s.body;
    }
    const bool right_paren = rp <= p && rp != kUnary;
    return left + " " + std::string(op_info(n.op).name) + " " + wrap(c[1], right_paren);
  }

  std::string text(std::size_t i) {
    const Node& n = e_.nodes[i];
    std::size_t c[3];
    if (n.arity > 0) e_.child_indices(i, std::span<std::size_t>(c, n.arity));
    if (n.arity == 2) order_factors(i, c);
    switch (n.op) {
      case Op::Const: return number(n.value);
      case Op::Var: return e_.variables.at(static_cast<std::size_t>(n.index));
      case Op::Param:
        return o_.substitute_parameters ? number(param_value(n))
                                        : e_.parameters.at(static_cast<std::size_t>(n.index));
      case Op::Add:
        // A negative constant first in a sum is written last, `x - c` for `-c + x`: the same
        // value bit for bit (a + b = b + a, and b + -c = b - c), read back as written.
        if (negative_literal(c[0]) && !is_literal(c[1]))
          return wrap(c[1], prec(c[1]) < kSum) + " - " + number(std::fabs(literal_value(c[0])));
        return binary(i, c, wrap(c[0], prec(c[0]) < prec(i)));
      case Op::Sub:
      case Op::Mul:
      case Op::Div: return binary(i, c, wrap(c[0], prec(c[0]) < prec(i)));
      case Op::Neg: {
        const Node& k = e_.nodes[c[0]];
        // "-(2)" keeps Neg(Const) apart from the literal -2; "-x^2" already means -(x^2).
        const bool literal = k.op == Op::Const || (k.op == Op::Param && o_.substitute_parameters);
        return "-" + wrap(c[0], literal || prec(c[0]) < kUnary);
      }
      case Op::IPow: {
        const Node& k = e_.nodes[c[0]];
        // A non-negative literal base stays bare ("2^3"); everything below atom level is wrapped.
        const bool paren = prec(c[0]) < kAtom || (k.op == Op::Const && std::signbit(k.value));
        return wrap(c[0], paren) + "^" + std::to_string(n.index);
      }
      case Op::Pow: {
        std::string exponent = text(c[1]);
        // An integer literal exponent would read back as the integer power; mark it real.
        const Node& k = e_.nodes[c[1]];
        if (k.op == Op::Const && std::isfinite(k.value) &&
            exponent.find_first_of(".en") == std::string::npos)
          exponent += ".0";
        return "pow(" + text(c[0]) + ", " + exponent + ")";
      }
      // The condition as the parser reads it back into the same operand (a literal 0 on the
      // right of >= adds no node).
      case Op::Select:
        return "select(" + text(c[0]) + " >= 0, " + text(c[1]) + ", " + text(c[2]) + ")";
      default: {
        std::string s = std::string(op_info(n.op).name) + "(";
        for (int k = 0; k < n.arity; ++k) s += (k ? ", " : "") + text(c[k]);
        return s + ")";
      }
    }
  }

  const Expression& e_;
  const PrintOptions& o_;
};

std::string latex_name(const std::string& name) {
  // r0 -> r_{0}; cos_theta -> \mathrm{cos\_theta}; single letters stay italic.
  std::size_t d = name.size();
  while (d > 0 && std::isdigit(static_cast<unsigned char>(name[d - 1]))) --d;
  if (d == 1 && d < name.size()) return name.substr(0, 1) + "_{" + name.substr(1) + "}";
  if (name.size() == 1) return name;
  std::string s;
  for (char ch : name) s += ch == '_' ? std::string("\\_") : std::string(1, ch);
  return "\\mathrm{" + s + "}";
}

class LatexPrinter {
 public:
  LatexPrinter(const Expression& e, const PrintOptions& o) : e_(e), o_(o) {}

  std::string text(std::size_t i) {
    const Node& n = e_.nodes[i];
    std::size_t c[3];
    if (n.arity > 0) e_.child_indices(i, std::span<std::size_t>(c, n.arity));
    switch (n.op) {
      case Op::Const: return number(n.value);
      case Op::Var: return latex_name(e_.variables.at(static_cast<std::size_t>(n.index)));
      case Op::Param: {
        const auto k = static_cast<std::size_t>(n.index);
        if (o_.substitute_parameters && k < e_.parameter_values.size())
          return number(e_.parameter_values[k]);
        return latex_name(e_.parameters.at(k));
      }
      case Op::Add: return sum(c[0], c[1], false);
      case Op::Sub: return sum(c[0], c[1], true);
      default: return pattern(op_info(n.op).latex, n, c);
    }
  }

 private:
  // An operator's LaTeX pattern from op.hpp with its operands written in: $0 as text, $f0 as a
  // factor, $b0 as the base of a power, $k the node's index.
  std::string pattern(std::string_view p, const Node& n, const std::size_t* c) {
    std::string s;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p[i] != '$') {
        s += p[i];
        continue;
      }
      const char kind = p[++i];
      if (kind == 'k') {
        s += std::to_string(n.index);
        continue;
      }
      if (kind == 'f' || kind == 'b') ++i;
      const std::size_t child = c[p[i] - '0'];
      s += kind == 'f' ? factor(child) : kind == 'b' ? base(child) : text(child);
    }
    return s;
  }

  std::string number(double v) const {
    std::string s = format_number(v, o_);
    auto e = s.find('e');
    if (e == std::string::npos) return s;
    std::string exp = s.substr(e + 1);
    if (!exp.empty() && exp[0] == '+') exp.erase(0, 1);
    return s.substr(0, e) + " \\times 10^{" + exp + "}";
  }
  bool is_sum(std::size_t i) const {
    const Op op = e_.nodes[i].op;
    return op == Op::Add || op == Op::Sub || op == Op::Fma;
  }
  std::string paren(std::size_t i) { return "\\left(" + text(i) + "\\right)"; }
  // a + b or a - b with one sign between them: a negative number on the right (a literal or a
  // substituted parameter) or a negation flips the operator.
  std::string sum(std::size_t left, std::size_t right, bool minus) {
    const Node& n = e_.nodes[right];
    double v = 0;
    bool number_node = n.op == Op::Const;
    if (n.op == Op::Const) v = n.value;
    if (n.op == Op::Param && o_.substitute_parameters &&
        static_cast<std::size_t>(n.index) < e_.parameter_values.size()) {
      v = e_.parameter_values[static_cast<std::size_t>(n.index)];
      number_node = true;
    }
    if (number_node && std::signbit(v) && !std::isnan(v))
      return text(left) + (minus ? " + " : " - ") + number(-v);
    if (n.op == Op::Neg) {
      std::size_t c[1];
      e_.child_indices(right, std::span<std::size_t>(c, 1));
      return text(left) + (minus ? " + " : " - ") + sum_right(c[0], !minus);
    }
    return text(left) + (minus ? " - " : " + ") + sum_right(right, minus);
  }
  std::string sum_right(std::size_t i, bool minus) {
    const Op op = e_.nodes[i].op;
    const bool neg = op == Op::Neg || (op == Op::Const && std::signbit(e_.nodes[i].value));
    return (minus && is_sum(i)) || neg ? paren(i) : text(i);
  }
  std::string factor(std::size_t i) {
    const Op op = e_.nodes[i].op;
    const bool neg = op == Op::Neg || (op == Op::Const && std::signbit(e_.nodes[i].value));
    return is_sum(i) || neg ? paren(i) : text(i);
  }
  std::string base(std::size_t i) {
    const Node& n = e_.nodes[i];
    const bool atom = n.op == Op::Var || n.op == Op::Param ||
                      (n.op == Op::Const && !std::signbit(n.value) &&
                       format_number(n.value, o_).find('e') == std::string::npos);
    return atom ? text(i) : paren(i);
  }

  const Expression& e_;
  const PrintOptions& o_;
};

// e without the parts its text would show as neutral: a literal factor or divisor written 1 or
// -1 (x * -1 is written -x), a literal addend or subtrahend written 0 (0 - x is written -x), and
// ^1. The text means the same without them (a literal is what its text reads: 1.0000000001 shown
// in float32 is 1), up to the sign of a zero sum. A sign counts as written too, because a sum
// shows its terms' signs as its own (a - -1 * x is written a + 1 * x).
Expression without_neutral_text(const Expression& e, const PrintOptions& o) {
  using Frag = std::vector<Node>;
  // The value of a literal: a constant, or a parameter printed as its value.
  const auto literal = [&](const Frag& f) -> std::optional<double> {
    if (f.size() != 1) return std::nullopt;
    if (f[0].op == Op::Const) return f[0].value;
    const auto k = static_cast<std::size_t>(f[0].index);
    if (f[0].op == Op::Param && o.substitute_parameters && k < e.parameter_values.size())
      return e.parameter_values[k];
    return std::nullopt;
  };
  // Whether f is a literal whose text reads `value` (0 with either sign).
  const auto reads = [&](const Frag& f, double value) {
    const std::optional<double> v = literal(f);
    return v && format_number(value == 0 ? std::fabs(*v) : *v, o) == format_number(value, o);
  };
  const auto negated = [&](Frag f) -> Frag {
    if (f.back().op == Op::Neg) {
      f.pop_back();
      return f;
    }
    if (const std::optional<double> v = literal(f)) return {Node::constant(-*v)};
    f.push_back(Node::op_node(Op::Neg));
    return f;
  };
  std::vector<Frag> stack;
  for (const Node& n : e.nodes) {
    std::vector<Frag> kids(static_cast<std::size_t>(n.arity));
    for (std::size_t k = kids.size(); k-- > 0;) {
      kids[k] = std::move(stack.back());
      stack.pop_back();
    }
    const bool product = n.op == Op::Mul || n.op == Op::Div,
               sum = n.op == Op::Add || n.op == Op::Sub;
    if (n.op == Op::IPow && n.index == 1) {
      stack.push_back(std::move(kids[0]));
    } else if (product && reads(kids[1], 1)) {
      stack.push_back(std::move(kids[0]));
    } else if (product && reads(kids[1], -1)) {
      stack.push_back(negated(std::move(kids[0])));
    } else if (n.op == Op::Mul && reads(kids[0], 1)) {
      stack.push_back(std::move(kids[1]));
    } else if (n.op == Op::Mul && reads(kids[0], -1)) {
      stack.push_back(negated(std::move(kids[1])));
    } else if (sum && reads(kids[1], 0)) {
      stack.push_back(std::move(kids[0]));
    } else if (n.op == Op::Add && reads(kids[0], 0)) {
      stack.push_back(std::move(kids[1]));
    } else if (n.op == Op::Sub && reads(kids[0], 0)) {
      stack.push_back(negated(std::move(kids[1])));
    } else {
      Frag f;
      for (Frag& k : kids) f.insert(f.end(), k.begin(), k.end());
      f.push_back(n);
      stack.push_back(std::move(f));
    }
  }
  Expression out = e;
  out.nodes = std::move(stack.back());
  out.update_lengths();
  return out;
}

}  // namespace

std::string to_infix(const Expression& e, const PrintOptions& options) {
  if (e.nodes.empty()) return "";
  const Expression shown = without_neutral_text(e, options);
  return InfixPrinter(shown, options).print(shown.nodes.size() - 1);
}

std::string to_latex(const Expression& e, const PrintOptions& options) {
  if (e.nodes.empty()) return "";
  const Expression shown = without_neutral_text(e, options);
  return LatexPrinter(shown, options).text(shown.nodes.size() - 1);
}

}  // namespace shaderfit
