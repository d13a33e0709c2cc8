// What the reference fuzz targets (reference_fuzz.cpp, shader_fuzz.cpp) check of every program
// compile_reference makes: straight-line code whose operands come before their instruction,
// outputs and names that agree, and evaluation in double and on Taylor jets without a crash.
#pragma once

#include <string>
#include <vector>

#include "fuzz_targets.hpp"
#include "shaderfit/expr/jet.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/reference/program_evaluate.hpp"

namespace shaderfit::fuzz {

inline void check_program(const shaderfit::reference::Program& p) {
  using shaderfit::reference::Instruction;
  using shaderfit::reference::ProgramOp;
  for (std::size_t i = 0; i < p.code.size(); ++i) {
    const Instruction& in = p.code[i];
    if (static_cast<int>(in.op) >= shaderfit::reference::kProgramOpCount)
      throw FuzzFailure("instruction " + std::to_string(i) + " has no op");
    for (int k = 0; k < in.arity; ++k) {
      if (in.operands[static_cast<std::size_t>(k)] >= i)
        throw FuzzFailure("instruction " + std::to_string(i) + " reads a later register");
    }
    if (in.op == ProgramOp::Input &&
        (in.index < 0 || static_cast<std::size_t>(in.index) >= p.inputs.size()))
      throw FuzzFailure("instruction " + std::to_string(i) + " reads no input");
  }
  if (p.outputs.size() != p.output_names.size() || p.outputs.empty() ||
      p.output_names.back() != shaderfit::reference::kReferenceOutput)
    throw FuzzFailure("the outputs do not end with the reference");
  for (const std::uint32_t r : p.outputs)
    if (r >= p.code.size()) throw FuzzFailure("an output reads no register");
  for (std::size_t i = 0; i < p.inputs.size(); ++i)
    if (p.output_names[i] != p.inputs[i])
      throw FuzzFailure("the outputs do not start with the inputs");
  // A few points, in double and on jets: the values must agree.
  for (const double v : {0.0, 0.5, -1.25, 3.0}) {
    const std::vector<double> point(p.inputs.size(), v);
    const double y = p.evaluate(point);
    std::vector<Jet> at(p.inputs.size(), Jet::variable(v, 2));
    std::vector<Jet> registers;
    shaderfit::reference::evaluate_program<Jet>(p, at, registers);
    const double jet = registers[p.outputs.back()].value();
    if (!(jet == y || (jet != jet && y != y)))
      throw FuzzFailure("jets and doubles disagree: " + std::to_string(jet) + " vs " +
                        std::to_string(y));
  }
}

}  // namespace shaderfit::fuzz
