// `shaderfit-mpi batch` under mpirun: two ranks finish a count-budgeted manifest with the results
// of one process, and a rank killed while it searches loses only its entry, which rank 0
// finishes. Skipped where mpirun is not found or cannot start two ranks.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "mpi_test_util.hpp"

namespace {

namespace fs = std::filesystem;
using shaderfit::mpi_testing::mpirun;
using shaderfit::mpi_testing::Outcome;
using shaderfit::mpi_testing::run;

// A fresh directory for one test.
fs::path scratch_dir(const std::string& name) {
  const fs::path dir = shaderfit::mpi_testing::scratch(name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Eight functions under a candidate budget (results depend on the seed only); the one named
// `across` is searched by every rank together (a short enumeration and a budget of its own, so
// that its islands evolve).
std::string manifest(std::size_t evals, const std::string& across = "") {
  std::string m = "[defaults]\ntime = 600\nevals = " + std::to_string(evals) +
                  "\nseed = 2\nloss = \"max_abs\"\nsamples = 400\n";
  const char* entries[][3] = {
      {"f_tanh", "tanh(x)", "0.0, 4.0"},   {"f_exp", "exp(x)", "0.0, 1.0"},
      {"f_sin", "sin(x)", "0.0, 1.5"},     {"f_sqrt", "sqrt(x)", "0.1, 1.0"},
      {"f_log", "log(x + 1)", "0.0, 1.0"}, {"f_inv", "1 / (1 + x)", "0.0, 1.0"},
      {"f_cos", "cos(x)", "0.0, 1.5"},     {"f_atan", "atan(x)", "0.0, 1.0"},
  };
  for (const auto& e : entries)
    m += std::string("\n[[function]]\nname = \"") + e[0] + "\"\nreference = \"" + e[1] +
         "\"\ndomain = { x = [" + e[2] + "] }\n" +
         (across == e[0] ? "across_ranks = true\nmax_enumeration_cost = 2\nevals = 60000\n" : "");
  return m;
}

std::map<std::string, std::string> chosen(const fs::path& out) {
  std::ifstream in(out / "batch.json");
  const nlohmann::json doc = nlohmann::json::parse(in);
  std::map<std::string, std::string> r;
  for (const auto& e : doc.at("entries"))
    r[e.at("name").get<std::string>()] =
        e.at("run").at("front").at(e.at("chosen").get<std::size_t>()).at("formula");
  return r;
}

// The manifest `text` in `dir`, run by one process into dir/one and by two ranks into dir/two;
// the two ranks' output.
Outcome one_then_two_ranks(const fs::path& dir, const std::string& text) {
  std::ofstream(dir / "m.toml") << text;
  const std::string m = (dir / "m.toml").string();
  const Outcome one = run(std::string(SHADERFIT_CLI_PATH) + " batch " + m + " --out " +
                          (dir / "one").string() + " --parallel 1");
  EXPECT_EQ(one.status, 0) << one.output;
  const Outcome two = run(mpirun(2) + " batch " + m + " --out " + (dir / "two").string());
  EXPECT_EQ(two.status, 0) << two.output;
  return two;
}

TEST(MpiBatch, TwoRanksGiveTheResultsOfOneProcess) {
  REQUIRE_MPIRUN();
  const fs::path dir = scratch_dir("same");
  one_then_two_ranks(dir, manifest(20000));
  ASSERT_FALSE(HasFailure());
  const auto a = chosen(dir / "one"), b = chosen(dir / "two");
  EXPECT_EQ(a.size(), 8u);
  EXPECT_EQ(a, b);
}

// An entry too large for one rank: both ranks search it, its islands shared, before the others
// are handed out (each of which gives one process's result).
TEST(MpiBatch, AnEntryAcrossRanksSharesItsIslands) {
  REQUIRE_MPIRUN();
  const fs::path dir = scratch_dir("across");
  const Outcome two = one_then_two_ranks(dir, manifest(20000, "f_atan"));
  ASSERT_FALSE(HasFailure());
  EXPECT_NE(two.output.find(" on every rank"), std::string::npos) << two.output;
  auto a = chosen(dir / "one"), b = chosen(dir / "two");
  a.erase("f_atan");
  b.erase("f_atan");
  EXPECT_EQ(a, b);
  std::ifstream in(dir / "two" / "batch.json");
  const nlohmann::json doc = nlohmann::json::parse(in);
  for (const auto& e : doc.at("entries")) {
    const int rank = e.at("rank").get<int>();
    if (e.at("name") == "f_atan") {
      EXPECT_EQ(rank, -1);  // every rank
      const auto& summary = e.at("run").at("summary");
      EXPECT_EQ(summary.at("ranks").get<int>(), 2);
      EXPECT_GT(summary.at("generations").get<int>(), 0);  // the islands evolved
      EXPECT_GT(summary.at("bytes_sent").get<double>(), 0);
    } else {
      EXPECT_GE(rank, 0);
    }
  }
  // Run again: read back, not searched.
  const Outcome again =
      run(mpirun(2) + " batch " + (dir / "m.toml").string() + " --out " + (dir / "two").string());
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("8 of 8 functions done (8 finished by an earlier run)"),
            std::string::npos)
      << again.output;
}

// The rank of a process of this job, from its environment (Open MPI's OMPI_COMM_WORLD_RANK).
int rank_of(pid_t p) {
  std::ifstream env("/proc/" + std::to_string(p) + "/environ", std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(env)), {});
  const std::string key = std::string("OMPI_COMM_WORLD_RANK=");
  const auto at = text.find(key);
  return at == std::string::npos ? -1 : std::atoi(text.c_str() + at + key.size());
}

TEST(MpiBatch, AKilledRanksEntryIsFinishedByAnother) {
  REQUIRE_MPIRUN();
  const fs::path dir = scratch_dir("killed");
  std::ofstream(dir / "m.toml") << manifest(400000);
  const fs::path out = dir / "out", log = dir / "log";
  const std::string command = mpirun(2, true) + " batch " + (dir / "m.toml").string() + " --out " +
                              out.string() + " --rank-timeout 3 > " + log.string() + " 2>&1";
  const pid_t launcher = fork();
  ASSERT_GE(launcher, 0);
  if (launcher == 0) {
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Rank 1 takes its first entry at once; kill it while it searches.
  pid_t victim = -1;
  const auto start = std::chrono::steady_clock::now();
  while (victim < 0 && std::chrono::steady_clock::now() - start < std::chrono::seconds(30)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    std::istringstream pids(run("pgrep -x shaderfit-mpi").output);
    for (pid_t p; pids >> p;) {
      std::ifstream cmdline("/proc/" + std::to_string(p) + "/cmdline", std::ios::binary);
      const std::string text((std::istreambuf_iterator<char>(cmdline)), {});
      if (text.find(out.string()) != std::string::npos && rank_of(p) == 1) victim = p;
    }
  }
  ASSERT_GT(victim, 0) << "rank 1 not found";
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(victim, SIGKILL);
  int status = 0;
  waitpid(launcher, &status, 0);
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text;
  const auto r = chosen(out);
  EXPECT_EQ(r.size(), 8u) << text;
  EXPECT_NE(text.find("taken for dead"), std::string::npos) << text;
}

}  // namespace
