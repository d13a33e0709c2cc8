#include "shaderfit/batch/batch.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include "shaderfit/problem/problem.hpp"
#include "shaderfit/search/options.hpp"

namespace shaderfit {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("shaderfit_batch_test_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// An entry built in code (the manifest reader has its own tests): a reference on a domain,
// a candidate budget (results then depend on the seed only), one thread.
ManifestEntry entry(const std::string& name, const std::string& reference,
                    const std::string& domain, const std::string& baseline = "",
                    BatchGoal goal = {}) {
  ManifestEntry e;
  e.name = name;
  e.problem.reference.formula = reference;
  e.problem.domain = {domain};
  e.problem.samples = 300;
  e.loaded = std::make_shared<const Problem>(load_problem(e.problem));
  e.options.threads = 1;
  e.options.time_limit_s = 600;
  e.options.max_candidates = 60000;
  e.options.seed = 3;
  e.options.loss = Loss::MaxAbs;
  e.baseline = baseline;
  e.goal = goal;
  e.hash = name + "-v1";
  return e;
}

Manifest small_manifest() {
  Manifest m;
  m.path = "test.toml";
  m.entries.push_back(entry("fast_tanh", "tanh(x)", "x=0:4", "x / (1 + abs(x))",
                            {BatchGoal::Kind::BeatBaseline, 0}));
  m.entries.push_back(entry("fast_exp", "exp(x)", "x=0:1"));
  m.entries.push_back(entry("fast_sqrt", "sqrt(x)", "x=0.1:1", "", {BatchGoal::Kind::MaxCost, 3}));
  m.entries.push_back(entry("fast_sin", "sin(x)", "x=0:1.5"));
  return m;
}

std::vector<std::string> formulas(const BatchEntryResult& r) {
  std::vector<std::string> out;
  for (const FrontMember& m : r.front) out.push_back(m.formula);
  return out;
}

void expect_same(const BatchResult& a, const BatchResult& b) {
  ASSERT_EQ(a.entries.size(), b.entries.size());
  for (std::size_t i = 0; i < a.entries.size(); ++i) {
    EXPECT_EQ(a.entries[i].name, b.entries[i].name);
    EXPECT_EQ(formulas(a.entries[i]), formulas(b.entries[i])) << a.entries[i].name;
    EXPECT_EQ(a.entries[i].chosen, b.entries[i].chosen) << a.entries[i].name;
    EXPECT_EQ(a.entries[i].goal_met, b.entries[i].goal_met) << a.entries[i].name;
  }
}

TEST(Batch, RunsEveryEntryAndMeetsTheGoals) {
  const Manifest m = small_manifest();
  BatchOptions o;
  o.parallel_entries = 2;
  std::vector<std::string> lines;
  o.on_entry = [&](const BatchEntryResult& r) { lines.push_back(batch_entry_line(r)); };
  const BatchResult r = run_batch(m, o);
  ASSERT_EQ(r.entries.size(), 4u);
  EXPECT_TRUE(r.bad.empty());
  EXPECT_EQ(lines.size(), 4u);
  const BatchEntryResult& tanh = r.entries[0];
  EXPECT_EQ(tanh.name, "fast_tanh");
  ASSERT_TRUE(tanh.baseline);
  EXPECT_GT(tanh.baseline->metrics.max_abs, 0.05);  // x / (1 + |x|) is a poor tanh
  EXPECT_TRUE(tanh.goal_met) << tanh.why;
  EXPECT_LE(tanh.front[tanh.chosen].cost, tanh.baseline->cost);
  EXPECT_LE(tanh.front[tanh.chosen].loss, tanh.baseline->loss);
  const BatchEntryResult& sq = r.entries[2];
  EXPECT_LE(sq.front[sq.chosen].cost, 3);
  EXPECT_TRUE(sq.goal_met);
}

TEST(Batch, AFinishedEntryIsReadBackNotRunAgainUnlessItChanged) {
  const fs::path dir = scratch("resume");
  Manifest m = small_manifest();
  BatchOptions o;
  o.parallel_entries = 2;
  o.checkpoint_directory = (dir / "entries").string();
  const BatchResult first = run_batch(m, o);
  for (const BatchEntryResult& r : first.entries) EXPECT_FALSE(r.from_checkpoint);
  const BatchResult second = run_batch(m, o);
  for (const BatchEntryResult& r : second.entries) EXPECT_TRUE(r.from_checkpoint) << r.name;
  expect_same(first, second);
  m.entries[1].options.seed = 4;
  m.entries[1].hash = "fast_exp-v2";
  const BatchResult third = run_batch(m, o);
  for (const BatchEntryResult& r : third.entries)
    EXPECT_EQ(r.from_checkpoint, r.name != "fast_exp") << r.name;
}

TEST(Batch, AnInterruptedBatchResumesToTheUninterruptedResult) {
  const Manifest m = small_manifest();
  BatchOptions whole;
  whole.parallel_entries = 1;
  const BatchResult uninterrupted = run_batch(m, whole);

  const fs::path dir = scratch("interrupt");
  std::atomic<bool> stop{false};
  BatchOptions o;
  o.parallel_entries = 1;
  o.checkpoint_directory = (dir / "entries").string();
  o.interrupt = &stop;
  o.on_entry = [&](const BatchEntryResult&) { stop.store(true); };  // after the first
  const BatchResult part = run_batch(m, o);
  EXPECT_TRUE(part.interrupted);
  EXPECT_GE(part.entries.size(), 1u);
  EXPECT_LT(part.entries.size(), 4u);
  stop.store(false);
  o.on_entry = nullptr;
  const BatchResult rest = run_batch(m, o);
  EXPECT_FALSE(rest.interrupted);
  std::size_t earlier = 0;
  for (const BatchEntryResult& r : rest.entries) earlier += r.from_checkpoint ? 1 : 0;
  EXPECT_EQ(earlier, part.entries.size());
  expect_same(uninterrupted, rest);
}

TEST(Batch, AnEntryThatFailsDoesNotStopTheOthers) {
  Manifest m = small_manifest();
  m.entries[1].baseline = "x +";  // does not parse: the entry fails when scored
  const BatchResult r = run_batch(m, {});
  EXPECT_EQ(r.entries.size(), 3u);
  ASSERT_EQ(r.bad.size(), 1u);
  EXPECT_EQ(r.bad[0].name, "fast_exp");
  EXPECT_NE(r.bad[0].message.find("entry 'fast_exp'"), std::string::npos) << r.bad[0].message;
}

TEST(Batch, CheckpointJsonRoundTrips) {
  const Manifest m = small_manifest();
  const BatchEntryResult r = run_batch_entry(m.entries[0]);
  const BatchEntryResult back = batch_entry_from_json(batch_entry_json(r), "test");
  EXPECT_EQ(formulas(back), formulas(r));
  EXPECT_EQ(back.chosen, r.chosen);
  ASSERT_TRUE(back.baseline);
  EXPECT_EQ(back.baseline->loss, r.baseline->loss);
  EXPECT_EQ(back.front[back.chosen].loss, r.front[r.chosen].loss);
  EXPECT_THROW(batch_entry_from_json("{}", "x.json"), Error);
  EXPECT_THROW(batch_entry_from_json("not json", "x.json"), Error);
}

// Ranks as threads: a mailbox per rank.
struct Mail {
  std::mutex mutex;
  std::condition_variable changed;
  std::map<int, std::deque<std::pair<int, std::string>>> box;
};

class ThreadRank final : public Communicator {
 public:
  ThreadRank(Mail& mail, int rank, int size) : mail_(mail), rank_(rank), size_(size) {}
  [[nodiscard]] int rank() const override { return rank_; }
  [[nodiscard]] int size() const override { return size_; }
  std::vector<std::string> all_gather(std::string_view) override { throw std::logic_error("no"); }
  std::string broadcast(std::string_view, int) override { throw std::logic_error("no"); }
  std::vector<std::string> exchange(const std::vector<std::pair<int, std::string>>&,
                                    const std::vector<int>&) override {
    throw std::logic_error("no");
  }
  void send(int to, std::string_view bytes) override {
    std::lock_guard lock(mail_.mutex);
    mail_.box[to].emplace_back(rank_, std::string(bytes));
    mail_.changed.notify_all();
  }
  std::optional<std::pair<int, std::string>> receive(double timeout_s) override {
    std::unique_lock lock(mail_.mutex);
    auto& box = mail_.box[rank_];
    mail_.changed.wait_for(lock, std::chrono::duration<double>(timeout_s),
                           [&] { return !box.empty(); });
    if (box.empty()) return std::nullopt;
    auto m = std::move(box.front());
    box.pop_front();
    return m;
  }
  void forget(int) override { lost_ = true; }
  [[nodiscard]] bool lost() const override { return lost_; }

 private:
  Mail& mail_;
  int rank_, size_;
  bool lost_ = false;
};

TEST(BatchDistributed, ThreeRanksGiveTheResultOfOne) {
  const Manifest m = small_manifest();
  BatchOptions one;
  one.parallel_entries = 1;
  const BatchResult alone = run_batch(m, one);
  Mail mail;
  std::vector<std::unique_ptr<ThreadRank>> ranks;
  for (int r = 0; r < 3; ++r) ranks.push_back(std::make_unique<ThreadRank>(mail, r, 3));
  BatchOptions o;
  o.parallel_entries = 1;
  std::vector<std::thread> workers;
  for (int r = 1; r < 3; ++r)
    workers.emplace_back(
        [&, r] { run_batch_distributed(m, o, *ranks[static_cast<std::size_t>(r)]); });
  const BatchResult together = run_batch_distributed(m, o, *ranks[0]);
  for (std::thread& t : workers) t.join();
  expect_same(alone, together);
  std::set<int> used;
  for (const BatchEntryResult& r : together.entries) used.insert(r.rank);
  EXPECT_GE(used.size(), 2u);  // the work was shared
  EXPECT_FALSE(ranks[0]->lost());
}

TEST(BatchDistributed, AnEntryOfARankThatDiesIsFinishedByAnother) {
  const Manifest m = small_manifest();
  Mail mail;
  ThreadRank zero(mail, 0, 2), one(mail, 1, 2);
  // Rank 1 asks for work, takes an entry and dies with it (never answers again).
  std::thread dying([&] {
    one.send(0, "ready");
    while (!one.receive(1.0)) {
    }
  });
  BatchOptions o;
  o.parallel_entries = 1;
  o.rank_timeout_s = 1;
  const BatchResult r = run_batch_distributed(m, o, zero);
  dying.join();
  EXPECT_EQ(r.entries.size(), 4u);
  EXPECT_TRUE(r.bad.empty());
  for (const BatchEntryResult& e : r.entries) EXPECT_EQ(e.rank, 0) << e.name;
  EXPECT_TRUE(zero.lost());
}

}  // namespace
}  // namespace shaderfit
