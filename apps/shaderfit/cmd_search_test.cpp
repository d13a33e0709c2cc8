// shaderfit search through run_cli, in-process: the seed task, JSON output, and bad input.
#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "cli_test_util.hpp"
#include "shaderfit/data/fresnel_seed.hpp"

extern char** environ;

namespace shaderfit::cli {
namespace {

using testing::expect_bad_input;
using testing::run;
using testing::scratch_file;


TEST(CmdSearch, SeedTaskFindsTheSeedFormulaAndWritesJson) {
  const auto r = run({"search", "--dataset", "fresnel-seed", "--inputs", "r0,x", "--target", "R",
                      "--time", "60", "--strategy", "enumerate", "--stop-loss", "0.00035236",
                      "--stop-cost", "4", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("] mse="), std::string::npos);  // members as found, on stderr with --json -
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("front"));
  bool met = false;
  for (const auto& m : j["front"]) {
    ASSERT_TRUE(m["formula"].is_string());
    ASSERT_TRUE(m["cost"].is_number());
    ASSERT_TRUE(m["mse"].is_number());
    ASSERT_TRUE(m["time_s"].is_number());
    met = met || (m["cost"].get<double>() <= 4 && m["mse"].get<double>() <= 0.00035236);
  }
  EXPECT_TRUE(met) << r.out;
  EXPECT_EQ(j["summary"]["termination"], "target reached");
  EXPECT_EQ(j["inputs"], nlohmann::json({"r0", "x"}));
}

TEST(CmdSearch, TableForPeople) {
  const auto r =
      run({"search", "--dataset", "fresnel-seed", "--time", "0.2", "--strategy", "enumerate"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("formula"), std::string::npos);
  EXPECT_NE(r.out.find("] mse="), std::string::npos);
  EXPECT_NE(r.out.find("r0"), std::string::npos);
}

// Issue 42: no printed front has two members whose losses differ by less than the minimum step
// (1% by default); --min-step 0 prints every step; the JSON keeps every member.
TEST(CmdSearch, ThePrintedFrontHasNoNoiseSteps) {
  const std::vector<std::string> args = {"search", "--dataset", "fresnel-seed", "--inputs",
                                         "r0,x", "--target", "R", "--evals", "300000",
                                         "--threads", "1", "--quiet"};
  // The mse column of the table's rows, cheapest first.
  const auto losses = [](const std::string& out) {
    std::vector<double> v;
    const std::size_t head = out.find("  cost nodes");
    std::istringstream lines(out.substr(head));
    std::string line;
    std::getline(lines, line);
    while (std::getline(lines, line)) {
      std::istringstream cells(line);
      double cost = 0, mse = 0;
      std::size_t nodes = 0;
      if (!(cells >> cost >> nodes >> mse)) break;
      v.push_back(mse);
    }
    return v;
  };
  auto with_json = args;
  with_json.insert(with_json.end(), {"--json", scratch_file("steps.json", "")});
  const auto r = run(with_json);
  ASSERT_EQ(r.status, 0) << r.err;
  const std::vector<double> shown = losses(r.out);
  ASSERT_GE(shown.size(), 3u) << r.out;
  for (std::size_t k = 1; k < shown.size(); ++k)
    EXPECT_LE(shown[k], 0.99 * shown[k - 1] * (1 + 1e-3)) << r.out;  // 4 printed digits
  std::ifstream f(with_json.back());
  const auto j = nlohmann::json::parse(f);
  std::size_t minor = 0;
  for (const auto& m : j["front"]) minor += m.value("minor_step", false) ? 1 : 0;
  EXPECT_EQ(j["front"].size(), shown.size() + minor);
  if (minor > 0) {
    EXPECT_NE(r.out.find("not shown: each lowers the loss"), std::string::npos);
  }
  auto every = args;
  every.insert(every.end(), {"--min-step", "0"});
  const auto all = run(every);
  ASSERT_EQ(all.status, 0) << all.err;
  EXPECT_EQ(losses(all.out).size(), j["front"].size()) << all.out;
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--min-step", "0.9"}, "--min-step");
}

TEST(CmdSearch, SaysWhichFormulaIsChosenHowAndWhy) {
  const auto knee =
      run({"search", "--dataset", "fresnel-seed", "--time", "0.2", "--strategy", "enumerate"});
  ASSERT_EQ(knee.status, 0) << knee.err;
  EXPECT_NE(knee.out.find("\nchosen: "), std::string::npos) << knee.out;
  EXPECT_NE(knee.out.find("  how: the knee of the front"), std::string::npos) << knee.out;
  EXPECT_NE(knee.out.find("--choose knee, cost=N or error=E"), std::string::npos) << knee.out;
  EXPECT_NE(knee.out.find("  why: "), std::string::npos) << knee.out;
  const auto cheap = run({"search", "--dataset", "fresnel-seed", "--time", "0.2", "--strategy",
                          "enumerate", "--choose", "cost=0"});
  ASSERT_EQ(cheap.status, 0) << cheap.err;
  EXPECT_NE(cheap.out.find("  how: the most accurate member that costs at most 0"),
            std::string::npos)
      << cheap.out;
  for (const char* bad : {"cheapest", "cost=", "error=-1"})
    expect_bad_input({"search", "--dataset", "fresnel-seed", "--choose", bad}, "--choose");
}

TEST(CmdSearch, UnknownOperator) {
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--ops", "+,*,frob"},
                   "unknown operator 'frob'");
}

TEST(CmdSearch, VariableNotInTheData) {
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--inputs", "r0,theta"},
                   "no column 'theta'");
}

TEST(CmdSearch, TargetColumnMissing) {
  const std::string csv = scratch_file("search_no_target.csv", "x,y\n1,2\n2,3\n3,4\n");
  expect_bad_input({"search", "--data", csv, "--inputs", "x", "--target", "R"}, "no column 'R'");
}

TEST(CmdSearch, ZeroOrNegativeBudget) {
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--time", "0"},
                   "time budget must be positive");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--time", "-3"},
                   "time budget must be positive");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--evals", "0"},
                   "evaluation budget must be positive");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--evals", "-5"},
                   "evaluation budget must be positive");
}

TEST(CmdSearch, DataSetWithOneRow) {
  const std::string csv = scratch_file("search_one_row.csv", "x,y\n1,2\n");
  expect_bad_input({"search", "--data", csv, "--inputs", "x", "--target", "y"}, "1 row");
}

TEST(CmdSearch, AutoOperatorsAreResolvedShownAndRecorded) {
  const auto r = run({"search", "--dataset", "fresnel-seed", "--ops", "auto", "--evolve-ops",
                      "auto", "--time", "60", "--threads", "1", "--strategy", "enumerate",
                      "--max-enumeration-cost", "2", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("operators (auto): +,-,*,/,^,sqrt,exp2,log2,abs,min,max; the evolution "
                       "also pow,rsqrt,saturate"),
            std::string::npos)
      << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["options"]["operators"], "+,-,*,/,^,sqrt,exp2,log2,abs,min,max");
  EXPECT_EQ(j["options"]["evolution_operators"], "pow,rsqrt,saturate");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--ops", "auto,sqrt"},
                   "shaderfit: error: --ops: unknown operator 'auto'");
}

// Ranked by RDNA 2: the JSON names the target, and every member's cost is its rdna2 count.
TEST(CmdSearch, CostTargetRdna2) {
  const auto r = run({"search", "--dataset", "fresnel-seed", "--cost-target", "rdna2", "--evals",
                      "20000", "--threads", "1", "--quiet", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["options"]["cost"], "rdna2");
  ASSERT_FALSE(j["front"].empty());
  for (const auto& m : j["front"]) {
    const auto c = run({"cost", "--inputs", "r0,x", "--json", "-", m["formula"].get<std::string>()});
    ASSERT_EQ(c.status, 0) << c.err;
    EXPECT_EQ(m["cost"].get<double>(), nlohmann::json::parse(c.out)["targets"]["rdna2"]["instructions"].get<double>())
        << m["formula"];
  }
  const auto same = run({"search", "--dataset", "fresnel-seed", "--cost", "rdna3", "--evals", "2000",
                         "--threads", "1", "--quiet", "--json", "-"});
  ASSERT_EQ(same.status, 0) << same.err;
  EXPECT_EQ(nlohmann::json::parse(same.out)["options"]["cost"], "rdna3");
}

TEST(CmdSearch, OtherBadOptions) {
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--loss", "l7"}, "unknown loss 'l7'");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--cost", "watts"},
                   "unknown cost 'watts' (known: instructions, rdna2, rdna3, nodes)");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--cost-target", "rdna"},
                   "--cost: unknown cost 'rdna'");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--literals", "1,two"},
                   "not a number: 'two'");
  // Library errors name the field (SearchOptions::max_power); the command shows its flag.
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--max-power", "17"},
                   "shaderfit: error: --max-power: must be in [2, 16]");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--ops", "+,frob"},
                   "shaderfit: error: --ops: unknown operator 'frob'");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--islands", "0"},
                   "shaderfit: error: --islands: must be at least 1");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--symmetry", "foo"},
                   "not expected: foo");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--symmetry=foo"},
                   "Could not convert: --symmetry = foo");
}

// Odd data: the search fits x >= 0 and the front's formulas carry the reflection.
TEST(CmdSearch, SymmetricDataIsSearchedOnItsHalf) {
  std::string csv = "x,y\n";
  for (int i = -64; i <= 64; ++i) csv += fmt::format("{},{}\n", i / 64.0, std::atan(i / 64.0));
  const std::string path = scratch_file("atan.csv", csv);
  const auto r = run({"search", "--data", path, "--inputs", "x", "--target", "y", "--threads", "1",
                      "--evals", "20000", "--loss", "max_abs", "--quiet", "--json", "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("summary").at("symmetry").at("kind"), "odd");
  EXPECT_EQ(j.at("options").at("symmetry"), true);
  bool reflected = false;
  for (const auto& m : j.at("front"))
    reflected = reflected || m.at("formula").get<std::string>().starts_with("copysign(");
  EXPECT_TRUE(reflected) << r.out;
  const auto plain = run({"search", "--data", path, "--inputs", "x", "--target", "y", "--threads",
                          "1", "--evals", "2000", "--no-symmetry", "--quiet", "--json", "-"});
  ASSERT_EQ(plain.status, 0) << plain.err;
  EXPECT_TRUE(nlohmann::json::parse(plain.out).at("summary").at("symmetry").is_null());
}

// Issue 16's acceptance: from Schlick's formula under max |error|, the front has a member at
// no more than Schlick's cost (5) and max |error|. One thread and a count budget: deterministic.
TEST(CmdSearch, StartFromSchlickUnderMaxAbs) {
  Rng rng(1);
  const Dataset d = make_fresnel_seed_dataset(rng);
  const auto& r0 = d.numeric("r0").values;
  const auto& x = d.numeric("x").values;
  const auto& y = d.numeric("R").values;
  double schlick = 0;
  for (std::size_t i = 0; i < y.size(); ++i)
    schlick = std::max(schlick, std::abs(r0[i] + (1 - r0[i]) * std::pow(x[i], 5) - y[i]));
  const auto r = run({"search",
                      "--dataset",
                      "fresnel-seed",
                      "--inputs",
                      "r0,x",
                      "--target",
                      "R",
                      "--loss",
                      "max_abs",
                      "--threads",
                      "1",
                      "--evals",
                      "20000",
                      "--time",
                      "1000",
                      "--start",
                      "r0 + (1 - r0)*x^5",
                      "--start",
                      "r0 + (x - r0)*x^4",
                      "--json",
                      "-"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["options"]["start"], nlohmann::json({"r0 + (1 - r0)*x^5", "r0 + (x - r0)*x^4"}));
  bool met = false, refitted = false;
  for (const auto& m : j["front"]) {
    met = met || (m["cost"].get<double>() <= 5 && m["max_abs"].get<double>() <= schlick);
    // Schlick's 1 refitted to the minimax: 0.88, max |error| 0.119 against 0.177; it stays
    // unless a member dominates it (the final minimax polish gives the enumeration's cost-3
    // (r0 a - x)^4 + r0 0.116).
    refitted = refitted || (m["cost"].get<double>() <= 5 && m["max_abs"].get<double>() <= 0.119 &&
                            (m["origin"] == "start" || m["cost"].get<double>() < 5));
  }
  EXPECT_TRUE(met) << r.out;
  EXPECT_TRUE(refitted) << r.out;
}

TEST(CmdSearch, BadStartFormula) {
  // The formula's position is the line, its column the column.
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--start", "r0 + y"},
                   "shaderfit: error: --start:1:6: unknown variable 'y' (known: r0, x)");
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--start", "x", "--start", "r0 *"},
                   "shaderfit: error: --start:2:5: unexpected end of formula");
}

// Seed 001's Fresnel data, every 16th row (256), as CSV: a short search for the tests below.
std::string small_fresnel_csv() {
  Rng rng(1);
  const Dataset d = make_fresnel_seed_dataset(rng);
  const auto& r0 = d.numeric("r0").values;
  const auto& x = d.numeric("x").values;
  const auto& y = d.numeric("R").values;
  std::string csv = "r0,x,R\n";
  for (std::size_t i = 0; i < y.size(); i += 16)
    csv += fmt::format("{},{},{}\n", r0[i], x[i], y[i]);
  return scratch_file("search_small_fresnel.csv", csv);
}

// One thread, no stop by the clock: the same options give the same search.
std::vector<std::string> evolution_args(const std::string& csv) {
  return {"search", "--data",       csv,  "--inputs",  "r0,x", "--target", "R",    "--strategy",
          "evolve", "--population", "16", "--threads", "1",    "--time",   "1000", "--quiet"};
}

// The start formula seeds the evolution; with one thread and a count budget the run repeats.
TEST(CmdSearch, StartIsReproducible) {
  std::vector<std::string> args = evolution_args(small_fresnel_csv());
  for (const char* extra : {"--start", "r0 + (1.1 - r0)*x^5", "--evals", "3000", "--json", "-"})
    args.emplace_back(extra);
  const auto a = run(args), b = run(args);
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  ASSERT_FALSE(ja["front"].empty());
  for (auto* j : {&ja, &jb})
    for (auto& m : (*j)["front"]) m.erase("time_s");
  EXPECT_EQ(ja["front"], jb["front"]);
  EXPECT_GT(ja["summary"]["generations"].get<int>(), 0);
}

std::string checkpoint_path(const std::string& name) {
  std::string path = scratch_file(name, "");
  std::filesystem::remove(path);
  return path;
}

nlohmann::json checkpoint_body(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int i = 0; i < 4; ++i) std::getline(in, line);  // the header
  return nlohmann::json::parse(in);
}

void expect_same_search(const nlohmann::json& a, const nlohmann::json& b) {
  for (const char* k : {"candidates", "node_evaluations", "generations", "termination"})
    EXPECT_EQ(a["summary"][k], b["summary"][k]) << k;
  ASSERT_EQ(a["front"].size(), b["front"].size());
  for (std::size_t i = 0; i < a["front"].size(); ++i) {
    const auto& x = a["front"][i];
    const auto& y = b["front"][i];
    // Everything but when it was found (time_s).
    for (const char* k : {"formula", "cost", "nodes", "loss", "mse", "max_abs", "origin",
                          "float32_max_abs_diff", "float32_stable"})
      EXPECT_EQ(x[k], y[k]) << k << " of member " << i;
  }
}

TEST(CmdSearch, KilledBySigtermThenResumedEndsAsTheUninterruptedRun) {
  const std::string csv = small_fresnel_csv();
  const std::string ckpt = checkpoint_path("search_sigterm.ckpt");
  // B: the real binary, with no budget it could reach, checkpointing at every generation;
  // SIGTERM once it has run some generations.
  std::vector<std::string> args = evolution_args(csv);
  args.insert(args.begin(), SHADERFIT_CLI_PATH);
  for (const char* a : {"--evals", "1000000000", "--checkpoint-every", "0", "--checkpoint"})
    args.emplace_back(a);
  args.push_back(ckpt);
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t quiet;
  posix_spawn_file_actions_init(&quiet);
  posix_spawn_file_actions_addopen(&quiet, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&quiet, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t child = 0;
  ASSERT_EQ(posix_spawn(&child, argv[0], &quiet, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&quiet);
  using std::chrono::steady_clock;
  auto wait_for = [&](auto done, double seconds) {  // done() is called until true, not after
    const auto until = steady_clock::now() + std::chrono::duration<double>(seconds);
    while (steady_clock::now() < until) {
      if (done()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
  };
  const bool started = wait_for([&] { return std::filesystem::exists(ckpt); }, 60);
  if (started) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  kill(child, SIGTERM);
  int status = 0;
  const bool ended = wait_for([&] { return waitpid(child, &status, WNOHANG) == child; }, 60);
  if (!ended) {
    kill(child, SIGKILL);
    waitpid(child, &status, 0);
  }
  ASSERT_TRUE(started);
  ASSERT_TRUE(ended) << "SIGTERM did not stop the search";
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);

  // A budget a few generations past the checkpoint; A runs it uninterrupted, B resumes to it.
  const nlohmann::json body = checkpoint_body(ckpt);
  ASSERT_EQ(body["phase"], "evolution");
  const auto budget = std::to_string(body["clock"]["candidates"].get<std::uint64_t>() + 300);
  const std::string a_json = checkpoint_path("search_sigterm_a.json");
  const std::string b_json = checkpoint_path("search_sigterm_b.json");
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> v = evolution_args(csv);
    v.insert(v.end(), extra.begin(), extra.end());
    return v;
  };
  const auto a = run(with({"--evals", budget, "--json", a_json}));
  ASSERT_EQ(a.status, 0) << a.err;
  const auto b = run(with({"--evals", budget, "--json", b_json, "--resume", ckpt}));
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_NE(b.out.find("resuming from"), std::string::npos) << b.out;
  std::ifstream fa(a_json), fb(b_json);
  expect_same_search(nlohmann::json::parse(fa), nlohmann::json::parse(fb));
}

// The start formulas are a Search option: a checkpoint records them and a resume must repeat
// them.
TEST(CmdSearch, CheckpointRecordsTheStartFormulas) {
  const std::string path = checkpoint_path("search_start.ckpt");
  std::vector<std::string> args = evolution_args(small_fresnel_csv());
  for (const char* extra : {"--start", "r0 + (1.1 - r0)*x^5", "--evals", "1500"})
    args.emplace_back(extra);
  std::vector<std::string> first = args;
  first.insert(first.end(), {"--checkpoint", path});
  ASSERT_EQ(run(first).status, 0);
  std::vector<std::string> resumed = args;
  resumed.insert(resumed.end(), {"--resume", path});
  const auto r = run(resumed);
  EXPECT_EQ(r.status, 0) << r.err;
  std::vector<std::string> other = evolution_args(small_fresnel_csv());
  other.insert(other.end(), {"--evals", "1500", "--resume", path});
  expect_bad_input(other, "made with start = r0 + (1.1 - r0)*x^5");
}

TEST(CmdSearch, DamagedOrForeignCheckpointIsRefused) {
  const std::string csv = small_fresnel_csv();
  const std::string ckpt = checkpoint_path("search_damaged.ckpt");
  std::vector<std::string> args = evolution_args(csv);
  for (const char* a : {"--evals", "100", "--checkpoint"}) args.emplace_back(a);
  args.push_back(ckpt);
  ASSERT_EQ(run(args).status, 0);
  std::string text;
  {
    std::ifstream in(ckpt, std::ios::binary);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GT(text.size(), 200u);
  std::string damaged = text;
  damaged[damaged.size() / 2] ^= 0x04;
  const std::string bad = scratch_file("search_damaged_copy.ckpt", damaged);
  std::vector<std::string> resume = evolution_args(csv);
  for (const char* a : {"--evals", "200", "--resume"}) resume.emplace_back(a);
  resume.push_back(bad);
  expect_bad_input(resume, "damaged checkpoint");
  resume.back() = scratch_file("search_not_a.ckpt", "r0,x,R\n1,2,3\n");
  expect_bad_input(resume, "not a shaderfit checkpoint");
  resume.back() = scratch_file("search_cut.ckpt", text.substr(0, text.size() / 3));
  expect_bad_input(resume, "damaged checkpoint");
  // A sound checkpoint, resumed with another seed.
  resume.back() = ckpt;
  resume.insert(resume.end(), {"--seed", "9"});
  expect_bad_input(resume, "seed = 1; this search has seed = 9");
}

// The most significant digits of any number in `text` (leading zeros and exponents aside).
int most_significant_digits(const std::string& text) {
  static const std::regex number(R"((\d*\.?\d+)(?:[eE][-+]?\d+)?)");
  int most = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number);
       it != std::sregex_iterator(); ++it) {
    std::string digits = (*it)[1].str();
    std::erase(digits, '.');
    const auto first = digits.find_first_not_of('0');
    if (first != std::string::npos) most = std::max(most, static_cast<int>(digits.size() - first));
  }
  return most;
}

// The formulas of the lines printed as members are found ("[12.3 ms] mse=... cost=4  FORMULA").
std::vector<std::string> progress_formulas(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.starts_with("[") && line.find("] mse=") != std::string::npos)
      out.push_back(line.substr(line.find("  ", line.find(" cost=")) + 2));
  return out;
}

// The README's first command for people: constants as short as float32 allows (no more than 9
// significant digits), no doubled sign; the JSON keeps the exact constants and adds the text
// for people.
TEST(CmdSearch, ConstantsForPeopleAreShortAndSumsHaveOneSign) {
  std::vector<std::string> args = evolution_args(small_fresnel_csv());
  args.pop_back();  // --quiet: the members as found are checked too
  for (const char* extra : {"--evals", "20000", "--json", "-"}) args.emplace_back(extra);
  const auto r = run(args);
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_FALSE(progress_formulas(r.err).empty()) << r.err;
  EXPECT_LE(most_significant_digits(r.err), 9) << r.err;
  EXPECT_EQ(r.err.find("- -"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("+ -"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  int exact_digits = 0;
  for (const auto& m : j["front"]) {
    ASSERT_TRUE(m["formula_display"].is_string()) << m;
    const std::string shown = m["formula_display"].get<std::string>();
    EXPECT_NE(r.err.find(shown), std::string::npos) << shown;
    EXPECT_LE(most_significant_digits(shown), 9) << shown;
    exact_digits = std::max(exact_digits, most_significant_digits(m["formula"].get<std::string>()));
  }
  EXPECT_GT(exact_digits, 9) << "no fitted constant to shorten: " << r.out;

  // --digits N: N significant digits.
  std::vector<std::string> three = evolution_args(small_fresnel_csv());
  three.pop_back();
  for (const char* extra : {"--evals", "20000", "--digits", "3"}) three.emplace_back(extra);
  const auto d = run(three);
  ASSERT_EQ(d.status, 0) << d.err;
  const std::vector<std::string> formulas = progress_formulas(d.out);
  ASSERT_FALSE(formulas.empty()) << d.out;
  for (const std::string& f : formulas) EXPECT_LE(most_significant_digits(f), 3) << f;
  expect_bad_input({"search", "--dataset", "fresnel-seed", "--digits", "18"},
                   "shaderfit: error: --digits: significant digits must be 1 to 17");
}

}  // namespace
}  // namespace shaderfit::cli
