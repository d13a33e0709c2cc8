#include "shaderfit/expr/print.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <span>
#include <vector>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

PrintOptions PrintOptions::for_people(int digits) {
  if (digits < 0 || digits > 17)
    throw Error("significant digits must be 1 to 17 (or 0: as many as float32 needs)",
                SourceLocation{"PrintOptions::digits"});
  return {.substitute_parameters = true,
          .numbers = digits > 0 ? NumberText::Digits : NumberText::Float32,
          .digits = digits,
          .natural = true};
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

// The value a leaf shows as a number: a constant, or a parameter printed as its value
// (PrintOptions::substitute_parameters; 0 where it has none); nullopt for the other nodes.
std::optional<double> literal_of(const Node& n, const Expression& e, const PrintOptions& o) {
  if (n.op == Op::Const) return n.value;
  if (n.op != Op::Param || !o.substitute_parameters) return std::nullopt;
  const auto k = static_cast<std::size_t>(n.index);
  return k < e.parameter_values.size() ? e.parameter_values[k] : 0.0;
}

// Precedence levels for infix printing; higher binds tighter.
enum Prec { kSum = 1, kProduct = 2, kUnary = 3, kPower = 4, kAtom = 5 };

// A formula's text in two parts: a sign and the text of the magnitude. Signs travel outward
// through products, quotients, odd functions and sums until a place that must show them (the
// whole formula, a function's argument), so that no text shows `x * -c`, `a - -b`, `a + -b` or
// a negated group `-(...)` after an operator; a negated sum is written with its terms' signs
// flipped (`b - a`, `-a - b`). Each move is exact: negation commutes with rounding, so
// -(a * b) = (-a) * b, -(a + b) = -a - b and -(a - b) = b - a bit for bit, up to the sign of a
// zero; an even function drops its operand's sign and an odd one passes it out, exactly for
// the arithmetic ones (abs, ipow, rcp, sign, copysign) and to the library's rounding for the
// others, which only the text for people moves.
class InfixPrinter {
 public:
  InfixPrinter(const Expression& e, const PrintOptions& o) : e_(e), o_(o) {}

  std::string print(std::size_t i) { return shown(term(i)); }

 private:
  struct Term {
    bool negative = false;  // the value is -(what `text` reads)
    std::string text;       // never starts with '-'
    Prec prec = kAtom;      // of `text`
    std::string minus;      // the text of -(text), never starting with "-(" where avoidable
    bool literal = false;
    bool abs = false;  // abs(...): the instruction model counts b - |a| apart from |a| - b
    bool abs_subtrahend = false;  // b - abs(a): its negation |a| - b costs one instruction less
  };

  static std::string paren(const std::string& s, bool p) { return p ? "(" + s + ")" : s; }
  // The text a place that shows signs writes: the whole formula, a function's argument.
  static std::string shown(const Term& t) { return t.negative ? t.minus : t.text; }

  Term leaf(std::string text, bool negative = false, bool literal = false) {
    Term t{negative, std::move(text), kAtom, "", literal};
    t.minus = "-" + t.text;
    return t;
  }

  std::string number(double v) const { return format_number(v, o_); }

  // Whether a unary operator's sign rule may be used: exact ones always, the library's (sin,
  // erf, ...) only in text for people, whose values are equal up to float rounding.
  bool parity_applies(Op op) const {
    return !op_info(op).library || o_.numbers != NumberText::Exact;
  }

  // a + b (minus_right false) or a - b of two terms, the sum's sign outside.
  Term sum(Term a, Term b, bool minus_right) {
    if (minus_right) b.negative = !b.negative;
    Term t;
    t.prec = kSum;
    // -|a| + b stays so: GPUs take it in one instruction, and b - |a| in two.
    if (a.negative && a.abs && !b.negative) {
      const std::string right = paren(b.text, b.prec <= kSum);
      t.text = a.minus + " + " + right;
      t.minus = a.text + " - " + right;
      return t;
    }
    // A positive term first, and in a negated sum a literal last (-c - x is -(x + c)):
    // a + b = b + a exactly.
    if ((a.negative && !b.negative) || (a.negative && b.negative && a.literal && !b.literal))
      std::swap(a, b);
    t.negative = a.negative && b.negative;  // -a - b = -(a + b)
    const bool subtract = a.negative != b.negative;
    const std::string op = subtract ? " - " : " + ";
    const std::string right = paren(b.text, b.prec <= kSum);
    t.text = a.text + op + right;
    // -(a - b) is b - a; -(a + b) is -a - b, a literal last (-(c + x) is -x - c, as the negated
    // sum -c - x is written). But -(|a| - b) stays so: GPUs take |a| - b in one instruction, and
    // b - |a| or -|a| + b in two.
    if (subtract && a.abs)
      t.minus = "-(" + t.text + ")";
    else if (subtract && a.prec > kSum)
      t.minus = b.text + " - " + a.text;
    else if (!subtract && a.literal && !b.literal)
      t.minus = b.minus + " - " + a.text;
    else
      t.minus = a.minus + (subtract ? " + " : " - ") + right;
    t.abs_subtrahend = subtract && b.abs && a.prec > kSum;
    return t;
  }

  Term product(Term a, Term b, Op op) {
    // c * x: a literal factor first, where that adds no parentheses (exact: a * b = b * a).
    if (op == Op::Mul && b.literal && !a.literal && a.prec != kProduct) std::swap(a, b);
    Term t;
    t.prec = kProduct;
    t.negative = a.negative != b.negative;
    const std::string name = op == Op::Mul ? " * " : " / ";
    const std::string right = paren(b.text, b.prec <= kProduct);
    t.text = paren(a.text, a.prec < kProduct) + name + right;
    t.minus = paren(a.minus, a.prec < kProduct) + name + right;
    return t;
  }

  Term call(const Node& n, const std::size_t* c) {
    const OpInfo& info = op_info(n.op);
    if (n.arity == 1 && info.parity != OpParity::None && parity_applies(n.op)) {
      Term a = term(c[0]);
      Term t = leaf(std::string(info.name) + "(" + a.text + ")");
      t.negative = info.parity == OpParity::Odd && a.negative;
      t.abs = n.op == Op::Abs;
      return t;
    }
    if (n.op == Op::CopySign)  // copysign(-a, b) = copysign(a, b)
      return leaf("copysign(" + term(c[0]).text + ", " + shown(term(c[1])) + ")");
    std::string s = std::string(info.name) + "(";
    for (int k = 0; k < n.arity; ++k) s += (k ? ", " : "") + shown(term(c[k]));
    return leaf(s + ")");
  }

  std::string condition(std::size_t i) {
    const Node& n = e_.nodes[i];
    if (o_.natural && n.op == Op::Sub) {
      std::size_t c[2] = {0, 0};
      e_.child_indices(i, std::span<std::size_t>(c, 2));
      const Term a = term(c[0]), b = term(c[1]);
      const auto zero = [](const Term& t) { return t.literal && (t.text == "0" || t.text == "0.0"); };
      if (!zero(a) && !zero(b)) {
        if (a.literal && !b.literal) return shown(b) + " <= " + shown(a);
        return shown(a) + " >= " + shown(b);
      }
    }
    if (o_.natural && n.op == Op::Neg) {  // -x >= 0 is x <= 0
      std::size_t c[1] = {0};
      e_.child_indices(i, std::span<std::size_t>(c, 1));
      return shown(term(c[0])) + " <= 0";
    }
    return shown(term(i)) + " >= 0";
  }

  Term term(std::size_t i) {
    const Node& n = e_.nodes[i];
    std::size_t c[3] = {0, 0, 0};
    if (n.arity > 0) e_.child_indices(i, std::span<std::size_t>(c, n.arity));
    switch (n.op) {
      case Op::Const:
      case Op::Param: {
        const std::optional<double> v = literal_of(n, e_, o_);
        if (!v) return leaf(e_.parameters.at(static_cast<std::size_t>(n.index)));
        if (std::isnan(*v)) return leaf(number(*v), false, true);
        return leaf(number(std::fabs(*v)), std::signbit(*v), true);
      }
      case Op::Var: return leaf(e_.variables.at(static_cast<std::size_t>(n.index)));
      case Op::Neg: {
        Term t = term(c[0]);
        if (t.abs_subtrahend && !t.negative) {  // -(b - |a|) is written |a| - b, as counted
          t.text = t.minus;
          t.minus = "-(" + t.text + ")";
          t.abs_subtrahend = false;
          return t;
        }
        t.negative = !t.negative;
        return t;
      }
      case Op::Add: return sum(term(c[0]), term(c[1]), false);
      case Op::Sub: return sum(term(c[0]), term(c[1]), true);
      case Op::Mul:
      case Op::Div: return product(term(c[0]), term(c[1]), n.op);
      case Op::IPow: {
        // (-a)^k = a^k for even k and -(a^k) for odd k, bit for bit (products of the operand).
        const Term a = term(c[0]);
        const bool bare = a.prec == kAtom;
        const std::string k = "^" + std::to_string(n.index);
        Term t{n.index % 2 != 0 && a.negative, paren(a.text, !bare) + k, kPower, "", false};
        t.minus = bare || n.index % 2 == 0 ? "-" + t.text : "(" + a.minus + ")" + k;
        return t;
      }
      case Op::Pow: {
        const Term k = term(c[1]);
        std::string exponent = shown(k);
        // An integer literal exponent would read back as the integer power; mark it real.
        if (k.literal && exponent.find_first_of(".en") == std::string::npos) exponent += ".0";
        return leaf("pow(" + shown(term(c[0])) + ", " + exponent + ")");
      }
      // The condition as the parser reads it back into the same operand (a literal 0 on the
      // right of >= adds no node); for people a difference is the comparison it came from,
      // x <= 0.5 for 0.5 - x >= 0, which the parser reads back into the same difference.
      case Op::Select:
        return leaf("select(" + condition(c[0]) + ", " + shown(term(c[1])) + ", " +
                    shown(term(c[2])) + ")");
      default: return call(n, c);
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
  // The value of a literal: a constant, or a parameter printed as its value, under any number of
  // negations (the text folds them: - -0 is written 0).
  const auto literal = [&](const Frag& f) -> std::optional<double> {
    if (f.size() > 1 && f[0].op == Op::Const &&
        std::all_of(f.begin() + 1, f.end(), [](const Node& n) { return n.op == Op::Neg; }))
      return f.size() % 2 == 0 ? -f[0].value : f[0].value;
    if (f.size() != 1) return std::nullopt;
    return literal_of(f[0], e, o);
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

// e as a person writes it (PrintOptions::natural): in each product (a tree of `*`), repeated
// factors as one power (`x * (x * y)` is `x^2 * y`, `x^2 * x` is `x^3`) and literal factors
// first (`c * x * y`); `exp2(c * x)` with c = log2(e) in float32 is `exp(x)` and `log2(x) * c`
// with c = ln(2) is `log(x)`. The instruction model counts the same for each (a power is its
// squaring chain of products; exp and log are exp2 and log2 with that product), and the value
// is equal up to float rounding (the products' order).
class Natural {
 public:
  Natural(const Expression& e, const PrintOptions& o) : e_(e), o_(o) {}

  Expression run() {
    Expression out = e_;
    out.nodes.clear();
    emit(e_.nodes.size() - 1, out.nodes);
    out.update_lengths();
    return out;
  }

 private:
  static constexpr float kLog2E = 1.44269504088896340736f, kLn2 = 0.693147180559945309417f;

  std::vector<std::size_t> children(std::size_t i) const {
    std::vector<std::size_t> c(e_.nodes[i].arity);
    if (!c.empty()) e_.child_indices(i, c);
    return c;
  }
  std::span<const Node> nodes_of(std::size_t i) const {
    return {e_.nodes.data() + e_.subtree_begin(i), e_.nodes[i].length + 1};
  }
  bool same(std::size_t a, std::size_t b) const {
    const auto x = nodes_of(a), y = nodes_of(b);
    return std::equal(x.begin(), x.end(), y.begin(), y.end());
  }
  bool is_literal(std::size_t i) const { return literal_of(e_.nodes[i], e_, o_).has_value(); }
  double literal_value(std::size_t i) const { return *literal_of(e_.nodes[i], e_, o_); }
  // Within two float32 steps of v: a fitted or hand-written constant that means v.
  bool literal_reads(std::size_t i, float v) const {
    if (!is_literal(i)) return false;
    const float a = std::fabs(static_cast<float>(literal_value(i)));
    return std::fabs(a - v) <= 2 * (std::nextafter(v, 2 * v) - v);
  }

  // The factors of the product at i, in order, each once with its power.
  struct Factor {
    std::size_t node;
    int power;
  };
  // The products x^k takes (k > 0), its squaring chain: merged only where it is one fewer than
  // the two powers' and their product, so that the count stays (x * x^3 is not x^4).
  static int products(int k) {
    return std::bit_width(static_cast<unsigned>(k)) + std::popcount(static_cast<unsigned>(k)) - 2;
  }

  // How often the subtree at i occurs in the formula (the instruction model computes it once).
  int occurrences(std::size_t i) const {
    int n = 0;
    for (std::size_t j = 0; j < e_.nodes.size(); ++j)
      n += e_.nodes[j].length == e_.nodes[i].length && same(i, j);
    return n;
  }

  // A negated factor (but a sum) counts as its operand, the sign kept in `negative`; a product that
  // occurs elsewhere stays one factor, so that its value is still computed once.
  //
  // The left operands of a chain of products are its factors as written (a * b * c); a product
  // on the right, a group as written (a * (b * c)), is taken apart only where a factor of it
  // repeats one before it or it holds the literal being dropped: its grouping may be what makes
  // part of it once per material, which the instruction model counts.
  void factors(std::size_t i, std::vector<Factor>& out, bool& negative, bool root = true) const {
    const Node& n = e_.nodes[i];
    // Shared: found more often than the product being gathered (`root_`), whose own copies
    // hold it too.
    if (root) root_ = i;
    if (n.op == Op::Mul) {  // a * a is a^2, whatever a is (one product either way)
      const std::vector<std::size_t> c = children(i);
      if (same(c[0], c[1]) && !is_literal(c[0])) {
        out.push_back({c[0], 2});
        return;
      }
    }
    if (n.op == Op::Mul && (root || occurrences(i) <= occurrences(root_))) {
      const std::vector<std::size_t> c = children(i);
      factors(c[0], out, negative, false);
      if (e_.nodes[c[1]].op == Op::Mul && !opens(c[1], out)) {
        out.push_back({c[1], 1});
        return;
      }
      factors(c[1], out, negative, false);
      return;
    }
    // A negated sum stays a factor: the printer writes -(b - a) as a - b, as counted.
    if (n.op == Op::Neg && e_.nodes[children(i)[0]].op != Op::Add &&
        e_.nodes[children(i)[0]].op != Op::Sub) {
      negative = !negative;
      factors(children(i)[0], out, negative, false);
      return;
    }
    std::size_t base = i;
    int power = 1;
    if (n.op == Op::IPow && n.index > 0) {
      base = children(i)[0];
      power = n.index;
    }
    for (Factor& f : out)
      if (f.power > 0 && same(f.node, base) && f.power + power <= kMaxIntegerPower &&
          !is_literal(base) &&
          products(f.power + power) == products(f.power) + products(power) + 1) {
        f.power += power;
        return;
      }
    out.push_back({base, power});
  }

  // Whether the product group at i is taken apart in a product whose factors so far are `before`.
  bool opens(std::size_t i, const std::vector<Factor>& before) const {
    std::vector<Factor> inner;
    bool negative = false;
    const std::size_t outer = root_;
    factors(i, inner, negative);
    root_ = outer;
    for (const Factor& f : inner) {
      if (drop_ != 0 && f.power == 1 && literal_reads(f.node, drop_)) return true;
      if (is_literal(f.node)) continue;
      for (const Factor& b : before)
        if (same(b.node, f.node)) return true;
    }
    return false;
  }

  // The product at i (a Mul node) rebuilt: literals first, then the other factors in the order
  // they first appear, each with its power; one literal reading `drop` (if any) left out, and
  // the factor at node `log` (a log2) written as log.
  void product(std::size_t i, std::vector<Node>& out, float drop = 0,
               std::size_t log = static_cast<std::size_t>(-1)) {
    std::vector<Factor> fs;
    bool negative = false;
    drop_ = drop;
    factors(i, fs, negative);
    drop_ = 0;
    std::stable_partition(fs.begin(), fs.end(),
                          [&](const Factor& f) { return is_literal(f.node); });
    bool dropped = false, first = true;
    for (const Factor& f : fs) {
      if (!dropped && drop != 0 && f.power == 1 && literal_reads(f.node, drop)) {
        dropped = true;
        if (std::signbit(literal_value(f.node))) {
          out.push_back(Node::constant(-1.0));  // shown as a sign: -1 * x is written -x
          if (!first) out.push_back(Node::op_node(Op::Mul));
          first = false;
        }
        continue;
      }
      if (f.node == log) {
        emit(children(log)[0], out);
        out.push_back(Node::op_node(Op::Log));
      } else {
        emit(f.node, out);
        if (f.power != 1) out.push_back(Node::ipow(f.power));
      }
      if (!first) out.push_back(Node::op_node(Op::Mul));
      first = false;
    }
    if (first) out.push_back(Node::constant(1.0));
    if (negative) out.push_back(Node::op_node(Op::Neg));
  }

  // Whether the product at i has a literal factor reading `v` (either sign).
  bool has_literal(std::size_t i, float v) {
    if (e_.nodes[i].op != Op::Mul) return false;
    std::vector<Factor> fs;
    bool negative = false;
    drop_ = v;
    factors(i, fs, negative);
    drop_ = 0;
    return std::any_of(fs.begin(), fs.end(),
                       [&](const Factor& f) { return f.power == 1 && literal_reads(f.node, v); });
  }

  void emit(std::size_t i, std::vector<Node>& out) {
    const Node& n = e_.nodes[i];
    const std::vector<std::size_t> c = children(i);
    if (n.op == Op::Exp2) {  // exp2(log2(e) * x) = exp(x), and exp2(-(log2(e) * x)) = exp(-x)
      const bool negated = e_.nodes[c[0]].op == Op::Neg;
      const std::size_t arg = negated ? children(c[0])[0] : c[0];
      if (has_literal(arg, kLog2E)) {
        product(arg, out, kLog2E);
        if (negated) out.push_back(Node::op_node(Op::Neg));
        out.push_back(Node::op_node(Op::Exp));
        return;
      }
    }
    if (n.op == Op::Mul) {
      // log2(x) * ln(2) = log(x), the rest of the product kept.
      std::vector<Factor> fs;
      bool negative = false;
      factors(i, fs, negative);
      for (const Factor& f : fs)
        if (f.power == 1 && e_.nodes[f.node].op == Op::Log2 && has_literal(i, kLn2)) {
          product(i, out, kLn2, f.node);
          return;
        }
      product(i, out);
      return;
    }
    for (std::size_t k : c) emit(k, out);
    out.push_back(n);
  }

  const Expression& e_;
  const PrintOptions& o_;
  float drop_ = 0;                // the literal product() leaves out, while it gathers the factors
  mutable std::size_t root_ = 0;  // the product whose factors factors() gathers
};

}  // namespace

std::string to_infix(const Expression& e, const PrintOptions& options) {
  if (e.nodes.empty()) return "";
  Expression shown = without_neutral_text(e, options);
  if (options.natural) shown = without_neutral_text(Natural(shown, options).run(), options);
  return InfixPrinter(shown, options).print(shown.nodes.size() - 1);
}

std::string to_latex(const Expression& e, const PrintOptions& options) {
  if (e.nodes.empty()) return "";
  Expression shown = without_neutral_text(e, options);
  if (options.natural) shown = without_neutral_text(Natural(shown, options).run(), options);
  return LatexPrinter(shown, options).text(shown.nodes.size() - 1);
}

}  // namespace shaderfit
