#include "shaderfit/batch/manifest.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "shaderfit/core/error.hpp"

namespace shaderfit {
namespace {

namespace fs = std::filesystem;

// A fresh folder for one test's files, named for the process (ctest runs tests side by side).
class Scratch {
 public:
  explicit Scratch(const std::string& name)
      : dir_(fs::temp_directory_path() / ("shaderfit_manifest_test_" + std::to_string(::getpid())) /
             name) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~Scratch() { fs::remove_all(dir_); }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;

  // Writes the file and returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }

 private:
  fs::path dir_;
};

// Schlick's Fresnel and a little more, over a grid of r0 and x: columns r0, x, R.
std::string fresnel_csv(double extra = 0.01) {
  std::string csv = "r0,x,R\n";
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j <= 10; ++j) {
      const double r0 = 0.02 + 0.2 * i, x = 0.1 * j;
      const double r = r0 + (1 - r0) * std::pow(1 - x, 5) + extra * x * (1 - x);
      csv += std::to_string(r0) + "," + std::to_string(x) + "," + std::to_string(r) + "\n";
    }
  }
  return csv;
}

// The manifest of issue 30.
const std::string kIssueManifest = R"toml([defaults]
time = 5
loss = "max_abs"

[[function]]
name = "fast_tanh"
reference = "tanh(x)"
domain = { x = [0.0, 4.0] }
samples = 200

[[function]]
name = "fast_fresnel"
data = "fresnel.csv"          # a CSV: inputs and target as `search --data` picks them
baseline = "r0 + (1 - r0)*x^5"
goal = "beat-baseline"
)toml";

// The manifest's one bad entry, which must be the whole manifest's only entry.
BadManifestEntry only_bad(const std::string& text, const Scratch& dir) {
  dir.write("fresnel.csv", fresnel_csv());
  const Manifest m = read_manifest(dir.write("m.toml", text));
  EXPECT_TRUE(m.entries.empty());
  EXPECT_EQ(m.bad.size(), 1u);
  return m.bad.empty() ? BadManifestEntry{} : m.bad[0];
}

// Runs `f`, which must throw Error at this line of the manifest with a message containing `part`.
void expect_manifest_error(const std::function<void()>& f, const std::string& path, int line,
                           const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no error; expected: " << part;
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, path) << e.what();
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

// docs/batch.md's worked example.
TEST(Manifest, TheDocsExampleReads) {
  const Manifest m = read_manifest(SHADERFIT_SOURCE_DIR "/docs/examples/shader-library.toml");
  ASSERT_TRUE(m.bad.empty()) << m.bad[0].message;
  std::vector<std::string> names;
  for (const ManifestEntry& e : m.entries) names.push_back(e.name);
  EXPECT_EQ(names, (std::vector<std::string>{"fast_fresnel", "fast_acos", "fast_erf", "fast_tanh",
                                             "srgb_encode"}));
}

TEST(Manifest, TheIssuesManifestReadsAsWritten) {
  Scratch dir("issue");
  dir.write("fresnel.csv", fresnel_csv());
  const std::string path = dir.write("m.toml", kIssueManifest);
  const Manifest m = read_manifest(path);
  EXPECT_EQ(m.path, path);
  ASSERT_TRUE(m.bad.empty()) << m.bad[0].message;
  ASSERT_EQ(m.entries.size(), 2u);

  const ManifestEntry& tanh = m.entries[0];
  EXPECT_EQ(tanh.name, "fast_tanh");
  EXPECT_EQ(tanh.line, 5);
  EXPECT_EQ(tanh.options.time_limit_s, 5.0);
  EXPECT_EQ(tanh.options.loss, Loss::MaxAbs);
  EXPECT_EQ(tanh.options.threads, 1);
  EXPECT_EQ(tanh.problem.reference.formula, "tanh(x)");
  EXPECT_EQ(tanh.problem.domain, std::vector<std::string>{"x=0:4"});
  EXPECT_EQ(tanh.problem.inputs, std::vector<std::string>{"x"});
  EXPECT_EQ(tanh.goal.kind, BatchGoal::Kind::Knee);
  EXPECT_TRUE(tanh.baseline.empty());
  ASSERT_NE(tanh.loaded, nullptr);
  EXPECT_EQ(tanh.loaded->data.rows(), 200u);
  EXPECT_NE(tanh.loaded->reference, nullptr);

  const ManifestEntry& fresnel = m.entries[1];
  EXPECT_EQ(fresnel.name, "fast_fresnel");
  EXPECT_EQ(fresnel.line, 11);
  EXPECT_EQ(fresnel.options.time_limit_s, 5.0);
  EXPECT_EQ(fresnel.options.loss, Loss::MaxAbs);
  EXPECT_EQ(fresnel.problem.csv_path, (fs::path(path).parent_path() / "fresnel.csv").string());
  EXPECT_EQ(fresnel.baseline, "r0 + (1 - r0)*x^5");
  EXPECT_EQ(fresnel.goal.kind, BatchGoal::Kind::BeatBaseline);
  ASSERT_NE(fresnel.loaded, nullptr);
  EXPECT_EQ(fresnel.loaded->inputs, (std::vector<std::string>{"r0", "x"}));
  EXPECT_EQ(fresnel.loaded->target, "R");
  EXPECT_EQ(fresnel.loaded->data.rows(), 55u);
  EXPECT_EQ(fresnel.problem.target, "R");

  // The hash: stable across reads, and changed by the entry or its CSV.
  EXPECT_EQ(tanh.hash.size(), 16u);
  EXPECT_NE(tanh.hash, fresnel.hash);
  const Manifest again = read_manifest(path);
  EXPECT_EQ(again.entries[0].hash, tanh.hash);
  EXPECT_EQ(again.entries[1].hash, fresnel.hash);

  std::string edited = kIssueManifest;
  edited.replace(edited.find("[0.0, 4.0]"), 10, "[0.0, 3.0]");
  const Manifest other_domain = read_manifest(dir.write("m.toml", edited));
  EXPECT_NE(other_domain.entries[0].hash, tanh.hash);
  EXPECT_EQ(other_domain.entries[1].hash, fresnel.hash);

  dir.write("fresnel.csv", fresnel_csv(0.02));
  const Manifest other_csv = read_manifest(path);
  EXPECT_EQ(other_csv.entries[0].hash, other_domain.entries[0].hash);
  EXPECT_NE(other_csv.entries[1].hash, fresnel.hash);

  // What a hash covers besides: options, goal, baseline, weights.
  edited = kIssueManifest + "seed = 7\n";
  EXPECT_NE(read_manifest(dir.write("m.toml", edited)).entries[1].hash, other_csv.entries[1].hash);
}

TEST(Manifest, EntriesOverrideDefaultsAndTakeEveryOptionByName) {
  Scratch dir("options");
  const std::string path = dir.write("m.toml", R"toml([defaults]
max_nodes = 30
operators = ["+", "-", "*"]
evals = 5000
samples = 200

[[function]]
name = "a"
reference = "x^2 + 1"
domain = { x = "0:1" }

[[function]]
name = "b"
reference = "x*y"
domain = { y = [0, 1], x = [-1, "pi/2"] }
samples = 0x40
operators = "+,-,*,/"
evolution_operators = []
max_nodes = 12
seed = 42
time = 2.5
literals = [0.5, 1, 2.25]
start = ["x*y", "min(x, y)"]
uniform = ["y"]
symmetry = false
stop_at = [1e-3, 6]
loss = "mse"
threads = 3
goal = { cost = 6 }
across_ranks = true
)toml");
  const Manifest m = read_manifest(path);
  ASSERT_TRUE(m.bad.empty()) << m.bad[0].message;
  ASSERT_EQ(m.entries.size(), 2u);

  const SearchOptions& a = m.entries[0].options;
  EXPECT_EQ(a.max_nodes, 30u);
  EXPECT_EQ(a.operators, (std::vector<Op>{Op::Add, Op::Sub, Op::Mul}));
  EXPECT_EQ(a.max_candidates, 5000);
  EXPECT_EQ(a.time_limit_s, SearchOptions{}.time_limit_s);
  EXPECT_EQ(a.threads, 1);
  EXPECT_EQ(m.entries[0].problem.domain, std::vector<std::string>{"x=0:1"});
  EXPECT_EQ(m.entries[0].loaded->data.rows(), 200u);

  const ManifestEntry& b = m.entries[1];
  EXPECT_EQ(b.options.max_nodes, 12u);
  EXPECT_EQ(b.options.operators, (std::vector<Op>{Op::Add, Op::Sub, Op::Mul, Op::Div}));
  EXPECT_TRUE(b.options.evolution_operators.empty());
  EXPECT_EQ(b.options.max_candidates, 5000);
  EXPECT_EQ(b.options.seed, 42u);
  EXPECT_EQ(b.options.time_limit_s, 2.5);
  EXPECT_EQ(b.options.literals, (std::vector<double>{0.5, 1, 2.25}));
  EXPECT_EQ(b.options.start, (std::vector<std::string>{"x*y", "min(x, y)"}));
  EXPECT_EQ(b.options.uniform, std::vector<std::string>{"y"});
  EXPECT_FALSE(b.options.symmetry);
  ASSERT_TRUE(b.options.stop_at.has_value());
  EXPECT_EQ(b.options.stop_at->max_loss, 1e-3);
  EXPECT_EQ(b.options.stop_at->max_cost, 6);
  EXPECT_EQ(b.options.loss, Loss::Mse);
  EXPECT_EQ(b.options.threads, 3);
  EXPECT_EQ(b.goal.kind, BatchGoal::Kind::MaxCost);
  EXPECT_EQ(b.goal.limit, 6);
  EXPECT_FALSE(m.entries[0].across_ranks);
  EXPECT_TRUE(b.across_ranks);
  // The domain in the manifest's order, and the inputs in the same order.
  EXPECT_EQ(b.problem.domain, (std::vector<std::string>{"y=0:1", "x=-1:pi/2"}));
  EXPECT_EQ(b.loaded->inputs, (std::vector<std::string>{"y", "x"}));
  EXPECT_EQ(b.problem.samples, 64u);
}

TEST(Manifest, GoalsAndTheirText) {
  Scratch dir("goals");
  const std::string path = dir.write("m.toml", R"toml(
[[function]]
name = "a"
reference = "exp(x)"
domain = { x = [0, 1] }
samples = 200
goal = "error = 1e-3"

[[function]]
name = "b"
reference = "exp(x)"
domain = { x = [0, 1] }
samples = 200
goal = { error = 0.5 }

[[function]]
name = "c"
reference = "exp(x)"
domain = { x = [0, 1] }
samples = 200
goal = "cost=7"
)toml");
  const Manifest m = read_manifest(path);
  ASSERT_EQ(m.entries.size(), 3u);
  EXPECT_EQ(batch_goal_text(m.entries[0].goal), "error=0.001");
  EXPECT_EQ(batch_goal_text(m.entries[1].goal), "error=0.5");
  EXPECT_EQ(batch_goal_text(m.entries[2].goal), "cost=7");
  EXPECT_EQ(batch_goal_text({}), "knee");
  EXPECT_EQ(batch_goal_text({BatchGoal::Kind::BeatBaseline, 0}), "beat-baseline");
}

TEST(Manifest, AShaderFunctionIsReadBesideTheManifest) {
  Scratch dir("shader");
  dir.write("g1.glsl",
            "float G1(float n_dot_v, float alpha) {\n"
            "  float a2 = alpha * alpha;\n"
            "  return 2.0 * n_dot_v / (n_dot_v + sqrt(a2 + (1.0 - a2) * n_dot_v * n_dot_v));\n"
            "}\n");
  const std::string text = R"toml([defaults]
samples = 200

[[function]]
name = "smith_g1"
reference_file = "g1.glsl"
function = "G1"
domain = { n_dot_v = [0.01, 1], alpha = [0.05, 1] }
)toml";
  const std::string path = dir.write("m.toml", text);
  const Manifest m = read_manifest(path);
  ASSERT_TRUE(m.bad.empty()) << m.bad[0].message;
  const ManifestEntry& e = m.entries[0];
  EXPECT_EQ(e.problem.reference.shader_path, (fs::path(path).parent_path() / "g1.glsl").string());
  EXPECT_NE(e.problem.reference.shader_source.find("float G1"), std::string::npos);
  EXPECT_EQ(e.problem.samples, 200u);  // from [defaults]
  EXPECT_EQ(e.loaded->inputs, (std::vector<std::string>{"n_dot_v", "alpha"}));

  // The shader's text is part of the hash; a function the file lacks is located at its key.
  dir.write("g1.glsl", "float G1(float n_dot_v, float alpha) { return n_dot_v * alpha; }\n");
  EXPECT_NE(read_manifest(path).entries[0].hash, e.hash);
  std::string other = text;
  other.replace(other.find("\"G1\""), 4, "\"G2\"");
  const Manifest bad = read_manifest(dir.write("m.toml", other));
  ASSERT_EQ(bad.bad.size(), 1u);
  EXPECT_NE(bad.bad[0].message.find(":6:18: entry 'smith_g1': function 'G2' is not in "),
            std::string::npos)
      << bad.bad[0].message;
}

TEST(Manifest, WeightsNameAColumnThatIsNoInput) {
  Scratch dir("weights");
  dir.write("w.csv", "x,w,y\n0,1,0\n0.5,2,0.25\n1,1,1\n1.5,0.5,2.25\n");
  const std::string path = dir.write("m.toml", R"toml(
[[function]]
name = "a"
data = "w.csv"
weights = "w"

[[function]]
name = "b"
data = "w.csv"
weights = "v"
)toml");
  const Manifest m = read_manifest(path);
  ASSERT_EQ(m.entries.size(), 1u);
  EXPECT_EQ(m.entries[0].weights, "w");
  EXPECT_EQ(m.entries[0].loaded->inputs, std::vector<std::string>{"x"});
  EXPECT_EQ(m.entries[0].loaded->target, "y");
  ASSERT_EQ(m.bad.size(), 1u);
  EXPECT_NE(m.bad[0].message.find(":10:11: entry 'b': weights: no column 'v'"), std::string::npos)
      << m.bad[0].message;
}

TEST(Manifest, ACsvWithAGapIsAnErrorOrItsRowsDropped) {
  Scratch dir("gaps");
  dir.write("g.csv", "x,y\n0,0\n0.5,\n1,1\n1.5,2.25\n");
  const std::string path = dir.write("m.toml", R"toml(
[[function]]
name = "kept"
data = "g.csv"
drop_missing = true

[[function]]
name = "refused"
data = "g.csv"
)toml");
  const Manifest m = read_manifest(path);
  ASSERT_EQ(m.entries.size(), 1u);
  EXPECT_TRUE(m.entries[0].problem.drop_missing_rows);
  EXPECT_EQ(m.entries[0].loaded->data.rows(), 3u);
  ASSERT_EQ(m.bad.size(), 1u);
  EXPECT_NE(m.bad[0].message.find("column 'y' is numbers but for 1 cell: this one is empty (fix "
                                  "them, or drop their rows: drop_missing = true)"),
            std::string::npos)
      << m.bad[0].message;
}

TEST(Manifest, TheDisplayLossTakesASceneAndItsWeights) {
  Scratch dir("display");
  const std::string path = dir.write("m.toml", R"toml(
[defaults]
loss = "display"

[[function]]
name = "fresnel_f"
reference = "fresnel-dielectric-f0"
scene = "sphere"

[[function]]
name = "flat"
reference = "x^2"
domain = { x = [0, 1] }
)toml");
  const Manifest m = read_manifest(path);
  ASSERT_EQ(m.entries.size(), 1u) << (m.bad.empty() ? "" : m.bad[0].message);
  const ManifestEntry& e = m.entries[0];
  EXPECT_EQ(e.options.loss, Loss::Display);
  ASSERT_TRUE(e.problem.scene.has_value());
  EXPECT_EQ(e.problem.scene->kind, SceneKind::Sphere);
  EXPECT_EQ(e.problem.scene->term, ShadingTerm::F);
  ASSERT_TRUE(e.loaded->scene);
  EXPECT_EQ(e.loaded->display_weights.size(), e.loaded->data.rows());
  // A problem without a scene: the loss key, where [defaults] gives it.
  ASSERT_EQ(m.bad.size(), 1u);
  EXPECT_NE(m.bad[0].message.find(":3:8: entry 'flat': loss: the display loss needs a scene"),
            std::string::npos)
      << m.bad[0].message;
}

TEST(Manifest, BadEntriesSayWhichAndWhere) {
  Scratch dir("bad");
  auto expect_bad = [&](const std::string& text, const std::string& name, int line,
                        const std::string& part) {
    const BadManifestEntry b = only_bad(text, dir);
    EXPECT_EQ(b.name, name) << text;
    EXPECT_EQ(b.line, line) << text;
    EXPECT_NE(b.message.find(part), std::string::npos) << b.message;
  };
  // An unknown key: the entry, the line and column of the key, the known keys.
  expect_bad("[[function]]\nname = \"fast_fresnel\"\ndata = \"fresnel.csv\"\ntme = 5\n",
             "fast_fresnel", 1,
             "m.toml:4:1: entry 'fast_fresnel': unknown key 'tme' (known: name, data,");
  expect_bad("[[function]]\nname = \"f\"\n", "f", 1,
             "m.toml:1: entry 'f': no data: give a CSV file, a built-in data set, or a reference");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"fresnel.csv\"\ndataset = \"fresnel-seed\"\n",
             "f", 1, "m.toml:4:11: entry 'f': give one source of data");
  expect_bad("[[function]]\nname = \"f\"\nreference = \"tanhh(x)\"\ndomain = { x = [0, 1] }\n", "f",
             1, "m.toml:3:13: entry 'f': reference:1:1: unknown function 'tanhh'");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"missing.csv\"\n", "f", 1,
             "m.toml:3:8: entry 'f': cannot open '");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"fresnel.csv\"\nmax_nodes = \"many\"\n", "f", 1,
             "m.toml:4:13: entry 'f': max_nodes: not an integer in range: 'many'");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"fresnel.csv\"\ndrop_missing = \"yes\"\n", "f", 1,
             "m.toml:4:16: entry 'f': drop_missing: expected true or false, got a string");
  expect_bad("[[function]]\nname = \"f\"\nreference = \"x\"\ndomain = { x = [0, 1] }\n"
             "drop_missing = true\n",
             "f", 1,
             "m.toml:5:16: entry 'f': dropping rows with gaps is for a CSV file, not for a "
             "reference");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"fresnel.csv\"\nmax_power = 100\n", "f", 1,
             "m.toml:4:13: entry 'f': max_power: must be in");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"fresnel.csv\"\noperators = \"+,foo\"\n", "f", 1,
             "m.toml:4:13: entry 'f': operators: unknown operator 'foo'");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"fresnel.csv\"\ngoal = \"beat-baseline\"\n", "f",
             1, "m.toml:4:8: entry 'f': goal beat-baseline needs a baseline");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"fresnel.csv\"\nbaseline = \"r0 + y\"\n", "f", 1,
             "m.toml:4:12: entry 'f': baseline:1:6: unknown variable 'y'");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"fresnel.csv\"\ngoal = \"fast\"\n", "f", 1,
             "m.toml:4:8: entry 'f': goal: expected \"knee\"");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"fresnel.csv\"\nacross_ranks = 1\n", "f", 1,
             "m.toml:4:16: entry 'f': across_ranks: expected true or false");
  expect_bad("[[function]]\nname = \"2f\"\ndata = \"fresnel.csv\"\n", "2f", 1,
             "m.toml:2:8: entry '2f': name: not a C identifier");
  expect_bad("[[function]]\ndata = \"fresnel.csv\"\n", "function 1", 1,
             "m.toml:1: function 1: no name");
  expect_bad(
      "[[function]]\nname = \"f\"\nreference = \"x\"\ndomain = { x = [1, 0] }\nsamples = 200\n",
      "f", 1, "m.toml:4:16: entry 'f': ");
  expect_bad("[[function]]\nname = \"f\"\nreference = \"x*y\"\ndomain = { x = [0, 1] }\n", "f", 1,
             "m.toml:4:10: entry 'f': no domain for variable 'y'");
  expect_bad(
      "[[function]]\nname = \"f\"\nreference = \"a\"\ndefine = [\"a = x +\"]\n"
      "domain = { x = [0, 1] }\n",
      "f", 1, "m.toml:4:11: entry 'f': define:1:");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"fresnel.csv\"\ntime = 1\ntime_limit_s = 2\n",
             "f", 1, "m.toml:5:1: entry 'f': time_limit_s: 'time' sets time_limit_s already");
  expect_bad("[[function]]\nname = \"f\"\ndata = \"fresnel.csv\"\nsamples = \"many\"\n", "f", 1,
             "m.toml:4:11: entry 'f': samples: expected an integer > 0, got a string");
}

TEST(Manifest, TwoEntriesOfOneNameNameBothLines) {
  Scratch dir("names");
  dir.write("fresnel.csv", fresnel_csv());
  const Manifest m = read_manifest(dir.write("m.toml", R"toml([[function]]
name = "f"
data = "fresnel.csv"

[[function]]
name = "f"
data = "fresnel.csv"
)toml"));
  ASSERT_EQ(m.entries.size(), 1u);
  EXPECT_EQ(m.entries[0].line, 1);
  ASSERT_EQ(m.bad.size(), 1u);
  EXPECT_EQ(m.bad[0].name, "f");
  EXPECT_EQ(m.bad[0].line, 5);
  EXPECT_NE(m.bad[0].message.find("m.toml:6:8: entry 'f': name: the entry at line 1 has it too"),
            std::string::npos)
      << m.bad[0].message;
}

TEST(Manifest, OneBadEntryLeavesTheOthersUnlessStrict) {
  Scratch dir("strict");
  dir.write("fresnel.csv", fresnel_csv());
  const std::string path = dir.write("m.toml", R"toml([[function]]
name = "good"
data = "fresnel.csv"

[[function]]
name = "bad"
data = "fresnel.csv"
tme = 5

[[function]]
name = "also_good"
dataset = "fresnel-seed"
data_seed = 3
)toml");
  const Manifest m = read_manifest(path);
  ASSERT_EQ(m.entries.size(), 2u);
  EXPECT_EQ(m.entries[0].name, "good");
  EXPECT_EQ(m.entries[1].name, "also_good");
  EXPECT_EQ(m.entries[1].problem.dataset_seed, 3u);
  ASSERT_EQ(m.bad.size(), 1u);
  EXPECT_EQ(m.bad[0].name, "bad");
  EXPECT_EQ(m.bad[0].line, 5);
  EXPECT_EQ(m.bad[0].message.rfind(path + ":8:1: entry 'bad': unknown key 'tme'", 0), 0u)
      << m.bad[0].message;
  expect_manifest_error([&] { (void)read_manifest(path, true); }, path, 8,
                        "entry 'bad': unknown key 'tme'");
}

TEST(Manifest, BadManifestsThrowAtTheirLine) {
  Scratch dir("manifest");
  dir.write("fresnel.csv", fresnel_csv());
  auto expect_throws = [&](const std::string& text, int line, const std::string& part) {
    const std::string path = dir.write("m.toml", text);
    expect_manifest_error([&] { (void)read_manifest(path); }, path, line, part);
  };
  // A TOML syntax error at its file, line and column.
  expect_throws("[[function]]\nname = \"f\"\ndata = [1,\n", 3, "encountered end-of-file");
  try {
    (void)read_manifest(dir.write("m.toml", "[[function]]\nname = \"f\n"));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().line, 2);
    EXPECT_GT(e.where().column, 0);
  }
  expect_throws("[defaults]\ntime = 5\n\n[function_]\nname = \"f\"\n", 4,
                "unknown key 'function_' (known: defaults, function)");
  expect_throws("[defaults]\ntime = 5\n", 0, "no [[function]] entry");
  expect_throws("[function]\nname = \"f\"\n", 1, "function: expected [[function]] tables");
  expect_throws("[defaults]\ntme = 5\n[[function]]\nname = \"f\"\n", 2,
                "defaults: unknown key 'tme'");
  expect_throws("[defaults]\nmax_power = 1\n[[function]]\nname = \"f\"\n", 2,
                "defaults: max_power: must be in");
  expect_throws("[defaults]\nbaseline = \"x\"\n[[function]]\nname = \"f\"\n", 2,
                "defaults: 'baseline' is for an entry");
  expect_manifest_error(
      [&] { (void)read_manifest((fs::temp_directory_path() / "nope.toml").string()); },
      (fs::temp_directory_path() / "nope.toml").string(), 0, "cannot read the manifest");
}

}  // namespace
}  // namespace shaderfit
