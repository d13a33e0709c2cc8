// A search across ranks without MPI: threads of this process as the ranks, over an in-process
// Communicator, so that the distributed search is tested where mpirun cannot run
// (apps/shaderfit-mpi/mpi_search_test.cpp runs it under mpirun).
#include "search/distributed.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <condition_variable>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>

#include "search/exact_json.hpp"
#include "search/search_context.hpp"
#include "search/run/seed_problem_test_util.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/expr/simplify.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {
namespace {

// The ranks' shared state: a barrier that gathers one message per rank, and mailboxes.
struct LocalGroup {
  explicit LocalGroup(int n) : size(n), slots(static_cast<std::size_t>(n)) {}
  int size;
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<std::string> slots, result;
  int arrived = 0;
  std::uint64_t phase = 0;
  std::map<std::pair<int, int>, std::deque<std::string>> mail;  // (from, to)
};

class LocalRank final : public Communicator {
 public:
  LocalRank(LocalGroup& group, int rank) : g_(group), rank_(rank) {}
  [[nodiscard]] int rank() const override { return rank_; }
  [[nodiscard]] int size() const override { return g_.size; }

  std::vector<std::string> all_gather(std::string_view mine) override {
    gathered.emplace_back(mine);
    std::unique_lock lock(g_.mutex);
    const std::uint64_t phase = g_.phase;
    g_.slots[static_cast<std::size_t>(rank_)] = std::string(mine);
    if (++g_.arrived == g_.size) {
      g_.result = g_.slots;
      g_.arrived = 0;
      ++g_.phase;
      g_.changed.notify_all();
    } else {
      g_.changed.wait(lock, [&] { return g_.phase != phase; });
    }
    return g_.result;
  }

  std::string broadcast(std::string_view bytes, int root) override {
    return all_gather(rank_ == root ? bytes : std::string_view())[static_cast<std::size_t>(root)];
  }

  std::vector<std::string> exchange(const std::vector<std::pair<int, std::string>>& sends,
                                    const std::vector<int>& from) override {
    for (const auto& send : sends) gathered.push_back(send.second);
    std::unique_lock lock(g_.mutex);
    for (const auto& [to, bytes] : sends) g_.mail[{rank_, to}].push_back(bytes);
    g_.changed.notify_all();
    std::vector<std::string> out;
    for (int source : from) {
      auto& box = g_.mail[{source, rank_}];
      g_.changed.wait(lock, [&] { return !box.empty(); });
      out.push_back(std::move(box.front()));
      box.pop_front();
    }
    return out;
  }

  // Not used by the distributed search.
  void send(int /*to*/, std::string_view /*bytes*/) override { throw std::logic_error("send"); }
  std::optional<std::pair<int, std::string>> receive(double /*timeout_s*/) override {
    throw std::logic_error("receive");
  }
  void forget(int /*rank*/) override {}
  [[nodiscard]] bool lost() const override { return false; }

  std::vector<std::string> gathered;  // what this rank gave every all_gather and sent

 private:
  LocalGroup& g_;
  int rank_;
};

// Runs the search on `ranks` threads; returns rank 0's summary and checks the others'. `each`
// may add what only observes (a callback) to a rank's options; `kept` receives the ranks.
SearchSummary run_on_ranks(int ranks, SearchOptions options, const SearchProblem& problem,
                           const std::function<void(int, SearchOptions&)>& each = {},
                           std::vector<LocalRank>* kept = nullptr) {
  LocalGroup group(ranks);
  std::vector<LocalRank> members;
  for (int r = 0; r < ranks; ++r) members.emplace_back(group, r);
  std::vector<SearchSummary> summaries(static_cast<std::size_t>(ranks));
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r) {
    threads.emplace_back([&, r] {
      SearchOptions o = options;
      o.communicator = &members[static_cast<std::size_t>(r)];  // the same options otherwise
      if (each) each(r, o);
      run_search(o, problem, &summaries[static_cast<std::size_t>(r)]);
    });
  }
  for (std::thread& t : threads) t.join();
  for (int r = 1; r < ranks; ++r) EXPECT_TRUE(summaries[static_cast<std::size_t>(r)].front.empty());
  if (kept != nullptr) *kept = std::move(members);
  return summaries.front();
}

std::vector<std::string> formulas(const SearchSummary& s) {
  std::vector<std::string> out;
  for (const FrontMember& m : s.front) out.push_back(m.formula);
  return out;
}

SearchOptions short_search() {
  SearchOptions o = test::seed_task_options();
  o.threads = 1;
  o.seed = 3;
  o.time_limit_s = 120;
  o.max_enumeration_cost = 2;
  o.max_candidates = 20'000;
  return o;
}

TEST(Distributed, IslandsAreSharedRoundRobin) {
  LocalGroup group(3);
  LocalRank rank(group, 1);
  const search_detail::RankGroup ranks(&rank);
  EXPECT_TRUE(ranks.distributed());
  EXPECT_EQ(ranks.owner(0), 0);
  EXPECT_EQ(ranks.owner(4), 1);
  EXPECT_EQ(ranks.owner(5), 2);
  EXPECT_FALSE(search_detail::RankGroup(nullptr).distributed());
}

TEST(Distributed, TwoRanksAreReproducibleAndFindTheSeedFormula) {
  const SearchProblem problem = test::fresnel_seed_problem();
  SearchOptions o = short_search();
  o.max_enumeration_cost = 4;
  // The enumeration to cost 4 (which finds the seed's formula) across the ranks, then 40,000
  // candidates of evolution.
  SearchOptions enumeration = o;
  enumeration.evolve = false;
  enumeration.max_candidates.reset();
  const SearchSummary e = run_on_ranks(2, enumeration, problem);
  o.max_candidates = static_cast<std::int64_t>(e.candidates) + 40'000;
  const SearchSummary a = run_on_ranks(2, o, problem);
  const SearchSummary b = run_on_ranks(2, o, problem);
  EXPECT_EQ(formulas(a), formulas(b));
  EXPECT_EQ(a.candidates, b.candidates);
  EXPECT_EQ(a.ranks, 2);
  EXPECT_GT(a.bytes_sent, 0u);
  EXPECT_GT(a.generations, 0u);
  bool found = false;
  for (const FrontMember& m : a.front) found = found || (m.cost <= 4 && m.metrics.mse <= 3.5227e-4);
  EXPECT_TRUE(found);
}

// Islands are dealt again at synchronisations by the time they took (timings differ from run to
// run); an island evolves the same on any rank, so the front does not change with them.
TEST(Distributed, UnevenIslandsRebalancedGiveTheSameFront) {
  const SearchProblem problem = test::fresnel_seed_problem();
  SearchOptions o = short_search();
  o.islands = 5;  // 3 and 2 to start with
  o.max_candidates = 40'000;
  const SearchSummary a = run_on_ranks(2, o, problem);
  const SearchSummary b = run_on_ranks(2, o, problem);
  EXPECT_GT(a.generations, 0u);
  EXPECT_EQ(formulas(a), formulas(b));
  EXPECT_EQ(a.candidates, b.candidates);
}

TEST(Distributed, ResumedRunEndsAsTheUninterruptedOne) {
  const SearchProblem problem = test::fresnel_seed_problem();
  const std::string path = testing::TempDir() + "distributed_resume.ckpt";
  SearchOptions whole = short_search();
  whole.max_candidates = 30'000;
  const SearchSummary a = run_on_ranks(3, whole, problem);
  SearchOptions first = short_search();
  first.max_candidates = 15'000;
  first.checkpoint_path = path;
  first.checkpoint_interval_s = 0;
  (void)run_on_ranks(3, first, problem);
  SearchOptions rest = whole;
  rest.resume_path = path;
  const SearchSummary b = run_on_ranks(3, rest, problem);
  EXPECT_EQ(formulas(a), formulas(b));
  EXPECT_EQ(a.candidates, b.candidates);
  EXPECT_EQ(a.generations, b.generations);
}

// The front every rank holds is built from what the ranks reported to rank 0 at their
// synchronisations: rank 0's front after the evolution holds a member as good as every candidate
// any rank sent (nothing is lost on the way), and the other ranks' finds reach it. Every rank
// announces the same members (the others take what entered rank 0's front).
TEST(Distributed, TheFrontIsTheUnionOfWhatTheRanksReported) {
  const SearchProblem problem = test::fresnel_seed_problem();
  SearchOptions o = short_search();
  o.max_candidates = 30'000;
  constexpr int kRanks = 3;
  std::vector<std::vector<FrontMember>> announced(kRanks);
  std::vector<LocalRank> ranks;
  (void)run_on_ranks(
      kRanks, o, problem,
      [&](int r, SearchOptions& each) {
        each.on_new_member = [&announced, r](const FrontMember& m) {
          announced[static_cast<std::size_t>(r)].push_back(m);
        };
      },
      &ranks);
  // The other ranks take rank 0's front before the evolution whole (nothing is announced then).
  const auto evolved = [](const std::vector<FrontMember>& all) {
    std::vector<std::string> out;
    for (const FrontMember& m : all)
      if (m.origin == SearchPhase::Evolution) out.push_back(m.formula);
    return out;
  };
  ASSERT_FALSE(evolved(announced[0]).empty());
  for (int r = 1; r < kRanks; ++r)
    EXPECT_EQ(evolved(announced[static_cast<std::size_t>(r)]), evolved(announced[0]));
  // Every candidate each rank sent at a synchronisation, as one process scores it.
  search_detail::SearchContext scorer(o, problem);
  std::set<std::string> reported_formulas;
  std::size_t reported = 0, checked = 0;
  for (const LocalRank& rank : ranks) {
    for (const std::string& bytes : rank.gathered) {
      if (bytes.empty()) continue;  // a broadcast's receivers give nothing
      // The evolution's synchronisations (other messages are skipped).
      const nlohmann::json message = nlohmann::json::from_cbor(bytes, true, false);
      if (!message.is_object() || !message.contains("islands")) continue;
      for (const nlohmann::json& island : message.at("islands")) {
        for (const nlohmann::json& c : island.at(2)) {
          const Expression e = search_detail::exact_expression_from(c.at(0));
          ++reported;
          reported_formulas.insert(to_infix(e, {.substitute_parameters = true}));
          reported_formulas.insert(to_infix(simplify(e), {.substitute_parameters = true}));
          if (!scorer.finite_everywhere(e)) continue;
          const double loss = loss_value(o.loss, scorer.score(e));
          if (!std::isfinite(loss)) continue;
          const double cost = expression_cost(e, o.cost);
          ++checked;
          bool covered = false;
          for (const FrontMember& m : announced[0])
            covered = covered || (m.cost <= cost && m.loss <= loss * (1 + 1e-9) + 1e-300);
          EXPECT_TRUE(covered) << "reported but lost: " << to_infix(e) << " (cost " << cost
                               << ", loss " << loss << ")";
        }
      }
    }
  }
  EXPECT_GT(checked, 0u);
  // Rank 0 keeps its own islands' finds (it sends them to nobody): some of the members the
  // evolution added came from the other ranks' reports.
  std::size_t from_others = 0;
  for (const std::string& f : evolved(announced[0])) from_others += reported_formulas.count(f);
  EXPECT_GT(from_others, 0u);
}

// The lowest loss at each member's cost or below.
double best_at(const SearchSummary& s, double cost) {
  double best = std::numeric_limits<double>::infinity();
  for (const FrontMember& m : s.front)
    if (m.cost <= cost) best = std::min(best, m.loss);
  return best;
}

// Across ranks each rank enumerates its part of every batch, and a level is shared once it is
// needed whole (its classes deduplicated then); the last level's classes stay with their ranks
// (counted where they were made), so the work is about one process's and the front is as good
// at every cost.
TEST(Distributed, EnumerationAcrossRanksIsAsGoodAsOneProcess) {
  const SearchProblem problem = test::fresnel_seed_problem();
  SearchOptions o = short_search();
  o.max_enumeration_cost = 3;  // levels whose batches complete
  o.evolve = false;
  o.max_candidates.reset();
  SearchSummary one;
  run_search(o, problem, &one);
  for (int ranks : {2, 3}) {
    const SearchSummary many = run_on_ranks(ranks, o, problem);
    EXPECT_GE(many.distinct_candidates, one.distinct_candidates) << ranks << " ranks";
    EXPECT_NEAR(static_cast<double>(many.candidates), static_cast<double>(one.candidates),
                0.1 * static_cast<double>(one.candidates))
        << ranks << " ranks";
    EXPECT_EQ(many.enumeration_cost_completed, 3);
    for (const FrontMember& m : one.front)
      EXPECT_LE(best_at(many, m.cost), m.loss * (1 + 1e-9)) << ranks << " ranks, cost " << m.cost;
    // And the same again: reproducible on a given number of ranks.
    EXPECT_EQ(formulas(run_on_ranks(ranks, o, problem)), formulas(many)) << ranks << " ranks";
  }
  // Stopped in the middle of a batch by a rank's store filling up (each holds max_classes).
  o.max_enumeration_cost = 4;
  o.max_classes = 100'000;
  const SearchSummary many = run_on_ranks(2, o, problem);
  EXPECT_LE(many.distinct_candidates, 2 * o.max_classes);
  EXPECT_GE(many.enumeration_cost_completed, 2);
  EXPECT_FALSE(many.front.empty());
}

// A count budget is shared by the ranks: the enumeration ends within a round of it, the same
// way every time.
TEST(Distributed, ACountBudgetEndsTheEnumerationReproducibly) {
  const SearchProblem problem = test::fresnel_seed_problem();
  SearchOptions o = short_search();
  o.max_enumeration_cost = 4;
  o.evolve = false;
  o.max_candidates = 1'000'000;
  const SearchSummary a = run_on_ranks(2, o, problem);
  const SearchSummary b = run_on_ranks(2, o, problem);
  EXPECT_EQ(a.termination, Termination::CandidateLimit);
  EXPECT_GE(a.candidates, 1'000'000u);
  EXPECT_LE(a.candidates, 1'000'000u + 2 * 64 * 8'000u);  // about a round's tiles on each rank
  EXPECT_EQ(a.candidates, b.candidates);
  EXPECT_EQ(formulas(a), formulas(b));
}

TEST(Distributed, FewerIslandsThanRanksIsAnError) {
  SearchOptions o = short_search();
  o.islands = 1;
  LocalGroup group(2);
  LocalRank rank(group, 0);
  o.communicator = &rank;
  SearchSummary s;
  try {
    run_search(o, test::fresnel_seed_problem(), &s);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "SearchOptions::islands");
    EXPECT_NE(e.message().find("1 islands for 2 ranks"), std::string::npos);
  }
}

}  // namespace
}  // namespace shaderfit
