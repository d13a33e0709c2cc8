// Fuzz target: the command-line options that carry their own small languages. The first byte
// picks the parser (the seed files start with the letter in brackets), the rest is the option's
// text:
//   [m] --material (fit, plot)      [o] --ops (search)            [s] --domain (fit)
//   [g] --grid (fit)                [d] --define (fit)            [c] --constraint (fit)
//   [k] --cond (rational)           [f] --form (rational)         [t] --transform (rational)
// Each parse must succeed or throw shaderfit::Error; what a parse returns is then used the way
// the commands use it, and printed forms that are documented to read back must read back.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "fuzz_targets.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/data/fresnel_sweep.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/fit/constraint.hpp"
#include "shaderfit/fit/fit_blocks.hpp"
#include "shaderfit/rational/condition.hpp"
#include "shaderfit/rational/rational_function.hpp"
#include "shaderfit/rational/target.hpp"
#include "shaderfit/reference/domain.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit::fuzz {

namespace {

void material(std::string_view text) {
  const Material m = parse_material(text);
  // The name is the seed data set's label, which parse_material reads back (fresnel_sweep.hpp).
  const Material again = parse_material(m.name);
  if (again.n != m.n || again.k != m.k)
    throw FuzzFailure("material label '" + m.name + "' reads back as another material");
}

void operators(std::string_view text) {
  const std::vector<Op> ops = parse_operator_list(text);
  const std::string name = operator_list_name(ops);
  if (parse_operator_list(name) != ops)
    throw FuzzFailure("operator list '" + name + "' reads back differently");
}

void sample_axis(std::string_view text) {
  const reference::DomainAxis a = reference::parse_domain_axis(text, "--domain");
  for (std::size_t i = 0; i < std::min<std::size_t>(a.count, 4); ++i) (void)a.at(i);
  if (a.count > 0) (void)a.at(a.count - 1);
}

void grid_axis(std::string_view text) {
  const GridAxis g = parse_grid_axis(text, "--grid");
  for (std::size_t i = 0; i < std::min<std::size_t>(g.cells, 4); ++i) (void)g.cell_of(g.centre(i));
  (void)g.cell_of(g.centre(g.cells - 1));
  (void)g.cell_of(g.lo);
  (void)g.cell_of(g.hi);
}

void definition(std::string_view text) {
  // As `fit --domain theta=... --grid roughness=... --define "dot = cos(theta)"` uses it: a
  // derived column evaluated over a small sampled grid.
  reference::ReferenceText t;
  t.formula = "0";
  t.variables = {"roughness", "theta"};
  t.definitions = {std::string(text)};
  const reference::Program p = reference::compile_reference(t);
  const GridAxis grid{"roughness", 0.0, 1.0, 2, false};
  reference::DomainAxis domain;
  domain.name = "theta";
  domain.lo = 0.0;
  domain.hi = 1.5;
  domain.count = 3;
  Rng rng(1);
  for (GridCell& c : sample_grid({grid}, {domain}, 0, 0, rng)) (void)add_program_columns(c.data, p);
}

void constraint(std::string_view text) {
  ParseOptions po;
  po.variables = {"x", "cos_theta"};
  po.parameters = {"A", "B", "s"};
  const Expression formula = parse_formula("A + (1 - A - s*cos_theta) * x^4 + B", po);
  (void)parse_constraint(text, formula, "--constraint");
}

void condition(std::string_view text) {
  const rational::Condition c = rational::parse_condition(text, {"F0"});
  (void)rational::condition_text(c);
  // What `rational` then computes for a condition: the reference's value, derivatives or integral
  // at the condition's point, and the condition's own value.
  const auto target = rational::Target::builtin("fresnel-schlick");
  const std::array<double, 1> params = {0.04};
  if (c.order < 0 || c.order > rational::kMaxDerivativeOrder)
    throw FuzzFailure("condition '" + std::string(text) + "' has order " + std::to_string(c.order));
  if (c.is_integral()) {
    (void)target.integral(c.a, c.b, params);
  } else {
    (void)target.derivatives(c.a, c.order, params);
  }
}

void form(std::string_view text) {
  const rational::RationalForm f = rational::parse_form(text);
  (void)f.name("x");
}

void transform(std::string_view text) {
  const rational::Transform t = rational::Transform::parse(text, "cos");
  // The transform's printed text must read back as the same kind of formula.
  (void)t.expression("cos");
  (void)t.text("cos");
}

}  // namespace

void options(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return;
  const std::string_view text = as_text(data + 1, size - 1);
  try {
    switch (data[0]) {
      case 'm': material(text); break;
      case 'o': operators(text); break;
      case 's': sample_axis(text); break;
      case 'g': grid_axis(text); break;
      case 'd': definition(text); break;
      case 'c': constraint(text); break;
      case 'k': condition(text); break;
      case 'f': form(text); break;
      case 't': transform(text); break;
      default: break;  // not a parser: nothing to do
    }
  } catch (const Error&) {
    // the expected outcome for bad input
  }
}

}  // namespace shaderfit::fuzz

SHADERFIT_FUZZ_ENTRY(options)
