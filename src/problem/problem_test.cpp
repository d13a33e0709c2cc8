#include "shaderfit/problem/problem.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/data/fresnel_sweep.hpp"
#include "shaderfit/expr/op.hpp"

namespace shaderfit {
namespace {

// Runs `f`, which must throw Error with this message at this location.
void expect_error(const std::function<void()>& f, const std::string& message,
                  const std::string& source, int line = 0) {
  try {
    f();
    ADD_FAILURE() << "no error; expected: " << message;
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), message);
    EXPECT_EQ(e.where().source, source) << message;
    EXPECT_EQ(e.where().line, line) << message;
  }
}

void expect_problem_error(const ProblemSource& s, const std::string& message,
                          const std::string& source, int line = 0) {
  expect_error([&] { (void)load_problem(s); }, message, source, line);
}

// A file in the temporary directory with this text, removed at the end of the test. The name
// holds the process id: ctest runs tests side by side, each in its own process.
class TempFile {
 public:
  TempFile(const std::string& name, const std::string& text)
      : path_(std::filesystem::temp_directory_path() /
              ("shaderfit_problem_test_" + std::to_string(::getpid()) + "_" + name)) {
    std::ofstream(path_) << text;
  }
  ~TempFile() { std::filesystem::remove_all(path_); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  [[nodiscard]] std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

ProblemSource csv_source(const TempFile& f) {
  ProblemSource s;
  s.csv_path = f.path();
  return s;
}

ProblemSource reference_source(const std::string& formula, std::vector<std::string> domain) {
  ProblemSource s;
  s.reference.formula = formula;
  s.domain = std::move(domain);
  return s;
}

using Names = std::vector<std::string>;

// ---- which source ----

TEST(ProblemSourceChoice, ExactlyOneSource) {
  expect_problem_error(ProblemSource{},
                       "no data: give a CSV file, a built-in data set, or a reference and its "
                       "domain",
                       "ProblemSource::csv_path");
  ProblemSource two;
  two.csv_path = "xy.csv";
  two.dataset = "fresnel-seed";
  expect_problem_error(two,
                       "give one source of data, not both a CSV file (xy.csv) and a built-in "
                       "data set (fresnel-seed)",
                       "ProblemSource::dataset");
  ProblemSource three = reference_source("x", {"x=0:1"});
  three.dataset = "fresnel-seed";
  expect_problem_error(three,
                       "give one source of data, not both a built-in data set (fresnel-seed) and "
                       "a reference",
                       "ProblemSource::reference");
  ProblemSource shader;
  shader.csv_path = "xy.csv";
  shader.reference.shader_path = "f.glsl";
  shader.reference.function = "f";
  expect_problem_error(shader,
                       "give one source of data, not both a CSV file (xy.csv) and a shader "
                       "function",
                       "ReferenceText::shader_path");
  ProblemSource both = reference_source("x", {"x=0:1"});
  both.reference.shader_source = "float f(float x) { return x; }";
  both.reference.function = "f";
  expect_problem_error(both, "give a reference formula or a shader function, not both",
                       "ProblemSource::reference");
}

TEST(ProblemSourceChoice, ReferenceFieldsWithOtherData) {
  ProblemSource s;
  s.dataset = "fresnel-seed";
  s.domain = {"x=0:1"};
  expect_problem_error(
      s, "a domain is for a reference: a built-in data set (fresnel-seed) has its samples already",
      "ProblemSource::domain");
  s.domain.clear();
  s.samples = 100;
  expect_problem_error(s,
                       "a number of samples is for a reference: a built-in data set "
                       "(fresnel-seed) has its samples already",
                       "ProblemSource::samples");
  s.samples = 0;
  s.reference.definitions = {"u = x^2"};
  expect_problem_error(s,
                       "definitions are for a reference, not for a built-in data set "
                       "(fresnel-seed)",
                       "definitions");
  s.reference.definitions.clear();
  s.reference.function = "G1";
  expect_problem_error(s,
                       "a function or variables are for a reference, not for a built-in data "
                       "set (fresnel-seed)",
                       "ProblemSource::reference");
}

// ---- CSV ----

TEST(ProblemCsv, InfersTheColumnNamedY) {
  TempFile f("xy.csv", "x,y\n0,1\n0.5,2\n1,3\n");
  Problem p = load_problem(csv_source(f));
  EXPECT_EQ(p.inputs, Names{"x"});
  EXPECT_EQ(p.target, "y");
  EXPECT_EQ(p.description, f.path());
  EXPECT_EQ(p.data.rows(), 3u);
  EXPECT_EQ(p.reference, nullptr);
  EXPECT_EQ(p.operators, "");
  EXPECT_EQ(p.evolution_operators, "");
  EXPECT_EQ(p.notes, Names{"inputs x, target y (the column named y is the target, the other "
                           "numeric columns the inputs)"});
}

TEST(ProblemCsv, InfersTheColumnNamedTarget) {
  TempFile f("abc.csv", "a,b,c,target\n0,1,2,3\n1,2,3,4\n");
  Problem p = load_problem(csv_source(f));
  EXPECT_EQ(p.inputs, (Names{"a", "b", "c"}));
  EXPECT_EQ(p.target, "target");
  EXPECT_EQ(p.notes, Names{"inputs a, b, c, target target (the column named target is the "
                           "target, the other numeric columns the inputs)"});
  // "target" before "y": with x, y, target the y is an input.
  TempFile g("xyt.csv", "x,target,y\n0,1,2\n1,2,3\n");
  Problem q = load_problem(csv_source(g));
  EXPECT_EQ(q.inputs, (Names{"x", "y"}));
  EXPECT_EQ(q.target, "target");
}

TEST(ProblemCsv, InfersTheLastNumericColumn) {
  TempFile f("abc.csv", "a,b,c,label\n0,1,2,p\n1,2,3,q\n");
  Problem p = load_problem(csv_source(f));
  EXPECT_EQ(p.inputs, (Names{"a", "b"}));
  EXPECT_EQ(p.target, "c");
  EXPECT_EQ(p.notes, (Names{"inputs a, b, target c (the last numeric column is the target, the "
                            "other numeric columns the inputs)",
                            "text column label not used"}));
}

TEST(ProblemCsv, SkipsTextColumns) {
  TempFile f("mixed.csv", "x,kind,y,material\n0,a,1,m\n1,b,2,n\n");
  Problem p = load_problem(csv_source(f));
  EXPECT_EQ(p.inputs, Names{"x"});
  EXPECT_EQ(p.target, "y");
  EXPECT_EQ(p.notes.size(), 2u);
  EXPECT_EQ(p.notes.at(1), "text columns kind, material not used");
}

TEST(ProblemCsv, InfersWhatIsNotGiven) {
  TempFile f("abcd.csv", "a,b,c,d\n0,1,2,3\n1,2,3,4\n");
  ProblemSource s = csv_source(f);
  s.inputs = {"d", "b"};
  Problem p = load_problem(s);
  EXPECT_EQ(p.inputs, (Names{"d", "b"}));
  EXPECT_EQ(p.target, "c");
  EXPECT_EQ(p.notes, Names{"target c (the last numeric column that is not an input)"});

  s.inputs.clear();
  s.target = "a";
  p = load_problem(s);
  EXPECT_EQ(p.inputs, (Names{"b", "c", "d"}));
  EXPECT_EQ(p.target, "a");
  EXPECT_EQ(p.notes, Names{"inputs b, c, d (the numeric columns other than the target)"});

  s.inputs = {"c"};
  p = load_problem(s);
  EXPECT_EQ(p.inputs, Names{"c"});
  EXPECT_EQ(p.target, "a");
  EXPECT_TRUE(p.notes.empty());
}

TEST(ProblemCsv, OneColumnIsAnError) {
  TempFile f("x.csv", "x\n0\n1\n");
  expect_problem_error(csv_source(f),
                       f.path() +
                           " has one column ('x'): a target and at least one input are "
                           "needed",
                       f.path(), 1);
  TempFile g("xname.csv", "\n\nx,name\n0,a\n1,b\n");
  expect_problem_error(csv_source(g),
                       g.path() +
                           " has one numeric column ('x') and text (name): a target and "
                           "at least one input are needed",
                       g.path(), 3);
  TempFile h("names.csv", "name\na\nb\n");
  expect_problem_error(csv_source(h),
                       h.path() +
                           " has no numeric column (text: name): a target and at least "
                           "one input are needed",
                       h.path(), 1);
  // Named inputs that leave no column for the target.
  TempFile k("xy.csv", "x,y\n0,1\n1,2\n");
  ProblemSource s = csv_source(k);
  s.inputs = {"x", "y"};
  expect_problem_error(s,
                       "the inputs are every numeric column of " + k.path() +
                           " (x, y): none is left to be the target",
                       "ProblemSource::inputs");
  // A named target that leaves no input.
  ProblemSource t = csv_source(f);
  t.target = "x";
  expect_problem_error(t,
                       f.path() +
                           " has one column ('x'): a target and at least one input are "
                           "needed",
                       f.path(), 1);
}

TEST(ProblemCsv, NamedColumnsAreChecked) {
  TempFile f("xy.csv", "x,y,name\n0,1,a\n1,2,b\n");
  ProblemSource s = csv_source(f);
  s.inputs = {"z"};
  expect_problem_error(s, "no column 'z' in " + f.path() + " (numeric columns: x, y)",
                       "ProblemSource::inputs");
  s.inputs = {"name"};
  expect_problem_error(s,
                       "column 'name' of " + f.path() +
                           " is text, not numbers, first non-number at " + f.path() +
                           ":2:5 (numeric columns: x, y)",
                       "ProblemSource::inputs");
  s.inputs = {"x", "x"};
  expect_problem_error(s, "input 'x' is named twice", "ProblemSource::inputs");
  s.inputs = {"x"};
  s.target = "w";
  expect_problem_error(s, "no column 'w' in " + f.path() + " (numeric columns: x, y)",
                       "ProblemSource::target");
  s.target = "x";
  expect_problem_error(s, "the target 'x' is also an input", "ProblemSource::target");
}

TEST(ProblemCsv, RowsWithGapsAreAnErrorOrDroppedAndSaid) {
  const TempFile f("gaps.csv", "a,b,y\n1,2,3\n4,,5\n6,7,8\n");
  ProblemSource s = csv_source(f);
  expect_problem_error(s,
                       "column 'b' is numbers but for 1 cell: this one is empty (fix them, or "
                       "drop their rows: CsvOptions::drop_missing_rows)",
                       f.path(), 3);
  s.drop_missing_rows = true;
  const Problem p = load_problem(s);
  EXPECT_EQ(p.data.rows(), 2u);
  EXPECT_EQ(p.inputs, (Names{"a", "b"}));
  EXPECT_NE(std::find(p.notes.begin(), p.notes.end(),
                      "dropped 1 of 3 rows with an empty or non-number cell in a column of "
                      "numbers, first at line 3"),
            p.notes.end());
  ProblemSource r = reference_source("x", {"x=0:1"});
  r.drop_missing_rows = true;
  expect_problem_error(r, "dropping rows with gaps is for a CSV file, not for a reference",
                       "ProblemSource::drop_missing_rows");
}

TEST(ProblemCsv, FileErrorsComeFromTheReader) {
  ProblemSource s;
  s.csv_path =
      (std::filesystem::temp_directory_path() / "shaderfit_problem_test_missing.csv").string();
  EXPECT_THROW((void)load_problem(s), Error);
}

// ---- built-in data sets ----

TEST(ProblemDataset, FresnelSeedHasItsOwnColumnsAndOperators) {
  ProblemSource s;
  s.dataset = "fresnel-seed";
  s.dataset_seed = 7;
  Problem p = load_problem(s);
  EXPECT_EQ(p.inputs, (Names{"r0", "x"}));
  EXPECT_EQ(p.target, "R");
  EXPECT_EQ(p.data.rows(), 4096u);
  EXPECT_EQ(p.description, "fresnel-seed (seed 7)");
  EXPECT_EQ(p.notes, Names{"inputs r0, x, target R (the data set's own)"});
  // The seed task's operators (the search reads them: SearchOptions.TheSeedDataSetsOperators).
  EXPECT_EQ(p.operators, "+,-,*,/,^");
  EXPECT_EQ(p.evolution_operators, "pow,exp2");
  // The same rows as the generator gives for the seed.
  Rng rng(7);
  EXPECT_EQ(p.data.numeric("R").values, make_fresnel_seed_dataset(rng).numeric("R").values);
}

TEST(ProblemDataset, EveryBuiltinDataSetHasADescriptor) {
  for (const std::string& name : builtin_dataset_names()) {
    std::optional<BuiltinDatasetInfo> info = builtin_dataset_info(name);
    ASSERT_TRUE(info.has_value()) << name;
    EXPECT_EQ(info->name, name);
    ProblemSource s;
    s.dataset = name;
    Problem p = load_problem(s);
    for (const std::string& c : p.inputs) EXPECT_TRUE(p.data.numeric(c).numeric());
    EXPECT_TRUE(p.data.numeric(p.target).numeric());
  }
  EXPECT_FALSE(builtin_dataset_info("nope").has_value());
}

// The material sweep behind `plot --material`: a source of its own, "seed" for seed 001's set.
TEST(ProblemSweep, MaterialsSweptOverTheAngle) {
  ProblemSource s;
  s.materials = {"aluminium", "1.5"};
  s.angles = 91;
  Problem p = load_problem(s);
  EXPECT_EQ(p.inputs, (Names{"r0", "x"}));
  EXPECT_EQ(p.target, "R");
  EXPECT_EQ(p.data.rows(), 2u * 91u);
  EXPECT_EQ(p.description, "the Fresnel sweep of aluminium, ior1.5 (91 angles each)");
  EXPECT_EQ(p.data.numeric("R").values,
            make_fresnel_sweep({parse_material("aluminium"), parse_material("1.5")}, 91)
                .numeric("R")
                .values);
  s.materials = {"seed"};
  EXPECT_EQ(load_problem(s).data.rows(), seed_materials().size() * 91u);
  auto expect_bad = [](const ProblemSource& bad, const std::string& part, const std::string& source,
                       int line) {
    try {
      (void)load_problem(bad);
      ADD_FAILURE() << "no error; expected: " << part;
    } catch (const Error& e) {
      EXPECT_NE(e.message().find(part), std::string::npos) << e.what();
      EXPECT_EQ(e.where().source, source) << e.what();
      EXPECT_EQ(e.where().line, line) << e.what();
    }
  };
  s.materials = {"1.5", "unobtainium"};
  expect_bad(s, "unknown material 'unobtainium'", "ProblemSource::materials", 2);
  s.materials = {"1.5"};
  s.angles = 1;
  expect_bad(s, "at least 2 angles", "ProblemSource::angles", 0);
  s.angles = 181;
  s.dataset = "fresnel-seed";
  expect_bad(s, "give one source of data", "ProblemSource::materials", 0);
}

TEST(ProblemDataset, NamedColumnsAndErrors) {
  ProblemSource s;
  s.dataset = "fresnel-seed-half";
  s.target = "cos_theta";
  Problem p = load_problem(s);
  EXPECT_EQ(p.inputs, (Names{"r0", "x"}));
  EXPECT_EQ(p.target, "cos_theta");
  EXPECT_EQ(p.notes, Names{"inputs r0, x (the data set's own)"});
  s.target = "x";
  p = load_problem(s);
  EXPECT_EQ(p.inputs, Names{"r0"});
  s.target = "";
  s.inputs = {"R"};
  expect_problem_error(s, "input 'R' is the data set's target: name another target",
                       "ProblemSource::inputs");
  s.inputs = {"material"};
  expect_problem_error(s,
                       "column 'material' of fresnel-seed-half is text, not numbers (numeric "
                       "columns: r0, cos_theta, x, R, ior_n, ior_k)",
                       "ProblemSource::inputs");
  ProblemSource u;
  u.dataset = "nope";
  expect_problem_error(u, "unknown data set 'nope' (built-in: fresnel-seed, fresnel-seed-half)",
                       "ProblemSource::dataset");
}

// ---- references ----

TEST(ProblemReference, OneVariableFormula) {
  Problem p = load_problem(reference_source("acos(x)", {"x=-1:1"}));
  EXPECT_EQ(p.data.rows(), 10'001u);
  EXPECT_EQ(p.data.names(), (Names{"x", "reference"}));
  EXPECT_EQ(p.inputs, Names{"x"});
  EXPECT_EQ(p.target, "reference");
  EXPECT_EQ(p.description, "acos(x) on x in [-1, 1], 10,001 samples");
  EXPECT_EQ(p.notes, Names{"inputs x, target reference (the reference's own)"});
  EXPECT_EQ(p.operators, "");
  const std::vector<double>& x = p.data.numeric("x").values;
  const std::vector<double>& y = p.data.numeric("reference").values;
  EXPECT_EQ(x.front(), -1.0);
  EXPECT_EQ(x.back(), 1.0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    ASSERT_EQ(y[i], std::acos(x[i]));
    if (2 * i + 1 == x.size()) continue;  // 0 in the middle
    ASSERT_EQ(std::bit_cast<std::uint64_t>(x[x.size() - 1 - i]),
              std::bit_cast<std::uint64_t>(-x[i]));
  }
  ASSERT_NE(p.reference, nullptr);
  EXPECT_EQ(p.reference->target, "reference");
  ASSERT_EQ(p.reference->domain.size(), 1u);
  EXPECT_EQ(p.reference->domain[0].name, "x");
  EXPECT_EQ(p.reference->domain[0].lo, -1.0);
  EXPECT_EQ(p.reference->target_at(std::vector<double>{0.123}), std::acos(0.123));
}

TEST(ProblemReference, SamplesAndCountedDomains) {
  ProblemSource s = reference_source("x^2", {"x=0:1"});
  s.samples = 101;
  Problem p = load_problem(s);
  EXPECT_EQ(p.data.rows(), 101u);
  EXPECT_EQ(p.description, "x^2 on x in [0, 1], 101 samples");
  s.samples = 1;
  expect_problem_error(s, "one variable needs at least 2 samples (both ends), not 1",
                       "ProblemSource::samples");
  s.samples = 200'000'000;
  expect_problem_error(s, "at most 100,000,000 samples, not 200,000,000", "ProblemSource::samples");
  s.samples = 0;
  s.domain = {"x=0:1:90"};
  p = load_problem(s);
  EXPECT_EQ(p.data.rows(), 90u);
  EXPECT_DOUBLE_EQ(p.data.numeric("x").values.front(), 0.5 / 90);
  s.samples = 50;
  expect_problem_error(s,
                       "every variable has its number of points (a grid): a number of samples "
                       "does not apply",
                       "ProblemSource::samples");
}

TEST(ProblemReference, DefinitionsAreColumnsAndMayBeInputs) {
  ProblemSource s = reference_source("u * 2 + x", {"x=0:1"});
  s.reference.definitions = {"u = x^2"};
  s.samples = 11;
  Problem p = load_problem(s);
  EXPECT_EQ(p.data.names(), (Names{"x", "u", "reference"}));
  EXPECT_EQ(p.inputs, Names{"x"});
  const std::vector<double>& x = p.data.numeric("x").values;
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_EQ(p.data.numeric("u").values[i], x[i] * x[i]);
    EXPECT_EQ(p.data.numeric("reference").values[i], x[i] * x[i] * 2 + x[i]);
  }
  s.inputs = {"u", "x"};
  p = load_problem(s);
  EXPECT_EQ(p.inputs, (Names{"u", "x"}));
  EXPECT_EQ(p.target, "reference");
  EXPECT_EQ(p.notes, Names{"target reference (the reference's own)"});
  s.inputs = {"v"};
  expect_problem_error(s,
                       "no column 'v' in the reference's samples (numeric columns: x, u, "
                       "reference)",
                       "ProblemSource::inputs");
  s.inputs = {"x"};
  s.target = "u";
  p = load_problem(s);
  EXPECT_EQ(p.target, "u");
  EXPECT_EQ(p.reference->target, "u");
  s.inputs.clear();
  s.target = "x";
  expect_problem_error(s, "the target 'x' leaves no input: name the inputs too",
                       "ProblemSource::target");
  s.inputs = {"reference"};
  s.target.clear();
  expect_problem_error(s, "input 'reference' is the reference's target: name another target",
                       "ProblemSource::inputs");
}

TEST(ProblemReference, TwoVariablesInDomainOrder) {
  ProblemSource s = reference_source("x * y + y", {"y=0:2", "x=-1:1"});
  Problem p = load_problem(s);
  EXPECT_EQ(p.inputs, (Names{"y", "x"}));
  EXPECT_EQ(p.reference->program.inputs, (Names{"y", "x"}));
  EXPECT_EQ(p.data.rows(), 4u + 4 * 64 + 4096);
  EXPECT_EQ(p.description, "x * y + y on y in [0, 2], x in [-1, 1], 4,356 samples");
  EXPECT_EQ(p.reference->target_at(std::vector<double>{2, 0.5}), 3.0);
}

TEST(ProblemReference, DomainErrors) {
  expect_problem_error(reference_source("x * y", {"x=0:1"}),
                       "no domain for variable 'y' (give one: y=lo:hi)", "ProblemSource::domain");
  expect_problem_error(reference_source("x", {}), "no domain for variable 'x' (give one: x=lo:hi)",
                       "ProblemSource::domain");
  expect_problem_error(reference_source("x", {"x=0:1", "z=0:1"}),
                       "a domain for 'z', which the reference does not use (its variable: x)",
                       "ProblemSource::domain", 2);
  expect_problem_error(reference_source("x", {"x=0:1", "x=0:2"}),
                       "two domains for 'x' (entries 1 and 2)", "ProblemSource::domain", 2);
  expect_problem_error(reference_source("2 * pi", {}),
                       "the reference uses no variable: there is nothing to approximate",
                       "ProblemSource::reference");
  // The domain parser's own errors, at the entry's position.
  try {
    (void)load_problem(reference_source("x * y", {"x=0:1", "y=1:0"}));
    ADD_FAILURE() << "a reversed domain was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "ProblemSource::domain");
    EXPECT_EQ(e.where().line, 2);
  }
  try {
    (void)load_problem(reference_source("x", {"x=1:1"}));
    ADD_FAILURE() << "an empty domain was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "ProblemSource::domain");
    EXPECT_EQ(e.where().line, 1);
  }
  expect_problem_error(reference_source("x * y", {"x=0:1", "y=0:1", "z=0:1"}),
                       "a domain for 'z', which the reference does not use (its variables: x, y)",
                       "ProblemSource::domain", 3);
  ProblemSource seven = reference_source("a + b + c + d + e + f + g", {});
  for (const char* v : {"a", "b", "c", "d", "e", "f", "g"}) {
    seven.domain.push_back(std::string(v) + "=0:1");
  }
  expect_problem_error(seven,
                       "7 variables: the sample design covers 1 to 6 (a grid of more takes a "
                       "number of points for each, x=lo:hi:count)",
                       "ProblemSource::domain");
  seven.domain.back() = "g=0:1:2";
  for (std::size_t i = 0; i + 1 < seven.domain.size(); ++i) seven.domain[i] += ":2";
  EXPECT_EQ(load_problem(seven).data.rows(), 128u);
  ProblemSource mixed = reference_source("x * y", {"x=0:1", "y=0:1:10"});
  expect_problem_error(mixed,
                       "'y' has a number of points and 'x' has none: give every variable one (a "
                       "grid) or none (the sample design)",
                       "ProblemSource::domain");
}

TEST(ProblemReference, FormulaErrorsComeFromTheCompiler) {
  // An unknown function: located in the formula.
  try {
    (void)load_problem(reference_source("acoss(x)", {"x=-1:1"}));
    ADD_FAILURE() << "an unknown function was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "reference");
    EXPECT_NE(e.message().find("acoss"), std::string::npos) << e.message();
  }
}

TEST(ProblemReference, NonFiniteSamplesAreAnErrorOrDropped) {
  ProblemSource s = reference_source("sqrt(x)", {"x=-1:1"});
  expect_problem_error(s,
                       "the reference is NaN or infinite at 5,000 of 10,001 samples, first at x = "
                       "-1; they span x in [-1, -2e-04] (narrow the domain, or drop them: "
                       "ProblemSource::drop_nonfinite)",
                       "ProblemSource::reference");
  s.drop_nonfinite = true;
  Problem p = load_problem(s);
  EXPECT_EQ(p.data.rows(), 5'001u);
  EXPECT_EQ(p.data.numeric("x").values.front(), 0.0);
  EXPECT_EQ(p.data.numeric("x").values.back(), 1.0);
  EXPECT_EQ(p.description, "sqrt(x) on x in [-1, 1], 10,001 samples (5,000 dropped)");
  EXPECT_EQ(p.notes.back(),
            "dropped 5,000 of 10,001 samples where the reference is NaN or infinite, first at x "
            "= -1; they span x in [-1, -2e-04]");
  for (double v : p.data.numeric("reference").values) EXPECT_TRUE(std::isfinite(v));

  expect_problem_error(
      reference_source("1 / x", {"x=-1:1"}),
      "the reference is NaN or infinite at 1 of 10,001 samples, first at x = 0; "
      "they span x in [0, 0] (narrow the domain, or drop them: ProblemSource::drop_nonfinite)",
      "ProblemSource::reference");
  ProblemSource all = reference_source("sqrt(x)", {"x=-2:-1"});
  all.drop_nonfinite = true;
  expect_problem_error(all,
                       "the reference is NaN or infinite at 10,001 of 10,001 samples, first at x "
                       "= -2; they span x in [-2, -1]",
                       "ProblemSource::reference");
  // A definition used as an input is checked too.
  ProblemSource d = reference_source("x", {"x=-1:1"});
  d.reference.definitions = {"u = log(x)"};
  d.inputs = {"u"};
  d.samples = 5;
  expect_problem_error(d,
                       "'u' is NaN or infinite at 3 of 5 samples, first at x = -1; they span x in "
                       "[-1, 0] (narrow the domain, or drop them: ProblemSource::drop_nonfinite)",
                       "ProblemSource::reference");
}

constexpr const char* kSmithG1 = R"(// Smith GGX G1 for one direction.
float G1(float NdotV, float roughness) {
    float a = roughness * roughness;
    float a2 = a * a;
    float c = max(NdotV, 1e-4);
    float t = (1.0 - c * c) / (c * c);
    float g = 2.0 / (1.0 + sqrt(1.0 + a2 * t));
    return NdotV > 0.0 ? g : 0.0;
}
)";

double smith_g1(double n_dot_v, double roughness) {
  const double a2 = roughness * roughness * roughness * roughness;
  const double c = std::max(n_dot_v, 1e-4);
  const double g = 2.0 / (1.0 + std::sqrt(1.0 + a2 * ((1.0 - c * c) / (c * c))));
  return n_dot_v > 0.0 ? g : 0.0;
}

TEST(ProblemReference, ShaderFunction) {
  ProblemSource s;
  s.reference.shader_source = kSmithG1;
  s.reference.shader_path = "smith.glsl";
  s.reference.function = "G1";
  s.domain = {"roughness=0.05:1", "NdotV=0:1"};
  Problem p = load_problem(s);
  EXPECT_EQ(p.inputs, (Names{"roughness", "NdotV"}));
  EXPECT_EQ(p.target, "reference");
  EXPECT_EQ(p.data.rows(), 4u + 4 * 64 + 4096);
  const std::vector<double>& r = p.data.numeric("roughness").values;
  const std::vector<double>& n = p.data.numeric("NdotV").values;
  const std::vector<double>& g = p.data.numeric("reference").values;
  for (std::size_t i = 0; i < g.size(); ++i) ASSERT_NEAR(g[i], smith_g1(n[i], r[i]), 1e-15);
  EXPECT_EQ(p.reference->program.inputs, (Names{"roughness", "NdotV"}));
  EXPECT_NEAR(p.reference->target_at(std::vector<double>{0.5, 0.3}), smith_g1(0.3, 0.5), 1e-15);

  s.domain = {"NdotV=0:1"};
  expect_problem_error(s, "no domain for variable 'roughness' (give one: roughness=lo:hi)",
                       "ProblemSource::domain");
}

TEST(ProblemReference, TheDomainPicksAnOverloadedShaderFunction) {
  ProblemSource s;
  s.reference.shader_source =
      "float tonemap(float x, float k) { return x / (x + k); }\n"
      "float tonemap(float x) { return tonemap(x, 1.0); }\n";
  s.reference.shader_path = "tonemap.glsl";
  s.reference.function = "tonemap";
  s.domain = {"x=0:4"};
  Problem p = load_problem(s);
  EXPECT_NEAR(p.reference->target_at(std::vector<double>{3.0}), 0.75, 1e-15);
  s.domain = {"k=1:2", "x=0:4"};
  p = load_problem(s);
  EXPECT_NEAR(p.reference->target_at(std::vector<double>{2.0, 3.0}), 0.6, 1e-15);
  s.domain = {"y=0:4"};
  expect_problem_error(s,
                       "function 'tonemap' is defined 2 times (tonemap(float x, float k) at line "
                       "1, tonemap(float x) at line 2): the variables pick one, by its "
                       "parameters' names",
                       "tonemap.glsl", 2);
}

TEST(ProblemReference, ShaderFileIsReadWhenOnlyItsPathIsGiven) {
  TempFile f("smith.glsl", kSmithG1);
  ProblemSource s;
  s.reference.shader_path = f.path();
  s.reference.function = "G1";
  s.domain = {"NdotV=0:1", "roughness=0.05:1"};
  s.samples = 100;
  Problem p = load_problem(s);
  EXPECT_EQ(p.inputs, (Names{"NdotV", "roughness"}));
  EXPECT_EQ(p.data.rows(), 4u + 4 * 10 + 100);
  s.reference.shader_path = f.path() + ".missing";
  expect_problem_error(s, "cannot open '" + s.reference.shader_path + "'", s.reference.shader_path);
}

}  // namespace
}  // namespace shaderfit
