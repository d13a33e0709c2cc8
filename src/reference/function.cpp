#include "shaderfit/reference/function.hpp"

#include "shaderfit/core/error.hpp"
#include "shaderfit/reference/program_evaluate.hpp"

namespace shaderfit::reference {

double ReferenceFunction::target_at(std::span<const double> point) const {
  const int k = program.find_output(target);
  if (k < 0)
    throw Error("'" + target + "' is not an output of the reference", {program.description});
  if (point.size() != program.inputs.size()) {
    throw Error("the reference takes " + std::to_string(program.inputs.size()) + " inputs, got " +
                    std::to_string(point.size()),
                {program.description});
  }
  thread_local std::vector<double> registers;
  evaluate_program<double>(program, point, registers);
  return registers[program.outputs[static_cast<std::size_t>(k)]];
}

std::vector<int> ReferenceFunction::output_indices(std::span<const std::string> names) const {
  std::vector<int> out;
  for (const std::string& n : names) {
    const int k = program.find_output(n);
    if (k < 0) {
      std::string known;
      for (const std::string& o : program.output_names) known += (known.empty() ? "" : ", ") + o;
      throw Error("'" + n + "' is not a column of the reference (its columns: " + known + ")",
                  {program.description});
    }
    out.push_back(k);
  }
  return out;
}

void ReferenceFunction::validate() const {
  const SourceLocation where{program.description};
  if (domain.size() != program.inputs.size()) {
    throw Error("the reference has " + std::to_string(program.inputs.size()) +
                    " variables and the domain " + std::to_string(domain.size()),
                where);
  }
  for (std::size_t i = 0; i < domain.size(); ++i) {
    if (domain[i].name != program.inputs[i]) {
      throw Error("domain " + std::to_string(i + 1) + " is for '" + domain[i].name +
                      "', the reference's variable " + std::to_string(i + 1) + " is '" +
                      program.inputs[i] + "'",
                  where);
    }
  }
  if (program.find_output(target) < 0)
    throw Error("'" + target + "' is not an output of the reference", where);
}

}  // namespace shaderfit::reference
