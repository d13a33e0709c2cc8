// Minimax (best uniform) approximation by Remez exchange, and the equioscillation it reports.
//
// Used through solve() with RationalOptions::fit = Fit::Minimax: the conditions are kept exact
// and the remaining coefficients minimise max |error| over the domain (or max |error / f| with
// relative_minimax). Chebyshev's theorem characterises the optimum: the error equioscillates,
// reaching its maximum with alternating signs at (number of free coefficients + 1) points. The
// Equioscillation below lists those points, so a caller can check the optimum was reached: the
// relative spread of |error| at them is ~0 and the levelled error equals the maximum error.
//
// Method. Polynomials: the classic exchange (solve p(x_i) + (-1)^i E / w(x_i) = f(x_i) on the
// reference, move the reference to the extrema of the new error, repeat). Rationals: the standard
// nonlinear Remez, where P(x_i) - (f(x_i) - (-1)^i E / w(x_i)) Q(x_i) = 0 is linear in the
// coefficients for fixed E; E is found as a real generalised eigenvalue of that pencil, the one of
// least magnitude whose denominator has no zero on the domain. Internally P and Q are expanded in
// Chebyshev polynomials of the domain mapped to [-1, 1], for conditioning, and converted to the
// form's variable at the end. An odd or even target on a symmetric domain (atan on [-1, 1]) has a
// degenerate alternation in the full monomial basis (the best degree-4 approximation of an odd
// function is the odd degree-3 one); for polynomials without conditions, shaderfit detects the
// symmetry and runs the exchange on [0, hi] with the odd (or even) Chebyshev polynomials only.
#pragma once

#include <string>
#include <vector>

namespace shaderfit::rational {

struct MinimaxOptions {
  int max_iterations = 60;  // exchanges before giving up
  double tolerance = 1e-9;  // stop when the spread of |error| on the reference is below this
  int grid = 0;             // points of the extremum search; 0 = max(1000, 60 * coefficients)

  [[nodiscard]] bool is_valid(std::string* why) const;
};

struct Equioscillation {
  std::vector<double> points;  // the alternation points, ascending
  std::vector<double> errors;  // the (weighted) error at each: alternating signs
  double levelled_error = 0;   // |E| from the last reference solve
  double max_error = 0;        // max |weighted error| over the domain
  double spread = 0;           // (max - min) / max of |errors|
  int iterations = 0;
  bool converged = false;
  bool relative = false;   // errors are relative (error / f) rather than absolute
  bool symmetric = false;  // solved on half the domain by symmetry; points mirrored
};

}  // namespace shaderfit::rational
