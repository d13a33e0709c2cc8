// The parts of the evolution: the front, NSGA-II selection, and the variation operators.
#include <gtest/gtest.h>

#include "search/evolution/nsga2.hpp"
#include "search/pareto.hpp"
#include "search/evolution/variation.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit::search_detail {
namespace {

FrontMember member(double cost, double loss) {
  FrontMember m;
  m.cost = cost;
  m.loss = loss;
  m.formula = "f";
  return m;
}

TEST(ParetoFront, KeepsOnlyNonDominatedMembers) {
  int entered = 0;
  ParetoFront f([&](const FrontMember&) { ++entered; });
  EXPECT_TRUE(f.offer(member(4, 1.0)));
  EXPECT_TRUE(f.offer(member(2, 2.0)));
  EXPECT_FALSE(f.offer(member(5, 1.5)));  // dominated by (4, 1)
  EXPECT_FALSE(f.offer(member(4, 1.0)));  // equal: the first stays
  EXPECT_TRUE(f.offer(member(3, 0.5)));   // evicts (4, 1)
  const auto m = f.members();
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].cost, 2);
  EXPECT_EQ(m[1].cost, 3);
  EXPECT_EQ(entered, 3);
  EXPECT_EQ(f.best_loss_at(2.5), 2.0);
  EXPECT_TRUE(f.would_enter(1, 5.0));
  EXPECT_FALSE(f.would_enter(3, 0.6));
}

TEST(Nsga2, RanksAndCrowding) {
  const std::vector<Objectives> p = {{1, 5}, {2, 4}, {3, 3}, {2, 5}, {4, 4}, {0.5, 9}};
  std::vector<int> rank;
  std::vector<double> crowd;
  rank_and_crowding(p, &rank, &crowd);
  EXPECT_EQ(rank, (std::vector<int>{0, 0, 0, 1, 1, 0}));
  EXPECT_TRUE(std::isinf(crowd[5]));  // the ends of a front are kept first
  const auto keep = nsga2_select(p, 4);
  ASSERT_EQ(keep.size(), 4u);
  for (std::size_t i : keep) EXPECT_EQ(rank[i], 0);
}

VariationLimits limits() {
  VariationLimits l;
  l.variables = {"r0", "x"};
  l.operators = {Op::Add, Op::Sub, Op::Mul, Op::Div, Op::IPow, Op::Sqrt, Op::Exp2, Op::Pow};
  l.literals = {0.5, 1, 2};
  l.max_nodes = 25;
  l.max_parameters = 3;
  return l;
}

TEST(Variation, ChildrenAreWellFormedAndWithinLimits) {
  Rng rng(11);
  const VariationLimits l = limits();
  std::vector<Expression> pool;
  for (int i = 0; i < 50; ++i) {
    Expression e = random_formula(rng, l, 3);
    if (!e.empty()) pool.push_back(e);
  }
  ASSERT_GT(pool.size(), 20u);
  for (int i = 0; i < 5000; ++i) {
    const Expression& a = pool[uniform_index(rng, pool.size())];
    const Expression& b = pool[uniform_index(rng, pool.size())];
    Expression c = bernoulli(rng, 0.5) ? mutate(rng, a, l) : crossover(rng, a, b, l);
    if (c.empty()) continue;
    ASSERT_LE(c.size(), l.max_nodes);
    ASSERT_LE(c.parameters.size(), 3u);
    ASSERT_EQ(c.parameters.size(), c.parameter_values.size());
    Expression copy = c;
    ASSERT_NO_THROW(copy.update_lengths());
    for (const Node& n : c.nodes) {
      if (n.op == Op::Param) {
        ASSERT_LT(static_cast<std::size_t>(n.index), c.parameters.size());
      }
      if (n.op == Op::IPow) {
        ASSERT_TRUE(n.index >= 2 && n.index <= 5);
      }
    }
    pool[uniform_index(rng, pool.size())] = c;
  }
}

// With select, sign and copysign among the operators, random formulas and mutations use them
// (select also by wrapping a subtree), and every child stays well formed.
TEST(Variation, NewOperatorsAppearAndStayWellFormed) {
  Rng rng(12);
  VariationLimits l = limits();
  l.operators = {Op::Add, Op::Mul, Op::Select, Op::Sign, Op::CopySign};
  int seen[3] = {0, 0, 0};
  Expression e;
  for (int i = 0; i < 3000; ++i) {
    while (e.empty()) e = random_formula(rng, l, 3);
    Expression c = mutate(rng, e, l);
    if (c.empty()) continue;
    Expression copy = c;
    ASSERT_NO_THROW(copy.update_lengths());
    ASSERT_LE(c.parameters.size(), 3u);
    for (const Node& n : c.nodes) {
      seen[0] += n.op == Op::Select;
      seen[1] += n.op == Op::Sign;
      seen[2] += n.op == Op::CopySign;
    }
    e = bernoulli(rng, 0.1) ? Expression{} : c;
  }
  EXPECT_GT(seen[0], 0);
  EXPECT_GT(seen[1], 0);
  EXPECT_GT(seen[2], 0);
}

// The front's parts as building blocks: distinct subtrees of 2 to kMaxBlockNodes nodes, with
// their parameters' values; mutations insert them and stay well formed.
TEST(Variation, BuildingBlocksFromTheFront) {
  const VariationLimits base = limits();
  const Expression a =
      parse_formula("sqrt(1 - (x / r0)^2) * p0",
                    {.variables = base.variables, .parameters = {"p0"}, .parameter_values = {2.5}});
  const Expression b = parse_formula("(x / r0)^2 + x", {.variables = base.variables});
  const std::vector<std::vector<Node>> blocks = subtree_blocks({&a, &b});
  // a: x / y, (x / y)^2, 1 - (x / y)^2, sqrt(...), sqrt(...) * p0; b adds only (x / y)^2 + x.
  ASSERT_EQ(blocks.size(), 6u);
  EXPECT_EQ(blocks.back().size(), 6u);
  EXPECT_EQ(blocks[4].back().op, Op::Mul);
  EXPECT_EQ(blocks[4][blocks[4].size() - 2].value, 2.5);  // p0 with its value
  VariationLimits l = base;
  l.blocks = blocks;
  Rng rng(3);
  int inserted = 0;
  for (int i = 0; i < 2000; ++i) {
    const Expression c = mutate(rng, b, l);
    if (c.empty()) continue;
    Expression copy = c;
    ASSERT_NO_THROW(copy.update_lengths());
    inserted += to_infix(c).find("sqrt(") != std::string::npos;
  }
  EXPECT_GT(inserted, 0);
}

TEST(Variation, LinearScalingForm) {
  Expression e;
  e.variables = {"x"};
  e.nodes = {Node::variable(0), Node::ipow(2)};
  e.update_lengths();
  const Expression s = with_linear_scaling(e, 2.0, 0.5);
  EXPECT_EQ(to_infix(s), "p0 * x^2 + p1");
  EXPECT_EQ(s.parameter_values, (std::vector<double>{2.0, 0.5}));
}

}  // namespace
}  // namespace shaderfit::search_detail
