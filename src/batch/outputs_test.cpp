// The one result of a batch, from a BatchResult made by hand (no search): the headers hold every
// function with its comment and compile with every compiler present, the JSON holds every entry,
// and the report links each row of its sortable table to the entry's section.
#include "shaderfit/batch/outputs.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "codegen/toolchain_test_support.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/plot/chart.hpp"
#include "shaderfit/report/search_json.hpp"

namespace shaderfit {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// A front member as a search leaves it: its literals are fitted parameters (baked into the code),
// its formula has them as numbers, its cost is the model's; the errors are given.
FrontMember member(const std::string& formula, const std::vector<std::string>& inputs, double loss,
                   double max_abs, double float32_max_abs,
                   const std::vector<std::string>& uniform = {}) {
  ParseOptions po;
  po.variables = inputs;
  po.literals_as_parameters = true;
  FrontMember m;
  m.expression = parse_formula(formula, po);
  PrintOptions exact;
  exact.substitute_parameters = true;
  m.formula = to_infix(m.expression, exact);
  m.cost = expression_cost(m.expression, CostTarget::Instructions, uniform);
  m.uniform = uniform;
  m.nodes = m.expression.size();
  m.metrics.rows = 201;
  m.metrics.max_abs = max_abs;
  m.metrics.mse = loss * loss;
  m.metrics.rmse = loss;
  m.loss = loss;
  m.float32_max_abs = float32_max_abs;
  m.float32_max_abs_diff = 1e-7;
  return m;
}

// The entry's search JSON, as `search --json` writes it (search_json) for that front.
std::string run_json(const BatchEntryResult& e, const std::string& loss,
                     const std::vector<std::string>& uniform = {}) {
  SearchSummary s;
  s.front = e.front;
  SearchOptions o;
  set_search_option(o, "loss", loss);
  o.uniform = uniform;
  SearchDataInfo info{e.description, e.target, 0.0, 201, e.inputs};
  return search_json(s, o, info);
}

// fast_tanh: a reference with a baseline (its problem in the manifest); fresnel: two inputs, no
// baseline, no problem; ggx_d: a per-material input (two-part code); gauss_cdf: erf (the helper
// in GLSL, HLSL, Metal), its goal not met; and one bad entry.
struct Fixture {
  Manifest manifest;
  BatchResult result;
};

const Fixture& fixture() {
  static const Fixture fixed = [] {
    Fixture x;
    x.manifest.path = x.result.manifest = "lib.toml";
    ProblemSource tanh_source;
    tanh_source.reference.formula = "tanh(x)";
    tanh_source.domain = {"x=0:4"};
    tanh_source.samples = 201;
    ManifestEntry me;
    me.name = "fast_tanh";
    me.line = 3;
    me.problem = tanh_source;
    me.loaded = std::make_shared<const Problem>(load_problem(tanh_source));
    me.baseline = "x / (1 + abs(x))";
    me.goal.kind = BatchGoal::Kind::BeatBaseline;
    x.manifest.entries.push_back(me);

    BatchEntryResult t;
    t.name = "fast_tanh";
    t.hash = "0123abcd";
    t.description = me.loaded->description;
    t.inputs = {"x"};
    t.target = me.loaded->target;
    t.loss_name = "max_abs";
    t.cost_name = "instructions";
    t.goal = me.goal;
    t.front = {member("x", t.inputs, 3.0, 3.0, 3.0),
               member("x / sqrt(1 + x^2)", t.inputs, 0.0293, 0.0293, 0.0293),
               member("x * (27 + x^2) / (27 + 9 * x^2)", t.inputs, 0.0235, 0.0235, 0.0235)};
    t.chosen = 1;
    t.goal_met = true;
    t.why = "the most accurate member costing at most 3";
    BaselineScore b;
    b.formula = me.baseline;
    b.cost = expression_cost(parse_formula(me.baseline, {{"x"}}), CostTarget::Instructions);
    b.loss = b.metrics.max_abs = 0.1994;
    b.metrics.max_rel = 0.2;
    b.float32_max_abs = 0.1994;
    t.baseline = b;
    t.run_json = run_json(t, "max_abs");
    t.seconds = 3.1;
    x.result.entries.push_back(t);

    BatchEntryResult f;
    f.name = "fresnel";
    f.hash = "4567ef01";
    f.description = "fresnel-seed (seed 1)";
    f.inputs = {"r0", "cos_theta"};
    f.target = "R";
    f.loss_name = "mse";
    f.cost_name = "instructions";
    f.front = {member("r0", f.inputs, 0.0454, 0.98, 0.98),
               member("r0 + (1 - r0) * (1 - cos_theta)^5", f.inputs, 3.5e-4, 0.139, 0.139)};
    f.chosen = 1;
    f.goal_met = true;
    f.why = "the knee of the front";
    f.run_json = run_json(f, "mse");
    f.seconds = 1.25;
    f.from_checkpoint = true;
    x.result.entries.push_back(f);

    BatchEntryResult g;
    g.name = "ggx_d";
    g.hash = "89ab";
    g.description = "ggx(n_dot_h, alpha) on n_dot_h in [0, 1], alpha in [0.05, 1]";
    g.inputs = {"n_dot_h", "alpha"};
    g.target = "reference";
    g.loss_name = "max_rel";
    g.cost_name = "instructions";
    g.goal = {BatchGoal::Kind::MaxCost, 20};
    g.front = {member("n_dot_h", g.inputs, 1.0, 10.0, 10.0, {"alpha"}),
               member("alpha^2 / (3.14159 * (n_dot_h^2 * (alpha^2 - 1) + 1)^2)", g.inputs, 1e-7,
                      2e-6, 3e-6, {"alpha"})};
    g.chosen = 1;
    g.goal_met = true;
    g.why = "the most accurate member costing at most 20";
    g.run_json = run_json(g, "max_rel", {"alpha"});
    g.seconds = 2;
    g.rank = 1;
    x.result.entries.push_back(g);

    BatchEntryResult c;
    c.name = "gauss_cdf";
    c.hash = "cdef";
    c.description = "0.5 * (1 + erf(x / sqrt(2))) on x in [-3, 3], 201 samples";
    c.inputs = {"x"};
    c.target = "reference";
    c.loss_name = "max_abs";
    c.cost_name = "instructions";
    c.goal = {BatchGoal::Kind::MaxError, 1e-6};
    c.front = {member("0.5 + 0.5 * erf(0.7071 * x)", c.inputs, 2.1e-5, 2.1e-5, 2.2e-5)};
    c.chosen = 0;
    c.goal_met = false;
    c.why = "no member has max_abs at most 1e-06: the most accurate";
    c.run_json = run_json(c, "max_abs");
    c.seconds = 0.5;
    x.result.entries.push_back(c);

    x.result.bad.push_back(
        {"broken", 14,
         "lib.toml:14:1: entry 'broken': no problem (give reference, data or dataset)"});
    x.manifest.bad = x.result.bad;
    x.result.seconds = 7.5;
    return x;
  }();
  return fixed;
}

const Expression& chosen_expression(const std::string& name) {
  for (const BatchEntryResult& e : fixture().result.entries)
    if (e.name == name) return e.front[e.chosen].expression;
  throw Error("no entry " + name);
}

// Each function called at these inputs (in the expression's variable order) by the programs that
// include the headers; ggx_d's alpha goes through its per-material values.
struct Call {
  const char* name;
  std::vector<double> args;
};
const Call kCalls[] = {
    {"fast_tanh", {0.7}}, {"fresnel", {0.04, 0.5}}, {"ggx_d", {0.9, 0.3}}, {"gauss_cdf", {0.4}}};

// The call of one function in C-like code: `f(a, b)`, or for ggx_d the two-part form.
std::string call_text(const Call& c, const std::string& float_suffix, const std::string& material) {
  std::vector<std::string> args;
  for (double v : c.args) args.push_back(fmt::format("{}{}", v, float_suffix));
  if (std::string(c.name) == "ggx_d")
    return fmt::format("ggx_d({}, {})", args[0],
                       material.empty() ? "ggx_d_material_values(" + args[1] + ")" : material);
  return fmt::format("{}({})", c.name, fmt::join(args, ", "));
}

TEST(BatchOutputs, HeadersHoldEveryFunctionWithItsCommentAndMeasuredError) {
  const BatchResult& r = fixture().result;
  for (Language l :
       {Language::Glsl, Language::Hlsl, Language::Cuda, Language::Cpp, Language::Metal}) {
    SCOPED_TRACE(std::string(language_name(l)));
    const std::string h = batch_header(r, l);
    EXPECT_EQ(h.rfind("// shaderfit batch: lib.toml, 4 functions\n", 0), 0u) << h;
    for (const BatchEntryResult& e : r.entries) {
      EXPECT_NE(h.find(" " + e.name + "("), std::string::npos) << e.name << "\n" << h;
      EXPECT_NE(h.find("// " + e.name + ": approximates " + e.description), std::string::npos) << h;
      EXPECT_NE(h.find("// formula: " +
                       to_infix(e.front[e.chosen].expression, PrintOptions::for_people())),
                std::string::npos)
          << h;
      EXPECT_NE(h.find("// goal " + batch_goal_text(e.goal)), std::string::npos) << h;
    }
    // The measured errors, short, and the cost in the model's words.
    EXPECT_NE(h.find("// error: max_abs 0.0293; max |error| 0.0293; in float32 0.0293"),
              std::string::npos)
        << h;
    EXPECT_NE(h.find("// error: max_rel 1e-07; max |error| 2e-06; in float32 3e-06"),
              std::string::npos)
        << h;
    EXPECT_NE(h.find(fmt::format("// cost {:g} (instructions); cost model: ",
                                 r.entries[0].front[1].cost)),
              std::string::npos)
        << h;
    EXPECT_NE(h.find("per material"), std::string::npos) << h;  // ggx_d reads alpha
    EXPECT_NE(h.find(fmt::format("// baseline x / (1 + abs(x)): cost {:g}, max_abs 0.199, max "
                                 "|error| 0.199, in float32 0.199",
                                 r.entries[0].baseline->cost)),
              std::string::npos)
        << h;
    EXPECT_NE(h.find("// goal beat-baseline: met"), std::string::npos) << h;
    EXPECT_NE(h.find("// goal error=1e-06: not met"), std::string::npos) << h;
    EXPECT_NE(h.find("// not run: broken: lib.toml:14:1"), std::string::npos) << h;
    // Constants short in comments, baked into the code.
    EXPECT_NE(h.find("0.7071 * x"), std::string::npos) << h;
    EXPECT_EQ(h.find("0.70709999"), std::string::npos) << h;
  }
  const std::string both = batch_cpp_cuda_header(r);
  EXPECT_NE(both.find("#pragma once"), std::string::npos);
  const auto cuda = both.find("#ifdef __CUDACC__"), other = both.find("#else"),
             end = both.find("#endif");
  ASSERT_NE(cuda, std::string::npos);
  ASSERT_NE(other, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  EXPECT_NE(both.find("__device__ __forceinline__ float fast_tanh("), std::string::npos) << both;
  EXPECT_LT(both.find("__device__ __forceinline__ float fast_tanh("), other);
  EXPECT_GT(both.find("inline float fast_tanh("), other) << both;
}

// fastmath.h as written, included by two C++17 translation units linked together, run: each
// function agrees with the evaluator in float32.
TEST(BatchOutputs, CppHeaderCompilesAndRunsWithEveryCompiler) {
  const auto dir = testing::scratch_folder("batch_cpp");
  testing::write_text(dir / "fastmath.h", batch_cpp_cuda_header(fixture().result));
  std::string body;
  for (const Call& c : kCalls)
    body += fmt::format("  std::printf(\"%.9g\\n\", static_cast<double>({}));\n",
                        call_text(c, "f", ""));
  testing::write_text(dir / "main.cpp",
                      "#include <cstdio>\n#include \"fastmath.h\"\n"
                      "float other(float x);\nint main() {\n" +
                          body + "  std::printf(\"%.9g\\n\", other(1.5f));\n}\n");
  testing::write_text(dir / "other.cpp",
                      "#include \"fastmath.h\"\nfloat other(float x) { return fast_tanh(x); }\n");
  const auto compilers = testing::cpp_compilers();
  if (compilers.empty()) GTEST_SKIP() << "skipped: neither g++ nor clang++ found";
  for (const auto& [name, path] : compilers) {
    SCOPED_TRACE(name);
    std::string log;
    const std::string exe = (dir / ("main_" + name)).string();
    ASSERT_EQ(testing::run_command(fmt::format("cd '{}' && '{}' -std=c++17 -Wall -Wextra -Werror "
                                               "-pedantic main.cpp other.cpp -o '{}'",
                                               dir.string(), path, exe),
                                   &log),
              0)
        << log;
    std::string out;
    ASSERT_EQ(testing::run_command("'" + exe + "'", &out), 0) << out;
    std::istringstream lines(out);
    for (const Call& c : kCalls) {
      double v = 0;
      ASSERT_TRUE(lines >> v) << out;
      const double want = evaluate_scalar(chosen_expression(c.name), c.args);
      EXPECT_NEAR(v, want, 1e-5 * std::max(1.0, std::abs(want))) << c.name;
    }
    double v = 0;
    ASSERT_TRUE(lines >> v) << out;
    EXPECT_NEAR(v, evaluate_scalar(chosen_expression("fast_tanh"), std::vector<double>{1.5}), 1e-5);
  }
}

TEST(BatchOutputs, CudaHeaderCompilesWithNvcc) {
  const auto nvcc = testing::find_tool("nvcc");
  if (!nvcc) GTEST_SKIP() << "skipped: nvcc not found";
  const auto dir = testing::scratch_folder("batch_cuda");
  testing::write_text(dir / "fastmath.h", batch_cpp_cuda_header(fixture().result));
  std::string body;
  int k = 0;
  for (const Call& c : kCalls) body += fmt::format("  out[{}] = {};\n", k++, call_text(c, "f", ""));
  testing::write_text(dir / "k.cu",
                      "#include \"fastmath.h\"\n"
                      "__global__ void k(float* out) {\n" +
                          body + "}\n");
  std::string log;
  EXPECT_EQ(
      testing::run_command(
          fmt::format("cd '{}' && '{}' -std=c++17 -arch=sm_90 -c k.cu -o k.o", dir.string(), *nvcc),
          &log),
      0)
      << log;
}

// The shader files as written, with an entry point appended that calls every function.
TEST(BatchOutputs, ShaderHeadersCompileWithGlslang) {
  const auto glslang = testing::find_tool("glslangValidator");
  if (!glslang) GTEST_SKIP() << "skipped: glslangValidator not found";
  const auto dir = testing::scratch_folder("batch_shaders");
  for (Language l : {Language::Glsl, Language::Hlsl}) {
    const bool glsl = l == Language::Glsl;
    SCOPED_TRACE(glsl ? "glsl" : "hlsl");
    std::string src = batch_header(fixture().result, l);
    src += glsl ? "layout(local_size_x = 1) in;\n"
                  "layout(std430, binding = 0) buffer Data { float data[]; };\n"
                : "RWStructuredBuffer<float> data : register(u0);\n";
    std::string body;
    int k = 0;
    for (const Call& c : kCalls)
      body += fmt::format("  data[{}] = {};\n", k++, call_text(c, "", ""));
    src += glsl ? "void main() {\n" + body + "}\n"
                : "[numthreads(1, 1, 1)]\nvoid main() {\n" + body + "}\n";
    const std::string file = glsl ? "fastmath.comp" : "fastmath.hlsl";
    testing::write_text(dir / file, src);
    std::string log;
    EXPECT_EQ(testing::run_command(fmt::format("cd '{}' && '{}' -V {} -o out.spv {}", dir.string(),
                                               *glslang, glsl ? "" : "-D -S comp -e main", file),
                                   &log),
              0)
        << log << "\n"
        << src;
  }
}

TEST(BatchOutputs, JsonHoldsEveryEntryAndTheBadOnes) {
  const BatchResult& r = fixture().result;
  const json j = json::parse(batch_json(r));
  EXPECT_EQ(j["schema"], "shaderfit.batch/1");
  EXPECT_EQ(j["manifest"], "lib.toml");
  EXPECT_EQ(j["interrupted"], false);
  EXPECT_DOUBLE_EQ(j["seconds"].get<double>(), 7.5);
  ASSERT_EQ(j["entries"].size(), r.entries.size());
  for (std::size_t i = 0; i < r.entries.size(); ++i) {
    const BatchEntryResult& e = r.entries[i];
    const json& je = j["entries"][i];
    SCOPED_TRACE(e.name);
    EXPECT_EQ(je["name"], e.name);
    EXPECT_EQ(je["hash"], e.hash);
    EXPECT_EQ(je["description"], e.description);
    EXPECT_EQ(je["inputs"].get<std::vector<std::string>>(), e.inputs);
    EXPECT_EQ(je["target"], e.target);
    EXPECT_EQ(je["loss"], e.loss_name);
    EXPECT_EQ(je["cost"], e.cost_name);
    EXPECT_EQ(je["goal"], batch_goal_text(e.goal));
    EXPECT_EQ(je["goal_met"], e.goal_met);
    EXPECT_EQ(je["why"], e.why);
    EXPECT_EQ(je["chosen"], e.chosen);
    EXPECT_EQ(je["from_checkpoint"], e.from_checkpoint);
    EXPECT_EQ(je["rank"], e.rank);
    EXPECT_DOUBLE_EQ(je["seconds"].get<double>(), e.seconds);
    // The run is the entry's search JSON, as an object: its front holds the chosen member.
    ASSERT_TRUE(je["run"].is_object());
    ASSERT_EQ(je["run"]["front"].size(), e.front.size());
    EXPECT_EQ(je["run"]["front"][e.chosen]["formula"], e.front[e.chosen].formula);
    EXPECT_EQ(je["baseline"].is_null(), !e.baseline);
  }
  const json& b = j["entries"][0]["baseline"];
  EXPECT_EQ(b["formula"], "x / (1 + abs(x))");
  EXPECT_DOUBLE_EQ(b["cost"].get<double>(), r.entries[0].baseline->cost);
  EXPECT_DOUBLE_EQ(b["loss"].get<double>(), 0.1994);
  EXPECT_DOUBLE_EQ(b["max_abs"].get<double>(), 0.1994);
  EXPECT_DOUBLE_EQ(b["max_rel"].get<double>(), 0.2);
  EXPECT_DOUBLE_EQ(b["float32_max_abs"].get<double>(), 0.1994);
  ASSERT_EQ(j["bad"].size(), 1u);
  EXPECT_EQ(j["bad"][0]["name"], "broken");
  EXPECT_EQ(j["bad"][0]["line"], 14);
  EXPECT_EQ(j["bad"][0]["message"], r.bad[0].message);

  BatchResult broken = r;
  broken.entries[0].run_json = "{ not json";
  try {
    (void)batch_json(broken);
    ADD_FAILURE() << "a run JSON that does not parse was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("fast_tanh"), std::string::npos) << e.what();
  }
}

std::string find_chromium() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"})
    if (const auto path = testing::find_tool(name)) return *path;
  return "";
}

// Every file written; the report's table links each row to its entry's section, sorts by a
// column on a click (checked in headless Chromium where present), and loads nothing.
TEST(BatchOutputs, WritesEveryFileAndTheReportLinksAndSorts) {
  if (!gnuplot_available()) GTEST_SKIP() << "skipped: gnuplot not found (the report's plots)";
  const BatchResult& r = fixture().result;
  const auto dir = testing::scratch_folder("batch_outputs") / "out" / "nested";
  const std::vector<std::string> paths = write_batch_outputs(r, &fixture().manifest, dir.string());
  std::vector<std::string> names;
  for (const std::string& p : paths) {
    EXPECT_TRUE(fs::is_regular_file(p)) << p;
    names.push_back(fs::path(p).filename().string());
  }
  EXPECT_EQ(names, (std::vector<std::string>{"fastmath.glsl", "fastmath.hlsl", "fastmath.h",
                                             "fastmath.metal", "batch.json", "report.html"}));
  EXPECT_EQ(testing::read_text(dir / "fastmath.glsl"), batch_header(r, Language::Glsl));
  EXPECT_EQ(testing::read_text(dir / "fastmath.hlsl"), batch_header(r, Language::Hlsl));
  EXPECT_EQ(testing::read_text(dir / "fastmath.h"), batch_cpp_cuda_header(r));
  EXPECT_EQ(testing::read_text(dir / "fastmath.metal"), batch_header(r, Language::Metal));
  EXPECT_EQ(testing::read_text(dir / "batch.json"), batch_json(r));

  const std::string page = testing::read_text(dir / "report.html");
  EXPECT_EQ(page.find("http://"), std::string::npos);
  EXPECT_EQ(page.find("https://"), std::string::npos);
  EXPECT_NE(page.find("<table class=\"sortable\">"), std::string::npos);
  EXPECT_NE(page.find("table.sortable"), std::string::npos);  // the sorting script
  for (const BatchEntryResult& e : r.entries) {
    EXPECT_NE(page.find("<a href=\"#entry-" + e.name + "\">" + e.name + "</a>"), std::string::npos)
        << e.name;
    EXPECT_NE(page.find("id=\"entry-" + e.name + "\""), std::string::npos) << e.name;
  }
  EXPECT_NE(page.find("<a href=\"#not-run\">broken</a>"), std::string::npos);
  EXPECT_NE(page.find("id=\"not-run\""), std::string::npos);
  EXPECT_NE(page.find("not run: lib.toml:14:1"), std::string::npos);
  for (const char* column :
       {"baseline cost", "baseline error", "our cost", "our error", "instructions saved",
        "error ratio", "float32 max |error|", "goal met"})
    EXPECT_NE(page.find(std::string(">") + html_escape(column) + "</th>"), std::string::npos)
        << column;
  // fast_tanh's row: the instructions saved and the error ratio, short, sorted by their values.
  const BatchEntryResult& t = r.entries[0];
  const double saved = t.baseline->cost - t.front[1].cost, ratio = 0.0293 / 0.1994;
  EXPECT_NE(page.find(fmt::format("<td class=\"num\" data-sort=\"{:.17g}\">{:.3g}</td><td "
                                  "class=\"num\" data-sort=\"{:.17g}\">0.147</td>",
                                  saved, saved, ratio)),
            std::string::npos);
  // Its section: the search report's with the data (curves) and the baseline scored.
  EXPECT_NE(page.find("Against the baselines"), std::string::npos);

  const std::string chromium = find_chromium();
  if (chromium.empty()) GTEST_SKIP() << "skipped: chromium not found";
  // The page with a probe after it: click "our cost" twice and record the entry order each time.
  std::string probe = page;
  probe.insert(probe.rfind("</body>"),
               "<script>window.addEventListener('load',function(){var t=document.querySelector("
               "'table.sortable'),h=t.tHead.rows[0].cells[4];function order(){var n=[];for(var "
               "i=0;i<t.tBodies[0].rows.length;i++)n.push(t.tBodies[0].rows[i].cells[0]."
               "textContent);return n.join(',');}h.click();document.body.setAttribute('data-up',"
               "order());h.click();document.body.setAttribute('data-down',order());});</script>\n");
  testing::write_text(dir / "probe.html", probe);
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking"
      " --user-data-dir=" +
      (dir / "profile").string() + " ";
  std::string dom;
  testing::run_command("timeout 120 '" + chromium + "'" + flags + "--dump-dom 'file://" +
                           (dir / "probe.html").string() + "' 2>/dev/null",
                       &dom);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(dom, m, std::regex(R"re(data-errors="(\d+)")re")))
      << dom.substr(0, 400);
  EXPECT_EQ(m[1], "0");
  // Sorted by our cost, ties in page order; broken has none: last both ways.
  std::vector<std::pair<double, std::string>> costs;
  for (const BatchEntryResult& e : r.entries) costs.emplace_back(e.front[e.chosen].cost, e.name);
  std::stable_sort(costs.begin(), costs.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string up, down;
  for (const auto& c : costs) up += c.second + ",";
  std::stable_sort(costs.begin(), costs.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& c : costs) down += c.second + ",";
  EXPECT_NE(dom.find("data-up=\"" + up + "broken\""), std::string::npos) << dom.substr(0, 600);
  EXPECT_NE(dom.find("data-down=\"" + down + "broken\""), std::string::npos) << dom.substr(0, 600);
}

TEST(BatchOutputs, AFileThatCannotBeWrittenIsNamed) {
  const auto dir = testing::scratch_folder("batch_unwritable");
  fs::create_directories(dir / "fastmath.glsl");  // a folder where the file goes
  try {
    (void)write_batch_outputs(fixture().result, nullptr, dir.string());
    ADD_FAILURE() << "wrote over a folder";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("fastmath.glsl"), std::string::npos) << e.what();
  }
  testing::write_text(dir / "file", "x");
  try {
    (void)write_batch_outputs(fixture().result, nullptr, (dir / "file" / "out").string());
    ADD_FAILURE() << "made a folder under a file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("file/out"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace shaderfit
