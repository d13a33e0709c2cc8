#include <gtest/gtest.h>

#include <string>

#include "shaderfit/core/error.hpp"
#include "shaderfit/problem/problem.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {
namespace {

ProblemSource sphere_fresnel() {
  ProblemSource s;
  s.reference.formula = "fresnel-dielectric-f0";
  SceneSpec spec;
  spec.size = 16;
  s.scene = spec;
  return s;
}

// The display loss asks the problem for its scene's display weights; the other losses leave the
// rows unweighted.
TEST(SearchProblem, TheDisplayLossWeighsTheRowsByTheScene) {
  const Problem p = load_problem(sphere_fresnel());
  ASSERT_TRUE(p.scene);
  ASSERT_EQ(p.display_weights.size(), p.data.rows());
  EXPECT_EQ(p.display_weights, display_weights(*p.scene, p.data.numeric(p.target).values));
  EXPECT_EQ(search_problem(p, Loss::Display).weights, p.display_weights);
  EXPECT_TRUE(search_problem(p, Loss::Mse).weights.empty());
}

TEST(SearchProblem, TheDisplayLossNeedsASceneAndNoOtherWeights) {
  ProblemSource flat;
  flat.reference.formula = "x^2";
  flat.domain = {"x=0:1"};
  try {
    (void)search_problem(load_problem(flat), Loss::Display);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "SearchOptions::loss");
    EXPECT_NE(e.message().find("the display loss needs a scene"), std::string::npos) << e.what();
  }
  Problem p = load_problem(sphere_fresnel());
  EXPECT_THROW((void)search_problem(p, Loss::Display, p.target, {"weights"}), Error);
  // The search itself refuses the display loss on rows nobody weighed.
  SearchProblem rows = search_problem(p, Loss::Mse);
  SearchOptions o;
  o.loss = Loss::Display;
  o.max_candidates = 10;
  SearchSummary summary;
  EXPECT_THROW(run_search(o, rows, &summary), Error);
}

}  // namespace
}  // namespace shaderfit
