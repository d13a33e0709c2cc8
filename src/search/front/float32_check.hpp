// Float32 against float64: is a front member's formula stable when a shader computes it in
// float32? (internal; the bound is documented in docs/reliability.md.)
//
//   Float32Check check(problem);
//   check.apply(member);   // sets member.float32_max_abs_diff, float32_stable, float32_max_abs
//                          // float32_max_rel, half_max_abs and half_max_rel
#pragma once

#include <vector>

#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

// A member is stable when float32 and float64 differ by at most
//   max(kFloat32ScaleShare * max |target|, kFloat32ErrorShare * member max_abs error)
// on every row: float32 then changes its values by a tiny fraction of the target's scale, or by
// little next to the error the formula has anyway. Float32 rounding of a well-conditioned
// formula of 25 nodes stays near 1e-6 of the scale, so the bound flags cancellation and
// overflow, not ordinary rounding.
inline constexpr double kFloat32ScaleShare = 1e-4;
inline constexpr double kFloat32ErrorShare = 0.01;

class Float32Check {
 public:
  explicit Float32Check(const SearchProblem& problem);

  // The largest |float32(e) - float64(e)| over the rows, where float32 rounds the inputs and
  // constants and computes every operation in float (as the generated code does); +infinity
  // when either is not finite on a row.
  [[nodiscard]] double max_abs_diff(const Expression& e) const;
  // The largest |float32(e) - float64(e)| as above, and float32(e)'s error against the target:
  // the largest absolute and relative (over rows where the target is not 0) error.
  struct Errors {
    double max_abs_diff = 0;
    double max_abs = 0;
    double max_rel = 0;
    double half_max_abs = 0;  // the formula computed in half (eval/evaluate_in.hpp)
    double half_max_rel = 0;
  };
  [[nodiscard]] Errors errors(const Expression& e) const;
  [[nodiscard]] double bound(const FrontMember& m) const;
  void apply(FrontMember& m) const;

 private:
  const SearchProblem& problem_;
  std::vector<std::vector<float>> inputs32_;
  double scale_ = 1;  // max |target|
};

}  // namespace shaderfit::search_detail
