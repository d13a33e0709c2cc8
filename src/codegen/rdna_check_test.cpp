// The RDNA cost model (targets rdna2 and rdna3) against LLVM's AMDGPU back end: the generated code
// compiled by clang as OpenCL C for gfx1030 (RDNA 2) and gfx1100 (RDNA 3), its VALU instructions
// counted (compile_amdgpu). Each test skips with "skipped: ..." where clang lacks the processor;
// formulas with library functions need ROCm's OCML (Debian's rocm-device-libs) and clang 15.
// docs/cost-model.md, "RDNA", has the agreement and where the model differs.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "codegen/compiler_harness_test_support.hpp"
#include "cost/op_instructions.hpp"
#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/expr/simplify.hpp"

namespace shaderfit {
namespace {

struct Processor {
  const char* mcpu;
  InstructionTarget target;
};
constexpr Processor kProcessors[] = {{"gfx1030", InstructionTarget::Rdna2},
                                     {"gfx1100", InstructionTarget::Rdna3}};

std::vector<Expression> parsed(std::initializer_list<const char*> texts) {
  std::vector<Expression> out;
  for (const char* t : texts) out.push_back(parse_formula(t));
  return out;
}

// Compiles `formulas` for each processor clang has; returns per processor the formulas where the
// model and clang differ, as lines, and prints the table.
struct Agreement {
  int checked = 0, agree = 0;
  std::string differs;
};
// ROCm's OCML for the library functions where it can be linked: Debian's rocm-device-libs 5.2
// is LLVM 15 bitcode, which clang 14 cannot read.
std::optional<std::filesystem::path> usable_ocml(const std::string& clang) {
  if (clang.find("clang-15") == std::string::npos) return std::nullopt;
  return testing::find_ocml();
}

bool calls_library(const Expression& e) {
  return std::any_of(e.nodes.begin(), e.nodes.end(),
                     [](const Node& n) { return cost_detail::library_call(n.op) != nullptr; });
}

Agreement check(const Processor& cpu, const std::vector<Expression>& all, const std::string& name) {
  Agreement a;
  const auto clang = testing::find_amdgpu_clang(cpu.mcpu);
  if (!clang) {
    std::cout << "skipped: no clang with the AMDGPU target for " << cpu.mcpu << '\n';
    return a;
  }
  const auto ocml = usable_ocml(*clang);
  std::vector<Expression> formulas;
  for (const Expression& e : all)
    if (ocml || !calls_library(e)) formulas.push_back(e);
  if (formulas.size() < all.size())
    std::cout << "skipped: " << all.size() - formulas.size()
              << " formulas with asin ... erf (no clang 15 with ROCm's ocml.bc)\n";
  const testing::CompiledCounts c =
      testing::compile_amdgpu(formulas, *clang, cpu.mcpu, name + "_" + cpu.mcpu, ocml);
  EXPECT_TRUE(c.ok) << c.log;
  if (!c.ok) return a;
  for (std::size_t i = 0; i < formulas.size(); ++i) {
    int model = -1;
    try {
      model = instruction_count(formulas[i], cpu.target);
    } catch (const Error& e) {
      ADD_FAILURE() << to_infix(formulas[i]) << ": " << e.what();
    }
    ++a.checked;
    if (c.valu[i] == model)
      ++a.agree;
    else
      a.differs += "\n  " + std::to_string(model) + " model, " + std::to_string(c.valu[i]) +
                   " clang: " + to_infix(formulas[i]);
  }
  std::cout << cpu.mcpu << ", " << name << ": " << a.agree << " of " << a.checked << " agree"
            << a.differs << '\n';
  return a;
}

// The four formulas, as clang counts them written by hand: 4, 2, 3 and 4.
TEST(RdnaCheck, HandCountedFormulas) {
  const std::vector<Expression> f =
      parsed({"x*x*x + 1/(x + 2)", "exp2(a*x + 0.5)", "pow(x, 2.4)", "x > 0.5 ? x*x : sqrt(x)"});
  const int expected[] = {4, 2, 3, 4};
  for (const Processor& cpu : kProcessors) {
    for (std::size_t i = 0; i < f.size(); ++i)
      EXPECT_EQ(instruction_count(f[i], cpu.target), expected[i]) << i;
    const Agreement a = check(cpu, f, "hand");
    EXPECT_EQ(a.agree, a.checked) << a.differs;
  }
}

// The shading formulas of compiler_check_test's table, the operators with their own rules, and the
// sign, copysign and select formulas of the compiler checks.
TEST(RdnaCheck, ShadingFormulasAndOperatorRules) {
  std::vector<Expression> f = parsed({
      "r0 + (1 - r0) * (1 - cos_theta)^5",
      "r0 + (1 - cos_theta - r0) * (1 - cos_theta)^4",
      "r0 + (1 - r0 - s * cos_theta) * (1 - cos_theta)^4",
      "r0 + (1 - r0) * exp2((-5.55473 * cos_theta - 6.98316) * cos_theta)",
      "2 * n_dot_v / (n_dot_v + sqrt(a2 + (1 - a2) * n_dot_v^2))",
      "a2 / (3.14159265 * (n_dot_h^2 * (a2 - 1) + 1)^2)",
      "0.25 / ((n_dot_l * (1 - k) + k) * (n_dot_v * (1 - k) + k))",
      "exp2(log2(c) * 0.45454545)",
      "x / (1 + x)",
      "saturate(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14))",
      "saturate(x * y)",
      "saturate(fma(x, y, 0.3))",
      "saturate(fma(x, 0.3, y))",
      "saturate(x + 0.3)",
      "sqrt(x) * sqrt(y)",
      "sqrt(1 - x) * sqrt(y)",
      "y / rsqrt(x)",
      "saturate(x + y) * y",
      "saturate(x)",
      "saturate(sqrt(x)) + x",
      "min(max(x, 0.25), 0.75)",
      "max(min(x, 0.75), 0.25)",
      "min(max(x, y), 2)",
      "sin(x) + cos(x)",
      "sin(2 * x)",
      "exp(3 * x)",
      "log(x) * 3",
      "exp(-x * y)",
      "1 / exp2(x)",
      "-sqrt(x)",
      "-cos(x)",
      "copysign(x, y)",
      "copysign(x, -y)",
      "sign(x) * y",
      "abs(x * y) + sqrt(abs(x * y))",
      "x >= y ? x * y : x + 1",
      "x * y >= 1 ? x : y * y",
      "-x >= 0 ? y : x * x",
      "x >= 0 ? -y : x * x",
      "-(x >= 0 ? y : x * x)",
      "rcp(x) * y - rcp(x)",
      "rsqrt(x * y)",
      "x / y",
      "-(x * y + 1)",
  });
  for (const char* t : testing::kNewOperators) f.push_back(parse_formula(t));
  for (const Processor& cpu : kProcessors) {
    const Agreement a = check(cpu, f, "rules");
    EXPECT_EQ(a.agree, a.checked) << a.differs;
  }
}

TEST(RdnaCheck, LibraryFunctions) {
  std::vector<Expression> f;
  for (const char* t : testing::kLibraryOperators) f.push_back(parse_formula(t));
  for (const Processor& cpu : kProcessors) {
    const Agreement a = check(cpu, f, "library");
    EXPECT_EQ(a.agree, a.checked) << a.differs;
  }
}

// The yardstick's published formulas (bench/published_forms.py keeps them).
TEST(RdnaCheck, PublishedFormulas) {
  std::ifstream in(std::string(SHADERFIT_SOURCE_DIR) +
                   "/src/codegen/testdata/published_forms.json");
  ASSERT_TRUE(in) << "published_forms.json not found";
  const nlohmann::json j = nlohmann::json::parse(in);
  std::vector<Expression> f;
  for (const auto& form : j.at("forms")) {
    ParseOptions o;
    o.variables = form.at("inputs").get<std::vector<std::string>>();
    f.push_back(parse_formula(form.at("formula").get<std::string>(), o));
  }
  for (const Processor& cpu : kProcessors) {
    const Agreement a = check(cpu, f, "published");
    if (a.checked > 0) {
      EXPECT_GE(a.agree * 100, a.checked * 95) << a.differs;
    }
  }
}

// The members of real search fronts (the printer's corpus, bench/printed_fronts.py): the formulas
// users get.
TEST(RdnaCheck, SearchFronts) {
  std::ifstream in(std::string(SHADERFIT_SOURCE_DIR) +
                   "/src/search/front/testdata/printed_fronts.json");
  ASSERT_TRUE(in) << "printed_fronts.json not found";
  const nlohmann::json j = nlohmann::json::parse(in);
  std::vector<Expression> f;
  for (const auto& c : j.at("cases")) {
    ParseOptions o;
    for (const auto& [name, range] : c.at("ranges").items()) o.variables.push_back(name);
    for (const auto& m : c.at("members"))
      f.push_back(parse_formula(m.at("formula").get<std::string>(), o));
  }
  for (const Processor& cpu : kProcessors) {
    const Agreement a = check(cpu, f, "search fronts");
    if (a.checked > 0) {
      EXPECT_GE(a.agree * 100, a.checked * 95) << a.differs;
    }
  }
}

// docs/cost-model.md: the agreement on 200 random formulas of the search's operators, simplified
// as the search leaves its fronts (at least 95%); as generated, with the x - x, x / x and
// log2(exp2(x)) that LLVM's fast math removes and the model counts, the agreement is printed.
TEST(RdnaCheck, TwoHundredRandomFormulas) {
  for (const std::uint64_t seed : {2024, 7, 11}) {
    Rng rng(seed);
    const std::vector<Expression> raw = testing::random_formulas(rng, 200, {"a", "b", "c"});
    std::vector<Expression> simplified;
    for (const Expression& e : raw) simplified.push_back(simplify(e, {.regroup_constants = true}));
    const std::string name = "random seed " + std::to_string(seed);
    for (const Processor& cpu : kProcessors) {
      check(cpu, raw, name + " as generated");
      const Agreement a = check(cpu, simplified, name + " simplified");
      if (a.checked > 0) {
        EXPECT_GE(a.agree, 190) << a.differs;
      }
    }
  }
}

}  // namespace
}  // namespace shaderfit
