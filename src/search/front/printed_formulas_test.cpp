// Every member of real fronts (acos, erf, Burley and Henyey-Greenstein as their shader files,
// ten yardstick cases and ten AI-Feynman equations, kept in testdata/printed_fronts.json by
// bench/printed_fronts.py) and of random formulas, printed for people and read back: no text
// shows a sign twice, a negated group after an operator or a variable times itself, and what
// it reads is the same function (equal up to float rounding at 10,000 points of the inputs'
// ranges) at the same instruction count.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "expr/random_expression_test_util.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/expr/simplify.hpp"

namespace shaderfit {
namespace {

// The rules a printed formula keeps; an empty string where it keeps them all.
std::string broken_rule(const std::string& text) {
  for (const char* never : {"* -", "/ -", "- -", "+ -"})
    if (text.find(never) != std::string::npos) return std::string("'") + never + "'";
  for (std::size_t at = text.find("-("); at != std::string::npos; at = text.find("-(", at + 1)) {
    std::size_t k = at;
    if (k > 0 && text[k - 1] == ' ') --k;
    if (k == 0 || std::string_view("+-*/(,^").find(text[k - 1]) != std::string_view::npos)
      return "'-(' after an operator or opening a factor";
  }
  return "";
}

// The factors of the product at node i (a tree of *), each a subtree's root.
void factors(const Expression& e, std::size_t i, std::vector<std::size_t>& out) {
  if (e.nodes[i].op != Op::Mul) {
    out.push_back(i);
    return;
  }
  std::size_t c[2];
  e.child_indices(i, c);
  factors(e, c[0], out);
  factors(e, c[1], out);
}

// The products x^k takes (k > 0) by its squaring chain.
int products(int k) {
  return std::bit_width(static_cast<unsigned>(k)) + std::popcount(static_cast<unsigned>(k)) - 2;
}

// Whether some product multiplies a variable by itself where one power would count the same
// (x * x, x * (x * y), x^2 * x; not x * x^3, which x^4 computes in fewer products).
bool variable_times_itself(const Expression& e) {
  for (std::size_t i = 0; i < e.nodes.size(); ++i) {
    if (e.nodes[i].op != Op::Mul) continue;
    std::vector<std::size_t> fs;
    factors(e, i, fs);
    std::map<int, int> power;
    for (std::size_t f : fs) {
      std::size_t base = f;
      int k = 1;
      if (e.nodes[f].op == Op::IPow && e.nodes[f].index > 0) {
        base = f - 1;
        k = e.nodes[f].index;
      }
      if (e.nodes[base].op != Op::Var) continue;
      int& p = power[e.nodes[base].index];
      if (p > 0 && products(p + k) == products(p) + products(k) + 1) return true;
      p += k;
    }
  }
  return false;
}

// Float32 values equal up to rounding: within 64 float32 steps of the larger of the value and
// the values' mean magnitude (products taken in another order, exp for exp2(log2(e) * x)), or
// within 4 times float32's own error at that point (`exact`: the value in double) where the
// formula cancels.
bool close(float a, float b, double scale, double exact) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (std::isinf(a) || std::isinf(b)) return a == b;
  const double tol = 64 * 0x1p-24 * std::max<double>(std::fabs(a), scale) +
                     4 * std::fabs(static_cast<double>(a) - exact);
  return std::fabs(static_cast<double>(a) - b) <= tol;
}

struct Checked {
  int members = 0, broken = 0, different = 0, costlier = 0;
};

void check_member(const std::string& where, const Expression& e,
                  const std::vector<std::vector<float>>& points,
                  const std::vector<std::string>& uniform, Checked& tally) {
  ++tally.members;
  const std::string text = to_infix(e, PrintOptions::for_people());
  // -(|a| - b) is the one negated group a sign cannot enter at the same cost (print.hpp).
  const std::string rule = text.find("-(abs(") == std::string::npos ? broken_rule(text) : "";
  ParseOptions o;
  o.variables = e.variables;
  const Expression back = parse_formula(text, o);
  if (!rule.empty() || variable_times_itself(back)) {
    ++tally.broken;
    ADD_FAILURE() << where << ": " << text << " (" << (rule.empty() ? "x * x" : rule) << ")";
  }
  const double cost = expression_cost(e, CostTarget::Instructions, uniform),
               cost_back = expression_cost(back, CostTarget::Instructions, uniform);
  if (cost != cost_back) {
    ++tally.costlier;
    ADD_FAILURE() << where << ": " << to_infix(e) << " costs " << cost << ", printed " << text
                  << " costs " << cost_back;
  }
  std::vector<float> want(points.size()), got(points.size());
  double scale = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    want[p] = testing::eval_reference(e, points[p]);
    got[p] = testing::eval_reference(back, points[p]);
    if (std::isfinite(want[p])) scale += std::fabs(want[p]) / static_cast<double>(points.size());
  }
  for (std::size_t p = 0; p < points.size(); ++p)
    if (!close(
            want[p], got[p], scale,
            testing::eval_reference(e, std::vector<double>(points[p].begin(), points[p].end())))) {
      ++tally.different;
      ADD_FAILURE() << where << ": " << to_infix(e) << " printed " << text << " is " << got[p]
                    << " where it is " << want[p];
      break;
    }
}

TEST(PrintedFormulas, RealFrontsReadBackToTheSameFunctionAtTheSameCost) {
  std::ifstream in(std::string(SHADERFIT_SOURCE_DIR) +
                   "/src/search/front/testdata/printed_fronts.json");
  ASSERT_TRUE(in) << "testdata/printed_fronts.json (bench/printed_fronts.py writes it)";
  const nlohmann::json corpus = nlohmann::json::parse(in);
  Checked tally;
  int fronts = 0, exact_text_cost_other = 0;
  for (const auto& c : corpus.at("cases")) {
    ++fronts;
    std::vector<std::string> inputs;
    std::vector<std::pair<double, double>> ranges;
    for (const auto& [name, r] : c.at("ranges").items()) {
      inputs.push_back(name);
      ranges.emplace_back(r.at(0).get<double>(), r.at(1).get<double>());
    }
    const auto per_material = c.at("uniform").get<std::vector<std::string>>();
    Rng rng(7);
    std::vector<std::vector<float>> points(10000, std::vector<float>(inputs.size()));
    for (auto& p : points)
      for (std::size_t k = 0; k < inputs.size(); ++k)
        p[k] = static_cast<float>(uniform(rng, ranges[k].first, ranges[k].second));
    for (const auto& m : c.at("members")) {
      ParseOptions o;
      o.variables = inputs;
      const Expression e = parse_formula(m.at("formula").get<std::string>(), o);
      const std::string where = c.at("case").get<std::string>();
      // The JSON's exact text reads back at its member's cost (the search counts each member
      // as its text reads: search/front/tidy.hpp, count_as_printed).
      if (const double read = expression_cost(e, CostTarget::Instructions, per_material);
          read != m.at("cost").get<double>()) {
        ++exact_text_cost_other;
        std::printf("%s: %s reads back at %g, the member's cost %g\n", where.c_str(),
                    m.at("formula").get<std::string>().c_str(), read, m.at("cost").get<double>());
      }
      check_member(where, e, points, per_material, tally);
    }
  }
  EXPECT_GE(fronts, 20);
  EXPECT_GE(tally.members, 200);
  EXPECT_EQ(exact_text_cost_other, 0);
  std::printf(
      "%d members of %d fronts: %d break a rule, %d read back different, %d cost other "
      "(%d exact texts at another cost than their member's)\n",
      tally.members, fronts, tally.broken, tally.different, tally.costlier, exact_text_cost_other);
}

TEST(PrintedFormulas, RandomFormulasReadBackToTheSameFunctionAtTheSameCost) {
  Rng rng(42);
  const std::vector<std::string> vars = {"x", "y"};
  std::vector<std::vector<float>> points(1000, std::vector<float>(2));
  for (auto& p : points)
    for (float& v : p) v = static_cast<float>(uniform(rng, 0.05, 1.0));
  Checked tally;
  // Formulas of the searches' operators: the arithmetic, powers, exp2/log2 and their scales.
  const Op ops[] = {Op::Add, Op::Sub,  Op::Mul,  Op::Mul,  Op::Mul,  Op::Div,
                    Op::Neg, Op::IPow, Op::Sqrt, Op::Exp2, Op::Log2, Op::Abs};
  const double literals[] = {
      0.5, 2, -1.5, 1.4426950408889634, -1.4426950408889634, 0.6931471805599453, 3.25};
  for (int i = 0; i < 400; ++i) {
    Expression e;
    e.variables = vars;
    // No part without an input: a search's formulas have their constant parts folded.
    const std::function<bool(int)> grow = [&](int depth) {
      if (depth == 0 || bernoulli(rng, 0.3)) {
        const bool input = bernoulli(rng, 0.6);
        if (input)
          e.nodes.push_back(Node::variable(static_cast<int>(uniform_index(rng, 2))));
        else
          e.nodes.push_back(Node::constant(literals[uniform_index(rng, std::size(literals))]));
        return input;
      }
      const std::size_t begin = e.nodes.size();
      const Op op = ops[uniform_index(rng, std::size(ops))];
      bool input = false;
      for (int k = 0; k < arity(op); ++k) input = grow(depth - 1) || input;
      e.nodes.push_back(op == Op::IPow ? Node::ipow(2 + static_cast<int>(uniform_index(rng, 3)))
                                       : Node::op_node(op));
      if (!input) {
        e.nodes.resize(begin);
        e.nodes.push_back(Node::variable(static_cast<int>(uniform_index(rng, 2))));
      }
      return true;
    };
    grow(2 + i % 4);
    e.update_lengths();
    e = simplify(e, {.regroup_constants = true});  // as the search leaves its fronts
    check_member("random " + to_infix(e), e, points, {}, tally);
  }
  std::printf("%d random formulas: %d break a rule, %d read back different, %d cost other\n",
              tally.members, tally.broken, tally.different, tally.costlier);
}

}  // namespace
}  // namespace shaderfit
