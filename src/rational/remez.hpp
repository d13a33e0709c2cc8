// The Remez exchange behind Fit::Minimax (internal to src/rational; see minimax.hpp).
#pragma once

#include <Eigen/Dense>
#include <span>
#include <string>
#include <vector>

#include "shaderfit/rational/minimax.hpp"
#include "shaderfit/rational/rational_function.hpp"
#include "shaderfit/rational/solve.hpp"
#include "shaderfit/rational/target.hpp"

namespace shaderfit::rational_detail {

using namespace shaderfit::rational;  // the area's public names

struct MinimaxOutcome {
  FormStatus status = FormStatus::Failed;
  std::string message;
  Rational rational;
  Equioscillation equioscillation;
};

// Best approximation of `target` on `domain` by `form`, keeping the homogeneous rows
// `constraints` (over [p_0..p_m, q_0..q_n], see linear_rows.hpp) exact.
MinimaxOutcome remez(const Target& target, std::span<const double> params, Interval domain,
                     const RationalForm& form, const Eigen::MatrixXd& constraints, bool relative,
                     const MinimaxOptions& options);

// One local extremum of the error: where, and the signed error there.
struct Extremum {
  double s = 0, e = 0;
};

// From candidate extrema sorted by s, `count` points with alternating signs that keep the
// largest |e|: consecutive points of one sign are merged into the largest, then end points or
// adjacent pairs of the smallest |e| are dropped. Empty if fewer than `count` alternate.
std::vector<Extremum> choose_reference(const std::vector<Extremum>& candidates, std::size_t count);

}  // namespace shaderfit::rational_detail
