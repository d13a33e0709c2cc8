// A reference function with its domain: what a problem stated as a reference keeps besides its
// samples, so that errors can be checked between the samples (verify/worst_case.hpp) and bounded
// over the whole domain (verify/certify.hpp).
//
//   ReferenceFunction f;
//   f.program = compile_reference({.formula = "acos(x)", .variables = {"x"}});
//   f.domain = {parse_domain_axis("x=-1:1", "domain")};
//   double y = f.target_at(std::vector<double>{0.5});
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/reference/domain.hpp"
#include "shaderfit/reference/program.hpp"

namespace shaderfit::reference {

struct ReferenceFunction {
  // Inputs: the domain's variables, in domain order. Outputs: named columns (the variables, the
  // definitions, then the target), as compile_reference makes them.
  Program program;
  std::vector<DomainAxis> domain;    // one per program input, in the same order
  std::string target = "reference";  // the output that is the function to approximate

  // The target at one point of the domain (domain.size() values).
  [[nodiscard]] double target_at(std::span<const double> point) const;
  // The outputs named `names` (columns: variables, definitions or the target) at one point, in
  // the order of `names`. Throws Error for a name that is no output.
  [[nodiscard]] std::vector<int> output_indices(std::span<const std::string> names) const;
  // Throws shaderfit::Error when the domain and the program's inputs differ in number or names,
  // or the target is not an output.
  void validate() const;
};

}  // namespace shaderfit::reference
