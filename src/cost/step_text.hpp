// Internal: the value a program step computes, as short infix text for listings.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "cost/step_program.hpp"

namespace shaderfit::cost_detail {

// The name of the function a call step prints as ("sqrt", "fma", "saturate"): its operator's
// name (expr/op.hpp).
std::string_view step_call_name(Op op);

class StepText {
 public:
  StepText(const Dag& dag, const Program& program);

  // Infix of step i ("1 - r0", "(1 - cos_theta)^4"), cut to max_chars with "...".
  [[nodiscard]] std::string of(int step, std::size_t max_chars = 48) const;

 private:
  struct Power {
    Operand base;
    int k = 1;
  };
  // The infix text, or when it is longer than `limit`, a text longer than `limit` whose first
  // `limit` characters are the infix's: a listing line needs only its first characters, and the
  // whole text of every step would cost the square of the formula's size.
  [[nodiscard]] std::string operand(const Operand& o, int min_level, std::size_t limit) const;
  [[nodiscard]] std::string step(int i, int min_level, std::size_t limit) const;
  [[nodiscard]] std::string pair(const Operand& a, int level_a, std::string_view op,
                                 const Operand& b, int level_b, std::size_t limit) const;

  const Dag& dag_;
  const Program& p_;
  std::vector<Power> powers_;  // x^k chains of the squaring expansion, printed as powers
};

}  // namespace shaderfit::cost_detail
