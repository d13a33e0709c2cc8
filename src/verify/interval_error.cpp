#include "verify/interval_error.hpp"

#include "shaderfit/core/error.hpp"
#include "shaderfit/reference/program_evaluate.hpp"

namespace shaderfit::verify {

namespace {

const SourceLocation kWhere{"certify"};

}  // namespace

IntervalError::IntervalError(const Expression& formula, const std::vector<std::string>& inputs,
                             const reference::ReferenceFunction& reference, int precision_bits)
    : formula_(formula),
      reference_(reference),
      dims_(static_cast<int>(reference.domain.size())),
      arena_(precision_bits, static_cast<int>(reference.domain.size())) {
  const reference::Program& program = reference.program;
  if (dims_ < 1 || dims_ > kMaxCertifyDims) {
    throw Error("a certified bound takes 1 to " + std::to_string(kMaxCertifyDims) +
                    " domain variables, not " + std::to_string(dims_),
                kWhere);
  }
  reference.validate();
  for (const std::string& name : inputs) {
    const int k = program.find_output(name);
    if (k < 0) throw Error("the formula's input '" + name + "' is not a reference column", kWhere);
    input_outputs_.push_back(k);
  }
  target_output_ = program.find_output(reference.target);
  for (const Node& n : formula.nodes) {
    if (n.op == Op::Var && (n.index < 0 || static_cast<std::size_t>(n.index) >= inputs.size())) {
      throw Error("the formula's variable " + std::to_string(n.index) + " has no input", kWhere);
    }
    if (n.op == Op::Param &&
        (n.index < 0 || static_cast<std::size_t>(n.index) >= formula.parameter_values.size())) {
      throw Error("the formula's parameter " + std::to_string(n.index) + " has no value", kWhere);
    }
  }
  if (formula.nodes.empty()) throw Error("the formula is empty", kWhere);
  domain_.reserve(static_cast<std::size_t>(dims_));
  registers_.reserve(program.code.size());
  stack_.reserve(formula.nodes.size());
}

const Cell& IntervalError::over_box(std::span<const double> lo, std::span<const double> hi) {
  ArenaScope scope(arena_);
  arena_.begin(lo, hi, true);
  return evaluate();
}

const Cell& IntervalError::at_point(std::span<const double> point) {
  ArenaScope scope(arena_);
  arena_.begin(point, point, false);
  return evaluate();
}

const Cell& IntervalError::evaluate() {
  const reference::Program& program = reference_.program;
  domain_.clear();
  for (int i = 0; i < dims_; ++i) domain_.push_back(Dual::variable(i));
  reference::evaluate_program<Dual>(program, domain_, registers_);
  // The formula in postfix, its variables read from the program's outputs.
  stack_.clear();
  for (const Node& n : formula_.nodes) {
    switch (n.op) {
      case Op::Const: stack_.push_back(Dual(n.value)); break;
      case Op::Param:
        stack_.push_back(Dual(formula_.parameter_values[static_cast<std::size_t>(n.index)]));
        break;
      case Op::Var: {
        const int out = input_outputs_[static_cast<std::size_t>(n.index)];
        stack_.push_back(registers_[program.outputs[static_cast<std::size_t>(out)]]);
        break;
      }
      default: {
        const std::size_t k = n.arity;
        const Dual r =
            apply_op(n.op, n.index, std::span<const Dual>(stack_.data() + stack_.size() - k, k));
        stack_.resize(stack_.size() - k, r);
        stack_.push_back(r);
        break;
      }
    }
  }
  const Dual f = stack_.back();
  const Dual ref = registers_[program.outputs[static_cast<std::size_t>(target_output_)]];
  formula_value_ = f.get();
  reference_value_ = ref.get();
  return *(f - ref);
}

}  // namespace shaderfit::verify
