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

namespace {

namespace fs = std::filesystem;

struct Outcome {
  int status = -1;
  std::string output;  // stdout and stderr
};

Outcome run(const std::string& command) {
  Outcome r;
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (p == nullptr) return r;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, p) != nullptr) r.output += buffer;
  const int s = pclose(p);
  r.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  return r;
}

// As mpi_search_test.cpp's, and with recovery on: a rank that dies does not end the job.
std::string mpirun(int ranks) {
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
         "OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_rmaps_base_oversubscribe=1 "
         "OMPI_MCA_orte_enable_recovery=1 " +
         std::string(SHADERFIT_MPIEXEC) + " -np " + std::to_string(ranks) + " " +
         SHADERFIT_MPI_PATH;
}

const std::string& cannot_run_ranks() {
  static const std::string why = [] {
    if (!fs::exists(SHADERFIT_MPIEXEC) && run("command -v mpirun").status != 0)
      return std::string("mpirun not found");
    const Outcome r = run(mpirun(2) + " --version");
    if (r.status == 0) return std::string();
    return "mpirun cannot start 2 ranks here: " + r.output.substr(0, r.output.find('\n'));
  }();
  return why;
}

#define REQUIRE_MPIRUN() \
  if (!cannot_run_ranks().empty()) GTEST_SKIP() << "skipped: " << cannot_run_ranks()

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("shaderfit_mpi_batch_test_" + std::to_string(getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Eight functions under a candidate budget (results depend on the seed only).
std::string manifest(std::size_t evals) {
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
         "\"\ndomain = { x = [" + e[2] + "] }\n";
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

TEST(MpiBatch, TwoRanksGiveTheResultsOfOneProcess) {
  REQUIRE_MPIRUN();
  const fs::path dir = scratch("same");
  std::ofstream(dir / "m.toml") << manifest(20000);
  const std::string m = (dir / "m.toml").string();
  const Outcome one = run(std::string(SHADERFIT_CLI_PATH) + " batch " + m + " --out " +
                          (dir / "one").string() + " --parallel 1");
  ASSERT_EQ(one.status, 0) << one.output;
  const Outcome two = run(mpirun(2) + " batch " + m + " --out " + (dir / "two").string());
  ASSERT_EQ(two.status, 0) << two.output;
  const auto a = chosen(dir / "one"), b = chosen(dir / "two");
  EXPECT_EQ(a.size(), 8u);
  EXPECT_EQ(a, b);
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
  const fs::path dir = scratch("killed");
  std::ofstream(dir / "m.toml") << manifest(400000);
  const fs::path out = dir / "out", log = dir / "log";
  const std::string command = mpirun(2) + " batch " + (dir / "m.toml").string() + " --out " +
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
