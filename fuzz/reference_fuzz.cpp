// Fuzz target: a reference formula as users type it (--reference, --define), the lines before
// the last being definitions "name = formula". The compile must succeed or throw
// shaderfit::Error, and what it makes must be well-formed (program_checks.hpp). Every formula
// the approximation's parser reads must compile here too (the reference language is a superset)
// (but for a text that is a built-in reference's name) and, where no operator of different
// meaning is involved, mean the same.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "fuzz_targets.hpp"
#include "program_checks.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/reference/builtin.hpp"

namespace shaderfit::fuzz {

namespace {

// pow (C's here, exp2(b log2 a) there), select (comparisons here, differences there), and the
// functions that absorb a NaN operand (saturate, min, max, copysign) may differ.
bool means_the_same_here(const Expression& e) {
  for (const Node& n : e.nodes) {
    if (n.op == Op::Pow || n.op == Op::Select || n.op == Op::Saturate || n.op == Op::Min ||
        n.op == Op::Max || n.op == Op::CopySign)
      return false;
  }
  return true;
}

void check_superset(std::string_view text) {
  // The one exception: a text that is a built-in reference's name ("fresnel-exact", or
  // "fresnel_exact") calls it.
  for (const shaderfit::reference::BuiltinFunction& f : shaderfit::reference::builtin_functions()) {
    std::string_view t = text;
    while (!t.empty() && std::isspace(static_cast<unsigned char>(t.front())) != 0)
      t.remove_prefix(1);
    while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back())) != 0)
      t.remove_suffix(1);
    std::string underscores(f.name);
    std::replace(underscores.begin(), underscores.end(), '-', '_');
    if (t == f.name || t == underscores) return;
  }
  Expression e;
  try {
    e = parse_formula(text);
  } catch (const Error&) {
    return;
  }
  shaderfit::reference::ReferenceText t;
  t.formula = std::string(text);
  t.variables = e.variables;
  shaderfit::reference::Program p;
  try {
    p = shaderfit::reference::compile_reference(t);
  } catch (const Error& err) {
    // A variable named like the reference's own output is the one name the language keeps.
    if (err.message().find("names the reference's own output") != std::string::npos) return;
    throw FuzzFailure("'" + std::string(text) +
                      "' parses as an approximation, not as a reference: " + err.what());
  }
  if (!means_the_same_here(e)) return;
  for (const double v : {0.0, 0.5, -1.25, 3.0}) {
    const std::vector<double> point(e.variables.size(), v);
    const double want = evaluate_scalar(e, point);
    if (!std::isfinite(want)) continue;
    const double got = p.evaluate(point);
    if (got != want) {
      throw FuzzFailure("'" + std::string(text) + "' at " + std::to_string(v) + ": " +
                        std::to_string(got) + " as a reference, " + std::to_string(want) +
                        " as an approximation");
    }
  }
}

}  // namespace

void reference(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = as_text(data, size);
  shaderfit::reference::ReferenceText t;
  std::size_t start = 0;
  while (true) {
    const std::size_t newline = text.find('\n', start);
    if (newline == std::string_view::npos) break;
    t.definitions.emplace_back(text.substr(start, newline - start));
    start = newline + 1;
  }
  t.formula = std::string(text.substr(start));
  try {
    check_program(shaderfit::reference::compile_reference(t));
  } catch (const Error&) {
    // The expected outcome for bad input.
  }
  try {
    (void)shaderfit::reference::evaluate_constant(t.formula, "constant");
  } catch (const Error&) {
  }
  if (t.definitions.empty()) check_superset(text);
}

}  // namespace shaderfit::fuzz

SHADERFIT_FUZZ_ENTRY(reference)
