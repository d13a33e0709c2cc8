// The operator sets `auto` stands for, chosen from the data (docs/search.md, "Operators").
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "search/starts/library_operators.hpp"
#include "search/starts/operator_probe.hpp"
#include "shaderfit/search/search.hpp"
#include "shaderfit/search/symmetry.hpp"

namespace shaderfit {

namespace {

// The shading set: the default arithmetic and integer powers, plus the one-instruction functions
// that shading formulas are made of (square roots, base-2 exponentials and logarithms, abs, min
// and max). The yardstick (bench/approximations) measured it on 32 published approximations.
constexpr Op kShadingOperators[] = {Op::Add,  Op::Sub,  Op::Mul, Op::Div, Op::IPow, Op::Sqrt,
                                    Op::Exp2, Op::Log2, Op::Abs, Op::Min, Op::Max};
// What the evolution adds: a fitted exponent, the reciprocal square root (normalisation) and the
// clamp to [0, 1].
constexpr Op kShadingEvolutionOperators[] = {Op::Pow, Op::Rsqrt, Op::Saturate};
// A target whose largest magnitude exceeds its median magnitude by this factor has a high dynamic
// range (a sharp peak, as a specular lobe): pow with a variable exponent is enumerated for it.
constexpr double kHighDynamicRange = 100;
// Where an input takes both signs the function may be odd or even in it, or reflected at 0 (as
// acos, erf, atan): the enumeration gets sign and copysign, the evolution select.
constexpr Op kBothSignsOperators[] = {Op::Sign, Op::CopySign};
constexpr Op kBothSignsEvolutionOperators[] = {Op::Select};

bool high_dynamic_range(const std::vector<double>& y) {
  std::vector<double> a(y.size());
  std::transform(y.begin(), y.end(), a.begin(), [](double v) { return std::abs(v); });
  const auto mid = a.begin() + static_cast<std::ptrdiff_t>(a.size() / 2);
  std::nth_element(a.begin(), mid, a.end());
  const double median = *mid;
  const double largest = *std::max_element(a.begin(), a.end());
  return largest > kHighDynamicRange * median;
}

bool an_input_takes_both_signs(const SearchProblem& p) {
  return std::any_of(p.inputs.begin(), p.inputs.end(), [](const std::vector<double>& c) {
    const auto [lo, hi] = std::minmax_element(c.begin(), c.end());
    return lo != c.end() && *lo < 0 && *hi > 0;
  });
}

}  // namespace

SearchOptions resolve_auto_operators(SearchOptions o, const SearchProblem& p) {
  // Where the search will fold symmetric data, it sees the half x >= 0 (symmetry.hpp): an input
  // that takes both signs only there needs no sign operators.
  std::optional<DataSymmetry> symmetry;
  if (is_auto_operators(o.operators) || is_auto_operators(o.evolution_operators))
    symmetry = search_symmetry(o, p);
  const bool both_signs = an_input_takes_both_signs(symmetry ? symmetric_half(p, *symmetry) : p);
  if (is_auto_operators(o.operators)) {
    o.operators.assign(std::begin(kShadingOperators), std::end(kShadingOperators));
    if (!p.target.empty() && high_dynamic_range(p.target)) o.operators.push_back(Op::Pow);
    if (both_signs)
      o.operators.insert(o.operators.end(), std::begin(kBothSignsOperators),
                         std::end(kBothSignsOperators));
    // The optional groups the data asks for (search/operator_probe.hpp).
    const std::vector<Op> extra = search_detail::probe_operator_groups(
        o, p, o.operators, search_detail::probed_operator_groups());
    o.operators.insert(o.operators.end(), extra.begin(), extra.end());
    // asin ... erf where a reference calls them or the target is one of them of a simple
    // function of the inputs (search/library_operators.hpp).
    for (Op op : search_detail::suggested_library_operators(p))
      if (std::find(o.operators.begin(), o.operators.end(), op) == o.operators.end())
        o.operators.push_back(op);
  }
  if (is_auto_operators(o.evolution_operators)) {
    std::vector<Op> wanted(std::begin(kShadingEvolutionOperators),
                           std::end(kShadingEvolutionOperators));
    if (both_signs)
      wanted.insert(wanted.end(), std::begin(kBothSignsEvolutionOperators),
                    std::end(kBothSignsEvolutionOperators));
    o.evolution_operators.clear();
    for (Op op : wanted)
      if (std::find(o.operators.begin(), o.operators.end(), op) == o.operators.end())
        o.evolution_operators.push_back(op);
  }
  return o;
}

}  // namespace shaderfit
