// Checkpoints: the file format (round trip, damage, other versions and data), and resuming:
// a run stopped at a generation boundary or during the enumeration, then resumed with one
// thread, ends with the front the uninterrupted run ends with.
#include "search/checkpoint.hpp"
#include "core/hash.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "search/run/seed_problem_test_util.hpp"
#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit::search_detail {
namespace {

using core_detail::fnv1a64;

// Seed 001's Fresnel data, every 8th row (512), to keep the searches below short.
SearchProblem seed_problem() {
  Rng rng(1);
  const Dataset d = make_fresnel_seed_dataset(rng);
  SearchProblem p;
  p.input_names = {"r0", "x"};
  p.inputs.resize(2);
  const auto& r0 = d.numeric("r0").values;
  const auto& x = d.numeric("x").values;
  const auto& y = d.numeric("R").values;
  for (std::size_t i = 0; i < y.size(); i += 8) {
    p.inputs[0].push_back(r0[i]);
    p.inputs[1].push_back(x[i]);
    p.target.push_back(y[i]);
  }
  return p;
}

std::string scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "shaderfit_checkpoint_test";
  std::filesystem::create_directories(dir);
  auto path = (dir / name).string();
  std::filesystem::remove(path);
  return path;
}

Checkpoint sample_checkpoint() {
  const SearchProblem p = seed_problem();
  SearchOptions o = test::seed_task_options();
  Checkpoint c;
  c.phase = SearchPhase::Evolution;
  c.shaderfit_version = std::string(checkpoint_writer_version());
  c.data_hash = problem_hash(p);
  c.rows = p.target.size();
  c.input_names = p.input_names;
  c.options = checkpoint_options(o);
  c.elapsed_s = 12.25;
  c.candidates = 123456789012ULL;
  c.node_evaluations = std::numeric_limits<std::uint64_t>::max();
  FrontMember m;
  m.expression = parse_formula("r0 + (x - r0) * x^4", {.variables = {"r0", "x"}});
  m.formula = "r0 + (x - r0) * x^4";
  m.cost = 4;
  m.nodes = m.expression.size();
  m.loss = 0.1;
  m.metrics = {.mse = 0.1,
               .rmse = std::sqrt(0.1),
               .max_abs = 5e-324,
               .rel = std::numeric_limits<double>::quiet_NaN(),
               .log = -0.0};
  m.time_s = 1.0 / 3.0;
  m.origin = SearchPhase::Enumeration;
  c.front.push_back(m);
  Rng rng(42);
  rng.discard(1000);
  std::ostringstream state;
  state << rng;
  c.rng = state.str();
  SavedIsland island;
  island.rng = c.rng;
  SavedIndividual ind;
  ind.expr = parse_formula("p0 * exp2(x * p1) + r0",
                           {.variables = {"r0", "x"}, .parameters = {"p0", "p1"}});
  ind.expr.parameter_values = {0.1, -std::numeric_limits<double>::infinity()};
  ind.loss = 1e-300;
  ind.cost = 3;
  ind.raw_loss = std::numeric_limits<double>::infinity();
  ind.raw_cost = 2;
  ind.hash = 0xfedcba9876543210ULL;
  ind.scaled = true;
  ind.a = -1.5;
  ind.b = 1e308;
  island.population.push_back(ind);
  c.evolution.islands.push_back(island);
  c.evolution.generations = 17;
  c.evolution.polished = true;
  return c;
}

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b) ||
         (std::isnan(a) && std::isnan(b));
}

TEST(Checkpoint, TextRoundTripIsExact) {
  const Checkpoint c = sample_checkpoint();
  const Checkpoint r = parse_checkpoint(checkpoint_text(c), "mem");
  EXPECT_EQ(r.phase, c.phase);
  EXPECT_EQ(r.data_hash, c.data_hash);
  EXPECT_EQ(r.options, c.options);
  EXPECT_EQ(r.candidates, c.candidates);
  EXPECT_EQ(r.node_evaluations, c.node_evaluations);
  EXPECT_EQ(r.elapsed_s, c.elapsed_s);
  ASSERT_EQ(r.front.size(), 1u);
  EXPECT_EQ(r.front[0].expression, c.front[0].expression);
  EXPECT_TRUE(same_bits(r.front[0].time_s, c.front[0].time_s));
  EXPECT_TRUE(same_bits(r.front[0].metrics.max_abs, 5e-324));
  EXPECT_TRUE(std::isnan(r.front[0].metrics.rel));
  EXPECT_TRUE(same_bits(r.front[0].metrics.log, -0.0));
  EXPECT_EQ(r.rng, c.rng);
  ASSERT_EQ(r.evolution.islands.size(), 1u);
  const SavedIndividual& a = r.evolution.islands[0].population.at(0);
  const SavedIndividual& b = c.evolution.islands[0].population[0];
  EXPECT_EQ(a.expr, b.expr);
  EXPECT_TRUE(same_bits(a.expr.parameter_values[1], b.expr.parameter_values[1]));
  EXPECT_TRUE(same_bits(a.loss, b.loss));
  EXPECT_TRUE(same_bits(a.raw_loss, b.raw_loss));
  EXPECT_EQ(a.hash, b.hash);
  EXPECT_EQ(a.scaled, b.scaled);
  EXPECT_TRUE(same_bits(a.b, b.b));
  EXPECT_EQ(r.evolution.generations, 17u);
  EXPECT_TRUE(r.evolution.polished);
  // The generator continues where it was.
  Rng x(42), y;
  x.discard(1000);
  std::istringstream(r.rng) >> y;
  EXPECT_EQ(x(), y());
}

void expect_refused(const std::string& text, const std::string& why) {
  try {
    parse_checkpoint(text, "run.ckpt");
    ADD_FAILURE() << "accepted; expected: " << why;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("run.ckpt"), std::string::npos) << e.what();
  }
}

TEST(Checkpoint, DamagedForeignAndOtherVersionsAreRefused) {
  Checkpoint c = sample_checkpoint();
  const std::string good = checkpoint_text(c);
  std::string flipped = good;
  flipped[flipped.size() / 2] ^= 0x01;
  expect_refused(flipped, "checksum does not match");
  expect_refused(good.substr(0, good.size() - 10), "checksum does not match");
  expect_refused(good.substr(0, 30), "header is cut short");
  expect_refused("{\"phase\": \"evolution\"}\n", "not a shaderfit checkpoint");
  expect_refused("", "not a shaderfit checkpoint");
  std::string format2 = good;
  format2.replace(format2.find("format 1"), 8, "format 2");
  expect_refused(format2, "format 2 cannot be read");
  c.shaderfit_version = "0.0.1";
  expect_refused(checkpoint_text(c), "written by shaderfit 0.0.1");
}

// A body edited after writing, with its checksum made to match again (a hand edit, or a writer
// bug): what it holds is checked as well.
TEST(Checkpoint, EditedBodiesWithAMatchingChecksumAreRefused) {
  const std::string good = checkpoint_text(sample_checkpoint());
  const std::size_t body_at = good.find('{');
  const std::string head = good.substr(0, good.find("fnv1a64 "));
  auto edited = [&](const std::string& from, const std::string& to) {
    std::string body = good.substr(body_at);
    const std::size_t at = body.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) body.replace(at, from.size(), to);
    return head + fmt::format("fnv1a64 {:016x}\n", fnv1a64(body, fnv1a64(head))) + body;
  };
  expect_refused(edited("\"generations\":17", "\"generations\":17.5"), "an integer in range");
  expect_refused(edited("\"generations\":17", "\"generations\":-17"), "an integer in range");
  expect_refused(edited("\"generations\":17", "\"generations\":1e300"), "an integer in range");
  expect_refused(edited("\"cost_completed\":-1", "\"cost_completed\":9999999999"),
                 "an integer in range");
  expect_refused(edited("\"variables\":[\"r0\",\"x\"]", "\"variables\":[\"r0\",\"y\"]"),
                 "other inputs than the data's");
  expect_refused(edited("\"variables\":[\"r0\",\"x\"]", "\"variables\":[\"r0\"]"),
                 "damaged checkpoint");
  expect_refused(edited("\"phase\":\"evolution\"", "\"phase\":\"polish\""), "unknown phase");
  expect_refused(edited("\"phase\":\"evolution\"", "\"phase\":7"), "damaged checkpoint");
}

TEST(Checkpoint, OtherDataOrOptionsAreRefused) {
  const Checkpoint c = sample_checkpoint();
  SearchProblem p = seed_problem();
  SearchOptions o = test::seed_task_options();
  EXPECT_NO_THROW(check_checkpoint_matches(c, o, p, "run.ckpt"));
  o.time_limit_s = 99;  // budgets and threads may change
  o.max_candidates = 5;
  o.threads = 3;
  EXPECT_NO_THROW(check_checkpoint_matches(c, o, p, "run.ckpt"));
  o.seed = 2;
  EXPECT_THROW(check_checkpoint_matches(c, o, p, "run.ckpt"), Error);
  try {
    check_checkpoint_matches(c, o, p, "run.ckpt");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("seed = 1; this search has seed = 2"), std::string::npos)
        << e.what();
  }
  o.seed = 1;
  // An option the checkpoint does not record (added since) counts as its default.
  Checkpoint older = c;
  std::erase_if(older.options, [](const auto& kv) { return kv.first == "islands"; });
  EXPECT_NO_THROW(check_checkpoint_matches(older, o, p, "run.ckpt"));
  o.islands = 3;
  EXPECT_THROW(check_checkpoint_matches(older, o, p, "run.ckpt"), Error);
  o.islands = 4;
  p.target[7] += 1e-9;
  EXPECT_THROW(check_checkpoint_matches(c, o, p, "run.ckpt"), Error);
}

TEST(Checkpoint, WriteIsAtomicAndReadBack) {
  const std::string path = scratch("atomic.ckpt");
  const Checkpoint c = sample_checkpoint();
  write_checkpoint(path, c);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  EXPECT_EQ(read_checkpoint(path).candidates, c.candidates);
  EXPECT_THROW(read_checkpoint(path + ".missing"), Error);
  EXPECT_THROW(write_checkpoint("/nonexistent-dir/x.ckpt", c), Error);
}

// Small enough for a unit test; every stop is a count.
SearchOptions small_budget(std::int64_t candidates) {
  SearchOptions o = test::seed_task_options();
  o.threads = 1;
  o.time_limit_s = 600;
  o.max_enumeration_cost = 1;
  o.max_enumeration_share = 1.0;
  o.max_candidates = candidates;
  o.population = 16;
  o.fit_rows = 64;
  o.seed = 3;
  return o;
}

void expect_same_result(const SearchSummary& a, const SearchSummary& b) {
  ASSERT_EQ(a.front.size(), b.front.size());
  for (std::size_t i = 0; i < a.front.size(); ++i) {
    EXPECT_EQ(a.front[i].formula, b.front[i].formula);
    EXPECT_EQ(a.front[i].expression, b.front[i].expression);
    EXPECT_EQ(a.front[i].cost, b.front[i].cost);
    EXPECT_EQ(a.front[i].loss, b.front[i].loss);
    EXPECT_EQ(a.front[i].metrics.max_abs, b.front[i].metrics.max_abs);
    EXPECT_EQ(a.front[i].origin, b.front[i].origin);
  }
  EXPECT_EQ(a.candidates, b.candidates);
  EXPECT_EQ(a.node_evaluations, b.node_evaluations);
  EXPECT_EQ(a.generations, b.generations);
  EXPECT_EQ(a.termination, b.termination);
}

TEST(Checkpoint, ResumedAtAGenerationBoundaryEndsAsTheUninterruptedRun) {
  const SearchProblem p = seed_problem();
  constexpr std::int64_t kBudget = 1200;
  SearchSummary a;
  run_search(small_budget(kBudget), p, &a);
  ASSERT_GT(a.generations, 3u);

  // The same run, interrupted at a synchronisation point part-way (the progress callback runs
  // there), checkpointing every boundary.
  const std::string path = scratch("boundary.ckpt");
  std::atomic<bool> stop{false};
  SearchOptions o = small_budget(kBudget);
  o.checkpoint_path = path;
  o.checkpoint_interval_s = 0;
  o.interrupt = &stop;
  o.progress_interval_s = 1e-9;
  o.on_progress = [&](const SearchProgress& g) {
    if (g.phase == SearchPhase::Evolution && g.candidates > kBudget / 2) stop.store(true);
  };
  SearchSummary b;
  run_search(o, p, &b);
  ASSERT_TRUE(b.interrupted);
  const Checkpoint c = read_checkpoint(path);
  EXPECT_EQ(c.phase, SearchPhase::Evolution);
  EXPECT_GT(c.evolution.generations, 0u);
  EXPECT_LT(c.evolution.generations, a.generations);

  SearchOptions r = small_budget(kBudget);
  r.resume_path = path;
  SearchSummary resumed;
  run_search(r, p, &resumed);
  expect_same_result(a, resumed);
}

TEST(Checkpoint, ResumedFromTheEnumerationEndsAsTheUninterruptedRun) {
  const SearchProblem p = seed_problem();
  constexpr std::int64_t kBudget = 1000;
  SearchSummary a;
  run_search(small_budget(kBudget), p, &a);
  ASSERT_GT(a.generations, 0u);

  const std::string path = scratch("enumeration.ckpt");
  std::atomic<bool> stop{false};
  SearchOptions o = small_budget(kBudget);
  o.checkpoint_path = path;
  o.interrupt = &stop;
  o.on_new_member = [&](const FrontMember& m) {
    if (m.cost >= 1) stop.store(true);  // during the enumeration
  };
  SearchSummary b;
  run_search(o, p, &b);
  ASSERT_TRUE(b.interrupted);
  ASSERT_EQ(b.generations, 0u);
  const Checkpoint c = read_checkpoint(path);
  EXPECT_EQ(c.phase, SearchPhase::Enumeration);
  EXPECT_FALSE(c.front.empty());

  SearchOptions r = small_budget(kBudget);
  r.resume_path = path;
  SearchSummary resumed;
  run_search(r, p, &resumed);
  expect_same_result(a, resumed);
}

// atan on 257 rows of [-1, 1], mirrored exactly: odd in x.
SearchProblem atan_problem() {
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs.resize(1);
  for (int i = -128; i <= 128; ++i) {
    p.inputs[0].push_back(i / 128.0);
    p.target.push_back(std::atan(i / 128.0));
  }
  return p;
}

TEST(Checkpoint, RecordsTheSymmetry) {
  Checkpoint c = sample_checkpoint();
  EXPECT_FALSE(parse_checkpoint(checkpoint_text(c), "mem").symmetry);
  c.symmetry = DataSymmetry{1, "x", SymmetryKind::Point, 1.0 / 3.0, -1};
  const Checkpoint r = parse_checkpoint(checkpoint_text(c), "mem");
  ASSERT_TRUE(r.symmetry);
  EXPECT_EQ(*r.symmetry, *c.symmetry);
}

TEST(Checkpoint, RecordsTheSymmetryEvidence) {
  Checkpoint c = sample_checkpoint();
  DataSymmetry s{1, "x", SymmetryKind::Odd};
  s.evidence = {SymmetryMethod::Interpolation, 19993, 2.4e-14, 1.0 / 3.0 * 1e-16};
  c.symmetry = s;
  const Checkpoint r = parse_checkpoint(checkpoint_text(c), "mem");
  ASSERT_TRUE(r.symmetry);
  EXPECT_EQ(*r.symmetry, *c.symmetry);
}

TEST(Checkpoint, SymmetricSearchResumesAsTheUninterruptedRun) {
  const SearchProblem p = atan_problem();
  constexpr std::int64_t kBudget = 1200;
  SearchSummary a;
  run_search(small_budget(kBudget), p, &a);
  ASSERT_TRUE(a.symmetry);
  ASSERT_GT(a.generations, 3u);

  const std::string path = scratch("symmetric.ckpt");
  std::atomic<bool> stop{false};
  SearchOptions o = small_budget(kBudget);
  o.checkpoint_path = path;
  o.checkpoint_interval_s = 0;
  o.interrupt = &stop;
  o.progress_interval_s = 1e-9;
  o.on_progress = [&](const SearchProgress& g) {
    if (g.phase == SearchPhase::Evolution && g.candidates > kBudget / 2) stop.store(true);
  };
  SearchSummary b;
  run_search(o, p, &b);
  ASSERT_TRUE(b.interrupted);
  const Checkpoint c = read_checkpoint(path);
  ASSERT_TRUE(c.symmetry);
  EXPECT_EQ(c.symmetry->kind, SymmetryKind::Odd);
  EXPECT_EQ(c.rows, 129u);  // the half

  SearchOptions r = small_budget(kBudget);
  r.resume_path = path;
  SearchSummary resumed;
  run_search(r, p, &resumed);
  ASSERT_TRUE(resumed.symmetry);
  expect_same_result(a, resumed);
  // --no-symmetry does not resume it.
  r.symmetry = false;
  EXPECT_THROW(run_search(r, p, &resumed), Error);
}

TEST(Checkpoint, CheckpointsWithoutSymmetryResumeOnTheWholeData) {
  // As written before symmetry existed: the whole data, no "symmetry" option or decision.
  const SearchProblem p = atan_problem();
  const std::string path = scratch("older.ckpt");
  SearchOptions o = small_budget(600);
  o.symmetry = false;
  o.checkpoint_path = path;
  SearchSummary s;
  run_search(o, p, &s);
  EXPECT_FALSE(s.symmetry);
  Checkpoint c = read_checkpoint(path);
  EXPECT_FALSE(c.symmetry);
  std::erase_if(c.options, [](const auto& kv) { return kv.first == "symmetry"; });
  write_checkpoint(path, c);
  SearchOptions r = small_budget(900);  // symmetry on, the default
  r.resume_path = path;
  SearchSummary resumed;
  ASSERT_NO_THROW(run_search(r, p, &resumed));
  EXPECT_FALSE(resumed.symmetry);
  EXPECT_FALSE(resumed.front.empty());
}

TEST(Checkpoint, ResumeRefusesAnotherSeed) {
  const SearchProblem p = seed_problem();
  const std::string path = scratch("seed.ckpt");
  SearchOptions o = small_budget(500);
  o.checkpoint_path = path;
  SearchSummary s;
  run_search(o, p, &s);
  SearchOptions r = small_budget(1000);
  r.seed = 4;
  r.resume_path = path;
  EXPECT_THROW(run_search(r, p, &s), Error);
}

}  // namespace
}  // namespace shaderfit::search_detail
