// The largest error of a formula between the samples: the samples tell the error where they
// are, a shader meets every value of the domain. A denser design (data/sampling.hpp) is checked,
// then the worst points are refined by local maximisation within the domain (docs/reference.md,
// "Worst case").
//
//   WorstCaseSearch w(reference, {"x"}, 10001);      // builds and evaluates the denser design once
//   WorstCase c = w.check(formula);                  // formula over the inputs {"x"}
//   c.max_abs;       // >= the error at every sample and every point checked
//   c.points;        // the worst points found, to join the data where they exceed the samples'
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "shaderfit/expr/expression.hpp"
#include "shaderfit/reference/function.hpp"
#include "shaderfit/verify/certify.hpp"

namespace shaderfit {

struct WorstCaseOptions {
  std::size_t samples = 0;   // the problem's sample design (its size; 0: the default)
  std::size_t density = 10;  // the check's design is this many times denser
  std::size_t starts = 8;    // worst points of the check refined by local maximisation
  int threads = 0;           // 0: all hardware threads
};

struct ErrorPoint {
  std::vector<double> point;  // domain coordinates, in domain order
  double abs_error = 0;       // |formula - reference| there
  double rel_error = 0;       // abs_error / |reference|; 0 where the reference is 0 (as metrics)
};

struct WorstCase {
  double max_abs = 0;  // the largest |error| found: dense design and local maxima
  double max_rel = 0;  // the largest relative error found (where the reference is not 0)
  ErrorPoint worst_abs, worst_rel;
  // The local maxima found by refining the dense design's worst points, worst first (for a
  // refit, the points to add to the data).
  std::vector<ErrorPoint> points;
  // False when the formula is NaN or infinite at a point checked (worst_abs is one such point);
  // max_abs is then +inf.
  bool finite = true;
  std::size_t evaluations = 0;  // points at which the formula was evaluated
  // The formula computed in float32 operation by operation (inputs and constants rounded to
  // float, as a shader computes it) against the reference, over the dense design.
  double float32_max_abs = 0;
  double float32_max_rel = 0;
};

class WorstCaseSearch {
 public:
  // `inputs` are the formulas' variables: outputs of reference.program (domain variables or
  // definitions). Throws shaderfit::Error for an input that is no output.
  WorstCaseSearch(const reference::ReferenceFunction& reference, std::vector<std::string> inputs,
                  const WorstCaseOptions& options = {});

  // The formula (over `inputs`) checked on the dense design, then refined around its worst
  // points. Thread-safe (const).
  [[nodiscard]] WorstCase check(const Expression& formula) const;

  // The error's local maximum near `point` (domain coordinates): a compass search from it in
  // steps of a millionth of the domain's width, halved when nothing improves. For points a
  // certification could not bound (Certificate::trouble_point), where the error may blow up.
  [[nodiscard]] ErrorPoint refine(const Expression& formula, std::span<const double> point) const;

  // The largest error a certification of `formula` met at a point (Certificate::attained), or,
  // where it found no finite bound, the error maximised from its trouble point (refine),
  // whichever is larger: an error the formula reaches, so max_abs may be raised to it.
  [[nodiscard]] ErrorPoint certified_worst(const Expression& formula,
                                           const Certificate& certificate) const;

  [[nodiscard]] std::size_t dense_points() const;
  // The inputs' values at a domain point, in inputs order, and the reference there.
  void at(std::span<const double> point, std::span<double> inputs, double* target) const;

 private:
  const reference::ReferenceFunction& reference_;
  std::vector<std::string> input_names_;
  std::vector<int> input_outputs_;  // output index of each input
  int target_output_ = -1;
  WorstCaseOptions options_;
  std::vector<std::vector<double>> dense_domain_;   // the design, one column per domain axis
  std::vector<std::vector<double>> dense_inputs_;   // the inputs there, one column per input
  std::vector<std::vector<float>> dense_inputs32_;  // the same rounded to float
  std::vector<double> dense_target_;
};

}  // namespace shaderfit
