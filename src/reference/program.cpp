#include "shaderfit/reference/program.hpp"

#include <algorithm>
#include <array>

#include "shaderfit/core/error.hpp"
#include "shaderfit/reference/program_evaluate.hpp"

namespace shaderfit::reference {

namespace {

struct OpText {
  std::string_view name;
  int arity;  // -1: given by the instruction (Builtin)
};

constexpr std::array<OpText, kProgramOpCount> kOps = {{
    {"const", 0}, {"input", 0}, {"+", 2},     {"-", 2},         {"*", 2},        {"/", 2},
    {"neg", 1},   {"ipow", 1},  {"<", 2},     {"<=", 2},        {">", 2},        {">=", 2},
    {"==", 2},    {"!=", 2},    {"&&", 2},    {"||", 2},        {"!", 1},        {"select", 3},
    {"sign", 1},  {"cbrt", 1},  {"expm1", 1}, {"log10", 1},     {"log1p", 1},    {"tan", 1},
    {"sinh", 1},  {"cosh", 1},  {"asinh", 1}, {"acosh", 1},     {"atanh", 1},    {"erfc", 1},
    {"floor", 1}, {"ceil", 1},  {"trunc", 1}, {"round", 1},     {"pow", 2},      {"hypot", 2},
    {"fmod", 2},  {"min", 2},   {"max", 2},   {"operator", -1}, {"builtin", -1},
}};

SourceLocation where(const Program& p) { return SourceLocation{p.description}; }

void check_inputs(const Program& p, std::size_t given) {
  if (given != p.inputs.size()) {
    throw Error("the reference takes " + std::to_string(p.inputs.size()) + " inputs, got " +
                    std::to_string(given),
                where(p));
  }
}

// The registers of one thread's last evaluation, kept so that evaluating point after point
// allocates nothing.
std::vector<double>& scratch_registers() {
  thread_local std::vector<double> registers;
  return registers;
}

}  // namespace

std::string_view program_op_name(ProgramOp op) {
  const int i = static_cast<int>(op);
  return i >= 0 && i < kProgramOpCount ? kOps[static_cast<std::size_t>(i)].name : "?";
}

int program_op_arity(ProgramOp op) {
  const int i = static_cast<int>(op);
  return i >= 0 && i < kProgramOpCount ? kOps[static_cast<std::size_t>(i)].arity : 0;
}

double Program::evaluate(std::span<const double> point) const {
  check_inputs(*this, point.size());
  if (outputs.empty()) throw Error("the reference has no outputs", where(*this));
  std::vector<double>& registers = scratch_registers();
  evaluate_program<double>(*this, point, registers);
  return registers[outputs.back()];
}

void Program::evaluate_all(std::span<const double> point, std::span<double> out) const {
  check_inputs(*this, point.size());
  if (out.size() != outputs.size()) {
    throw Error("the reference has " + std::to_string(outputs.size()) +
                    " outputs, given room for " + std::to_string(out.size()),
                where(*this));
  }
  std::vector<double>& registers = scratch_registers();
  evaluate_program<double>(*this, point, registers);
  for (std::size_t k = 0; k < outputs.size(); ++k) out[k] = registers[outputs[k]];
}

std::vector<std::vector<double>> Program::evaluate_columns(
    std::span<const std::span<const double>> columns) const {
  check_inputs(*this, columns.size());
  const std::size_t rows = columns.empty() ? 1 : columns[0].size();
  for (std::size_t i = 1; i < columns.size(); ++i) {
    if (columns[i].size() != rows) {
      throw Error("input '" + inputs[i] + "' has " + std::to_string(columns[i].size()) +
                      " rows, input '" + inputs[0] + "' " + std::to_string(rows),
                  where(*this));
    }
  }
  std::vector<std::vector<double>> out(outputs.size(), std::vector<double>(rows));
  std::vector<double> point(columns.size());
  std::vector<double> registers(code.size());
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t i = 0; i < columns.size(); ++i) point[i] = columns[i][r];
    evaluate_program<double>(*this, point, registers);
    for (std::size_t k = 0; k < outputs.size(); ++k) out[k][r] = registers[outputs[k]];
  }
  return out;
}

int Program::find_output(std::string_view name) const {
  const auto it = std::find(output_names.begin(), output_names.end(), name);
  return it == output_names.end() ? -1 : static_cast<int>(it - output_names.begin());
}

int Program::find_input(std::string_view name) const {
  const auto it = std::find(inputs.begin(), inputs.end(), name);
  return it == inputs.end() ? -1 : static_cast<int>(it - inputs.begin());
}

}  // namespace shaderfit::reference
