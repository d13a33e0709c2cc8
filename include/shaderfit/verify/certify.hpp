// Certified error bounds: a rigorous upper bound of |formula - reference| over the whole domain,
// by interval arithmetic with outward rounding (MPFI over MPFR) and branch and bound over the
// box (docs/reference.md, "Certification"). The formula is the exact expression (its constants
// as stored, evaluated in real arithmetic), not its float32 rounding.
//
//   Certificate c = certify(formula, {"x"}, reference);   // formula over the inputs {"x"}
//   c.bound;      // |formula(x) - reference(x)| <= bound for every x of the domain
//   c.attained;   // and it reaches at least this somewhere (c.attained_point)
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "shaderfit/expr/expression.hpp"
#include "shaderfit/reference/function.hpp"

namespace shaderfit {

struct CertifyOptions {
  // Stop once the bound is at most (1 + tolerance) times the largest error found at a point.
  double tolerance = 0.01;
  // Also stop once the bound is at most `resolution` times the largest |reference| met: an exact
  // formula's bound (exp2(x) for exp2(x)) shrinks only with a power of the boxes' width, and
  // errors this small are far below float32's resolution (2^-24).
  double resolution = 0x1p-30;
  // The budget per formula; when it ends first the bound is still rigorous, only looser.
  double time_limit_s = 10.0;
  std::size_t max_boxes = 1u << 22;
  int precision_bits = 64;  // of the interval endpoints (MPFR), >= 53
};

struct Certificate {
  // |formula - reference| <= bound at every point of the domain; +inf when no finite bound was
  // found (the formula or the reference is undefined or unbounded somewhere: see note).
  double bound = 0;
  double attained = 0;  // the largest error found at a point: a lower bound of the true maximum
  std::vector<double> attained_point;  // domain coordinates
  bool converged = false;  // bound <= (1 + tolerance) * attained, or <= resolution's floor
  std::size_t boxes = 0;   // boxes evaluated
  double time_s = 0;
  std::string note;  // why not converged or infinite, for people; empty when converged
  // Where no finite bound could be found (a point where the error may be undefined, or the
  // centre of the narrowest box that kept an infinite bound); empty otherwise.
  std::vector<double> trouble_point;
};

// `inputs` are the formula's variables (Var index i is inputs[i]): outputs of reference.program
// (domain variables or definitions). Throws shaderfit::Error for an input that is no output, a
// domain of more than 8 variables or not finite, options out of range. Thread-safe: each call
// has its own interval registers.
Certificate certify(const Expression& formula, const std::vector<std::string>& inputs,
                    const reference::ReferenceFunction& reference,
                    const CertifyOptions& options = {});

}  // namespace shaderfit
