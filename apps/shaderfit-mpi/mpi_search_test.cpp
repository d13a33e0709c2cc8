// shaderfit-mpi under mpirun: two ranks (oversubscribed on a small machine) give the same front
// from the same seed under a count budget, on the seed task (finding the seed's formula) and on a
// problem from the literature (recovered exactly); a resumed run ends as the uninterrupted one; a
// rank that dies leaves the last checkpoint whole. Skipped where mpirun is not found or cannot
// start two ranks.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <thread>
#include <vector>

#include "mpi_test_util.hpp"
#include "shaderfit/core/random.hpp"

namespace {

namespace fs = std::filesystem;
using shaderfit::mpi_testing::mpirun;
using shaderfit::mpi_testing::Outcome;
using shaderfit::mpi_testing::run;
using shaderfit::mpi_testing::scratch;

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

std::vector<std::string> formulas(const nlohmann::json& doc) {
  std::vector<std::string> out;
  for (const auto& m : doc.at("front")) out.push_back(m.at("formula").get<std::string>());
  return out;
}

// The seed task under a count budget, one thread per rank: a short enumeration (rank 0's), then
// about 50,000 candidates of evolution spread over the ranks.
const std::string kSeedSearch =
    " search --dataset fresnel-seed --inputs r0,x --target R --threads 1 --quiet --seed 3";
const std::string kShort = " --max-enumeration-cost 2 --time 120";

TEST(MpiSearch, SeedTaskIsReproducibleAndFindsTheSeedFormula) {
  REQUIRE_MPIRUN();
  // The enumeration up to cost 4 across the ranks finds the seed's r0 + (x - r0) x^4 (MSE
  // 3.5227e-4 on this data) or better; then 40,000 candidates of evolution run on both ranks.
  const fs::path counted = scratch("enumeration.json");
  const Outcome e = run(mpirun(2) + kSeedSearch +
                        " --max-enumeration-cost 4 --strategy enumerate --time 120 --json " +
                        counted.string());
  ASSERT_EQ(e.status, 0) << e.output;
  const auto enumerated = read_json(counted)["summary"]["candidates"].get<std::int64_t>();
  const std::string budget =
      " --max-enumeration-cost 4 --time 120 --evals " + std::to_string(enumerated + 40'000);
  const fs::path first = scratch("first.json"), second = scratch("second.json");
  const Outcome a = run(mpirun(2) + kSeedSearch + budget + " --json " + first.string());
  ASSERT_EQ(a.status, 0) << a.output;
  const Outcome b = run(mpirun(2) + kSeedSearch + budget + " --json " + second.string());
  ASSERT_EQ(b.status, 0) << b.output;
  const nlohmann::json d1 = read_json(first), d2 = read_json(second);
  EXPECT_EQ(formulas(d1), formulas(d2));
  EXPECT_EQ(d1["summary"]["candidates"], d2["summary"]["candidates"]);
  EXPECT_EQ(d1["summary"]["termination"], "candidate limit");
  EXPECT_EQ(d1["summary"]["ranks"], 2);
  EXPECT_GT(d1["summary"]["generations"].get<int>(), 0);
  EXPECT_GT(d1["summary"]["bytes_sent"].get<double>(), 0);
  bool found = false;
  for (const auto& m : d1["front"])
    found = found || (m["cost"].get<double>() <= 4 && m["mse"].get<double>() <= 3.5227e-4);
  EXPECT_TRUE(found) << a.output;
}

TEST(MpiSearch, LiteratureProblemIsRecoveredReproducibly) {
  REQUIRE_MPIRUN();
  // Nguyen-3 (Uy et al. 2011): x^5 + x^4 + x^3 + x^2 + x, 20 points with x ~ U[-1, 1].
  const fs::path csv = scratch("nguyen3.csv");
  {
    std::ofstream out(csv);
    out.precision(17);
    out << "x,y\n";
    shaderfit::Rng rng(2024);
    for (int i = 0; i < 20; ++i) {
      const double x = shaderfit::uniform(rng, -1, 1);
      out << x << ',' << x * (1 + x * (1 + x * (1 + x * (1 + x)))) << '\n';
    }
  }
  const std::string search = " search --data " + csv.string() +
                             " --inputs x --target y --threads 1 --quiet --evals 150000 "
                             "--time 120 --islands 3";
  const fs::path first = scratch("n1.json"), second = scratch("n2.json");
  const Outcome a = run(mpirun(2) + search + " --json " + first.string());
  ASSERT_EQ(a.status, 0) << a.output;
  const Outcome b = run(mpirun(2) + search + " --json " + second.string());
  ASSERT_EQ(b.status, 0) << b.output;
  EXPECT_EQ(formulas(read_json(first)), formulas(read_json(second)));
  EXPECT_LE(read_json(first)["front"].back()["mse"].get<double>(), 1e-20) << a.output;
}

TEST(MpiSearch, ResumedRunEndsAsTheUninterruptedOne) {
  REQUIRE_MPIRUN();
  const fs::path whole = scratch("whole.json"), resumed = scratch("resumed.json");
  const fs::path ckpt = scratch("run.ckpt");
  const Outcome a =
      run(mpirun(2) + kSeedSearch + kShort + " --evals 40000 --json " + whole.string());
  ASSERT_EQ(a.status, 0) << a.output;
  const Outcome b = run(mpirun(2) + kSeedSearch + kShort + " --evals 20000 --checkpoint " +
                        ckpt.string() + " --checkpoint-every 0");
  ASSERT_EQ(b.status, 0) << b.output;
  const Outcome c = run(mpirun(2) + kSeedSearch + kShort + " --evals 40000 --resume " +
                        ckpt.string() + " --json " + resumed.string());
  ASSERT_EQ(c.status, 0) << c.output;
  EXPECT_EQ(formulas(read_json(resumed)), formulas(read_json(whole)));
  EXPECT_EQ(read_json(resumed)["summary"]["candidates"], read_json(whole)["summary"]["candidates"]);
  EXPECT_EQ(read_json(resumed)["summary"]["generations"],
            read_json(whole)["summary"]["generations"]);
}

// A checkpoint written by 2 ranks resumes in one process (shaderfit itself) and on 2 ranks
// again: the run goes on from the checkpoint's front and generation, and says how it was written.
TEST(MpiSearch, ACheckpointOfTwoRanksResumesOnOneAndOnTwo) {
  REQUIRE_MPIRUN();
  const fs::path ckpt = scratch("two.ckpt");
  const fs::path first = scratch("two_first.json");
  const Outcome a = run(mpirun(2) + kSeedSearch + kShort + " --evals 20000 --checkpoint " +
                        ckpt.string() + " --checkpoint-every 0 --json " + first.string());
  ASSERT_EQ(a.status, 0) << a.output;
  const nlohmann::json before = read_json(first);
  for (const auto& [name, command] :
       {std::pair{"one process", std::string(SHADERFIT_CLI_PATH)},
        std::pair{"two ranks", mpirun(2)}}) {
    const fs::path out = scratch(std::string("resumed_") + name[0] + ".json");
    const Outcome r = run(command + kSeedSearch + kShort + " --evals 40000 --resume " +
                          ckpt.string() + " --json " + out.string());
    ASSERT_EQ(r.status, 0) << name << ": " << r.output;
    const nlohmann::json after = read_json(out);
    EXPECT_GT(after["summary"]["generations"].get<int>(),
              before["summary"]["generations"].get<int>())
        << name;
    EXPECT_GE(after["summary"]["candidates"].get<double>(), 40000) << name;
    // Every member the checkpoint's front had is matched or bettered at its cost.
    for (const auto& m : before["front"]) {
      bool covered = false;
      for (const auto& n : after["front"])
        covered = covered || (n["cost"].get<double>() <= m["cost"].get<double>() &&
                              n["loss"].get<double>() <= m["loss"].get<double>() * (1 + 1e-9));
      EXPECT_TRUE(covered) << name << ": " << m["formula"];
    }
    if (std::string(name) == "one process")
      EXPECT_NE(r.output.find("written by 2 ranks"), std::string::npos) << r.output;
  }
}

TEST(MpiSearch, ARankThatDiesLeavesTheLastCheckpointWhole) {
  REQUIRE_MPIRUN();
  const fs::path ckpt = scratch("dies.ckpt"), log = scratch("dies.log");
  fs::remove(ckpt);
  // In the background: a long run that writes a checkpoint at every generation.
  const std::string command = mpirun(2) + kSeedSearch + " --time 60 --checkpoint " + ckpt.string() +
                              " --checkpoint-every 0 > " + log.string() + " 2>&1";
  const pid_t launcher = fork();
  ASSERT_GE(launcher, 0);
  if (launcher == 0) {
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto start = std::chrono::steady_clock::now();
  while (!fs::exists(ckpt) && std::chrono::steady_clock::now() - start < std::chrono::seconds(30))
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(fs::exists(ckpt)) << "no checkpoint within 30 s";
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // a few more generations
  // One of the ranks (the shaderfit-mpi processes writing this checkpoint) dies.
  const Outcome named = run("pgrep -x shaderfit-mpi");
  std::istringstream pids(named.output);
  std::vector<pid_t> found;
  for (pid_t p; pids >> p;) {
    std::ifstream cmdline("/proc/" + std::to_string(p) + "/cmdline", std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(cmdline)), {});
    if (text.find(ckpt.string()) != std::string::npos) found.push_back(p);
  }
  ASSERT_EQ(found.size(), 2u) << named.output;
  kill(found.back(), SIGKILL);
  int status = 0;
  waitpid(launcher, &status, 0);
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the run did not fail";
  // The checkpoint is whole: one process resumes from it and finishes.
  const Outcome resumed =
      run(std::string(SHADERFIT_CLI_PATH) + kSeedSearch + " --time 2 --resume " + ckpt.string());
  EXPECT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("written by 2 ranks, resumed on 1"), std::string::npos)
      << resumed.output;
}

TEST(MpiSearch, FewerIslandsThanRanksIsOneClearError) {
  REQUIRE_MPIRUN();
  const Outcome r = run(mpirun(2) + kSeedSearch + " --time 1 --islands 1");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("shaderfit: error: --islands: 1 islands for 2 ranks: give every rank "
                          "at least one island"),
            std::string::npos)
      << r.output;
}

}  // namespace
