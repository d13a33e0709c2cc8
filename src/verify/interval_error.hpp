// The error of a formula against a reference, formula - reference, evaluated in intervals
// (verify/interval.hpp) over a box of the domain (with its gradient) or at a point: the reference
// program first, then the formula on the program's outputs that are its inputs.
//
//   IntervalError e(formula, {"x"}, reference, 64);
//   const Cell& over = e.over_box(lo, hi);   // over.v encloses the error on the box
//   const Cell& at = e.at_point(mid);         // valid until the next call
#pragma once

#include <span>
#include <string>
#include <vector>

#include "shaderfit/expr/expression.hpp"
#include "shaderfit/reference/function.hpp"
#include "verify/interval.hpp"

namespace shaderfit::verify {

class IntervalError {
 public:
  // Throws shaderfit::Error for an input that is no output of the program, a target that is none,
  // a formula variable beyond `inputs` or a parameter without a value, or a domain of more than
  // kMaxCertifyDims variables.
  IntervalError(const Expression& formula, const std::vector<std::string>& inputs,
                const reference::ReferenceFunction& reference, int precision_bits);

  [[nodiscard]] int dims() const { return dims_; }

  // The error over the box [lo, hi] (dims() values each), with its gradient and its values at
  // the box's points (verify/interval.hpp); or at a point, value only. The cells stay valid
  // until the next evaluation.
  const Cell& over_box(std::span<const double> lo, std::span<const double> hi);
  const Cell& at_point(std::span<const double> point);
  // The two sides of the last evaluation.
  [[nodiscard]] const Cell& formula_value() const { return *formula_value_; }
  [[nodiscard]] const Cell& reference_value() const { return *reference_value_; }

  Arena& arena() { return arena_; }

 private:
  const Cell& evaluate();

  const Expression& formula_;
  const reference::ReferenceFunction& reference_;
  int dims_;
  std::vector<int> input_outputs_;  // program output of each formula input
  int target_output_ = -1;
  Arena arena_;
  std::vector<Dual> domain_, registers_, stack_;
  Cell* formula_value_ = nullptr;
  Cell* reference_value_ = nullptr;
};

}  // namespace shaderfit::verify
