#include "shaderfit/fit/fixed_form.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {
namespace {

Expression formula(const char* text, std::vector<std::string> vars,
                   std::vector<std::string> params) {
  ParseOptions po;
  po.variables = std::move(vars);
  po.parameters = std::move(params);
  return parse_formula(text, po);
}

// x at n midpoints of [0, 1]; y = f(x).
template <typename F>
FitBlock block_of(F f, std::size_t n = 64, std::string label = "all") {
  FitBlock b;
  b.label = std::move(label);
  b.columns.resize(1);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    b.columns[0].push_back(x);
    b.target.push_back(f(x));
  }
  return b;
}

FixedFormSummary solve(const FixedFormProblem& p, FixedFormOptions o = {}) {
  FixedFormSummary s;
  solve_fixed_form(o, p, &s);
  return s;
}

TEST(FixedForm, LinearLeastSquaresRecoversAPolynomial) {
  FixedFormProblem p;
  p.formula = formula("a + b*x + c*x^2", {"x"}, {"a", "b", "c"});
  p.blocks.push_back(block_of([](double x) { return 2 + 3 * x - x * x; }));
  const FixedFormSummary s = solve(p);
  ASSERT_EQ(s.failed_blocks, 0u) << s.brief_report();
  EXPECT_TRUE(s.linear);
  EXPECT_NEAR(s.blocks[0].parameters[0], 2, 1e-12);
  EXPECT_NEAR(s.blocks[0].parameters[1], 3, 1e-12);
  EXPECT_NEAR(s.blocks[0].parameters[2], -1, 1e-12);
  EXPECT_NE(s.brief_report().find("linear least squares"), std::string::npos);
}

TEST(FixedForm, ReportsBlocksFittedSoFar) {
  FixedFormProblem p;
  p.formula = formula("a * x", {"x"}, {"a"});
  p.scopes = {ParameterScope::per_block};
  for (int k = 1; k <= 5; ++k) p.blocks.push_back(block_of([k](double x) { return k * x; }));
  FixedFormOptions o;
  o.threads = 1;
  std::vector<std::size_t> seen;
  o.on_progress = [&](const Progress& q) {
    EXPECT_EQ(q.total, 5u);
    seen.push_back(q.done);
  };
  const FixedFormSummary s = solve(p, o);
  EXPECT_EQ(s.failed_blocks, 0u);
  EXPECT_EQ(seen, (std::vector<std::size_t>{1, 2, 3, 4, 5}));
}

// The seed's model: f0 exp2(A x^2 + B x + C) is linear in A, B, C after log2.
FixedFormProblem seed_problem(double f0, double a, double b, double c) {
  FixedFormProblem p;
  p.formula = formula("f0 * exp2(A*x^2 + B*x + C)", {"f0", "x"}, {"A", "B", "C"});
  FitBlock blk = block_of(
      [&](double x) { return f0 * std::exp2(a * x * x + b * x + c) * (1 + 0.05 * x * x * x); });
  blk.columns.insert(blk.columns.begin(), std::vector<double>(blk.target.size(), f0));
  blk.context = {{"f0", f0}};  // what f(x = 0) = f0 reads
  p.blocks.push_back(blk);
  return p;
}

TEST(FixedForm, LogLossAndNamedTransformAgreeAndAreLinear) {
  FixedFormProblem p = seed_problem(0.04, 3.0, 1.5, 0.2);
  FixedFormOptions log;
  log.loss = Loss::Log;
  log.solver = SolverKind::linear;
  const FixedFormSummary a = solve(p, log);
  p.transform = parse_formula("log2(y / f0)", {.variables = {"y", "f0"}});
  const FixedFormSummary b = solve(p);
  EXPECT_TRUE(a.linear);
  EXPECT_TRUE(b.linear);
  for (int j = 0; j < 3; ++j)
    EXPECT_NEAR(a.blocks[0].parameters[j], b.blocks[0].parameters[j], 1e-9);
  EXPECT_GT(a.blocks[0].final_cost, 0);
  EXPECT_LT(a.blocks[0].final_cost, 1e-3);
}

TEST(FixedForm, ParameterConstraintHoldsExactlyAndEqualsTheValueConstraint) {
  FixedFormProblem p = seed_problem(0.04, 3.0, 1.5, 0.2);
  FixedFormOptions o;
  o.loss = Loss::Log;
  p.constraints.push_back(parse_constraint("C = 0", p.formula));
  const FixedFormSummary a = solve(p, o);
  EXPECT_TRUE(a.linear);
  EXPECT_EQ(a.blocks[0].parameters[2], 0.0);
  // FV(x = 0) = f0: the same constraint through the formula's value (nonlinear in C: LM).
  p.constraints = {parse_constraint("f(x = 0) = f0", p.formula)};
  const FixedFormSummary b = solve(p, o);
  EXPECT_FALSE(b.linear);
  EXPECT_NEAR(b.blocks[0].parameters[2], 0.0, 1e-9);
  EXPECT_NEAR(b.blocks[0].parameters[0], a.blocks[0].parameters[0], 1e-6);
  EXPECT_NEAR(b.blocks[0].parameters[1], a.blocks[0].parameters[1], 1e-6);
}

TEST(FixedForm, DerivativeConstraint) {
  FixedFormProblem p;
  p.formula = formula("a + b*x + c*x^2", {"x"}, {"a", "b", "c"});
  p.blocks.push_back(block_of([](double x) { return std::exp(x); }));
  p.constraints.push_back(parse_constraint("df/dx(x = 0.5) = 2", p.formula));
  const FixedFormSummary s = solve(p);
  const auto& q = s.blocks[0].parameters;
  EXPECT_TRUE(s.linear);
  EXPECT_NEAR(q[1] + 2 * q[2] * 0.5, 2.0, 1e-9);
}

TEST(FixedForm, MinimaxLineThroughAParabola) {
  // The best uniform approximation of x^2 on [0, 1] by a line is x - 1/8, error 1/8.
  FixedFormProblem p;
  p.formula = formula("a + b*x", {"x"}, {"a", "b"});
  FitBlock b;
  b.columns.resize(1);
  for (int i = 0; i <= 400; ++i) {
    b.columns[0].push_back(i / 400.0);
    b.target.push_back(i / 400.0 * i / 400.0);
  }
  p.blocks.push_back(b);
  FixedFormOptions o;
  o.loss = Loss::MaxAbs;
  const FixedFormSummary s = solve(p, o);
  EXPECT_NEAR(s.blocks[0].parameters[0], -0.125, 1e-3);
  EXPECT_NEAR(s.blocks[0].parameters[1], 1.0, 1e-3);
  EXPECT_NEAR(s.blocks[0].max_abs, 0.125, 1e-3);
  EXPECT_NEAR(s.blocks[0].final_cost, s.blocks[0].max_abs, 1e-12);
}

TEST(FixedForm, LevenbergMarquardtOnANonlinearFormula) {
  FixedFormProblem p;
  p.formula = formula("a * exp(b * x)", {"x"}, {"a", "b"});
  p.formula.parameter_values = {1.0, 1.0};
  p.blocks.push_back(block_of([](double x) { return 0.7 * std::exp(-2.5 * x); }));
  const FixedFormSummary s = solve(p);
  EXPECT_FALSE(s.linear);
  EXPECT_NEAR(s.blocks[0].parameters[0], 0.7, 1e-8);
  EXPECT_NEAR(s.blocks[0].parameters[1], -2.5, 1e-8);
}

TEST(FixedForm, PerBlockAndGlobalParametersTogether) {
  // y = s_b x + 0.5 x^2: s one value per block, k shared.
  FixedFormProblem p;
  p.formula = formula("s*x + k*x^2", {"x"}, {"s", "k"});
  p.scopes = {ParameterScope::per_block, ParameterScope::global};
  for (double sb : {1.0, -2.0, 0.25})
    p.blocks.push_back(
        block_of([&](double x) { return sb * x + 0.5 * x * x; }, 32, "s=" + std::to_string(sb)));
  const FixedFormSummary s = solve(p);
  EXPECT_TRUE(s.coupled);
  EXPECT_NEAR(*s.global("k"), 0.5, 1e-10);
  EXPECT_NEAR(s.blocks[1].parameters[0], -2.0, 1e-10);
  EXPECT_NEAR(s.blocks[2].parameters[0], 0.25, 1e-10);
  // A constraint on the global parameter holds exactly in the joint solve, LM too.
  p.constraints.push_back(parse_constraint("k = 0.4", p.formula));
  FixedFormOptions lm;
  lm.solver = SolverKind::levenberg_marquardt;
  const FixedFormSummary c = solve(p, lm);
  EXPECT_NEAR(*c.global("k"), 0.4, 1e-12);
}

TEST(FixedForm, AFailingBlockIsReportedNotFilled) {
  FixedFormProblem p;
  p.formula = formula("a + b*x", {"x"}, {"a", "b"});
  p.scopes = {ParameterScope::per_block, ParameterScope::per_block};
  p.blocks.push_back(block_of([](double x) { return 1 + x; }, 16, "good"));
  FitBlock flat = block_of([](double) { return 1.0; }, 16, "cell (3, 4)");
  std::fill(flat.columns[0].begin(), flat.columns[0].end(), 0.0);  // b has no effect here
  p.blocks.push_back(flat);
  const FixedFormSummary s = solve(p);
  EXPECT_EQ(s.failed_blocks, 1u);
  EXPECT_TRUE(s.blocks[0].ok);
  EXPECT_FALSE(s.blocks[1].ok);
  EXPECT_NE(s.blocks[1].failure.find("singular"), std::string::npos);
  EXPECT_NE(s.brief_report().find("failed: cell (3, 4): singular"), std::string::npos)
      << s.brief_report();
}

void expect_error(const FixedFormProblem& p, const std::string& text, FixedFormOptions o = {}) {
  try {
    FixedFormSummary s;
    solve_fixed_form(o, p, &s);
    ADD_FAILURE() << "no error; expected " << text;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

TEST(FixedForm, BadInput) {
  FixedFormProblem p;
  p.formula = formula("a + b*x", {"x"}, {"a", "b"});
  p.blocks.push_back(block_of([](double x) { return x; }));
  FixedFormProblem none = p;
  none.formula = formula("x^2", {"x"}, {});
  expect_error(none, "has no free parameters");
  FixedFormProblem contradiction = p;
  contradiction.constraints = {parse_constraint("a = 0", p.formula),
                               parse_constraint("a = 1", p.formula)};
  expect_error(contradiction, "constraint 'a = 1' contradicts 'a = 0'");
  FixedFormProblem singular = p;
  singular.formula = formula("a*x + b*x", {"x"}, {"a", "b"});
  expect_error(singular, "singular system");
  FixedFormProblem negative = p;
  negative.blocks[0].weights.assign(negative.blocks[0].target.size(), 1.0);
  negative.blocks[0].weights[2] = -1;
  expect_error(negative, "weight -1 in row 3 of block 'all' is negative");
  FixedFormOptions bad;
  bad.max_iterations = 0;
  expect_error(p, "max_iterations", bad);
  FixedFormOptions lin;
  lin.solver = SolverKind::linear;
  FixedFormProblem nonlinear = p;
  nonlinear.formula = formula("exp(a*x)", {"x"}, {"a"});
  expect_error(nonlinear, "not linear", lin);
}

TEST(FixedForm, LossesTheFitDoesNotMinimiseAreRefused) {
  FixedFormProblem p;
  p.formula = formula("a + b*x", {"x"}, {"a", "b"});
  p.blocks.push_back(block_of([](double x) { return x; }));
  for (Loss loss : {Loss::Rmse, Loss::MaxRel, Loss::Relative}) {
    FixedFormOptions o;
    o.loss = loss;
    std::string why;
    EXPECT_FALSE(o.is_valid(&why));
    FixedFormSummary s;
    try {
      solve_fixed_form(o, p, &s);
      FAIL() << loss_name(loss);
    } catch (const Error& e) {
      EXPECT_EQ(e.where().source, "FixedFormOptions::loss") << e.what();
    }
  }
}

TEST(FixedForm, SubstituteVariable) {
  const Expression outer = parse_formula("log2(y / f0)", {.variables = {"y", "f0"}});
  const Expression inner = formula("f0 * exp2(A*x)", {"f0", "x"}, {"A"});
  const Expression e = substitute_variable(outer, "y", inner);
  EXPECT_EQ(e.variables, (std::vector<std::string>{"f0", "x"}));
  EXPECT_EQ(e.parameters, inner.parameters);
  EXPECT_EQ(e.nodes.size(), inner.nodes.size() + 3);
}

TEST(SolverKind, NamesReadBack) {
  for (SolverKind k : {SolverKind::automatic, SolverKind::linear, SolverKind::levenberg_marquardt})
    EXPECT_EQ(solver_kind_from_name(solver_kind_name(k)), k);
  EXPECT_EQ(solver_kind_name(SolverKind::levenberg_marquardt), "lm");
  EXPECT_FALSE(solver_kind_from_name("newton").has_value());
}

}  // namespace
}  // namespace shaderfit
