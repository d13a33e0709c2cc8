// The cost record (cost/op_instructions.hpp): every row complete for what its kind needs, and the
// operators without one those the selectors write themselves.
#include "cost/op_instructions.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit::cost_detail {
namespace {

Op op_at(int i) { return static_cast<Op>(i); }

TEST(OpInstructions, EveryRowIsComplete) {
  for (int i = 0; i < kOpCount; ++i) {
    const OpInstructions* f = op_instructions(op_at(i));
    if (f == nullptr) continue;
    SCOPED_TRACE(std::string(op_info(op_at(i)).name));
    if (f->library()) {
      // A library function: measured on every target.
      for (std::string_view list : {f->sass, f->ptx, f->spirv, f->ocml, f->rdna})
        EXPECT_FALSE(list.empty());
      EXPECT_TRUE(f->half2.empty()) << "half forms have no library functions";
    } else if (!f->sass.empty()) {
      // A function of the hardware: one instruction of the multi-function unit on each target,
      // and a packed half form.
      for (std::string_view m : {f->sass, f->ptx, f->spirv, f->rdna}) {
        EXPECT_EQ(mnemonics(m).size(), 1u) << m;
        EXPECT_EQ(mnemonic_unit(m), InstructionUnit::Mufu) << m;
      }
      EXPECT_FALSE(f->half2.empty());
      EXPECT_FALSE(f->half2_call.empty());
    } else if (!f->ptx.empty()) {
      // The arithmetic: one PTX and one SPIR-V instruction, the register-level targets' own.
      EXPECT_EQ(mnemonics(f->ptx).size(), 1u);
      EXPECT_EQ(mnemonics(f->spirv).size(), 1u);
      EXPECT_TRUE(f->rdna.empty() && f->half2.empty());
    } else {
      // Only a packed half form (exp, log: the selectors write the scaled forms).
      EXPECT_FALSE(f->half2.empty());
      EXPECT_FALSE(f->half2_call.empty());
    }
    if (f->turns || f->exponential) {
      EXPECT_EQ(arity(op_at(i)), 1);
    }
    if (f->sass_modifiers) {
      EXPECT_TRUE(f->sass.empty()) << "an arithmetic row";
    }
  }
}

// Every searchable operator costs on every target, with a row or by the selectors' own rules.
TEST(OpInstructions, EverySearchableOperatorHasACostOnEveryTarget) {
  for (int i = 0; i < kOpCount; ++i) {
    const Op op = op_at(i);
    const OpInfo& info = op_info(op);
    if (info.search == 0 || op == Op::IPow) continue;
    std::string formula(info.name);
    if (info.infix) {
      formula = "x " + formula + " y";
    } else if (op == Op::Select) {
      formula = "select(x >= y, x, y)";
    } else {
      formula += info.arity == 1 ? "(x)" : "(x, y)";
    }
    SCOPED_TRACE(formula);
    ParseOptions options;
    options.variables = {"x", "y"};
    const Expression e = parse_formula(formula, options);
    for (InstructionTarget t : kInstructionTargets) {
      SCOPED_TRACE(std::string(instruction_target_name(t)));
      if (t != InstructionTarget::SassHalf2) {
        EXPECT_GT(instruction_count(e, t), 0);
        continue;
      }
      // The packed half form lacks some (sign, select, asin ... erf: docs/precision.md), and
      // says so.
      try {
        EXPECT_GT(instruction_count(e, t), 0);
      } catch (const Error& error) {
        EXPECT_NE(std::string(error.what()).find("has no half form"), std::string::npos)
            << error.what();
      }
    }
  }
}

}  // namespace
}  // namespace shaderfit::cost_detail
