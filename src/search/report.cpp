#include "shaderfit/search/report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>

namespace shaderfit {

namespace {

std::string when(double s) {
  return s < 10 ? fmt::format("{:.1f} ms", s * 1e3) : fmt::format("{:.2f} s", s);
}

}  // namespace

std::string SearchSummary::brief_report() const {
  std::string s = fmt::format(
      "search: {} after {:.3f} s (enumeration {:.3f} s up to cost {}, {} distinct; evolution "
      "{:.3f} s, "
      "{} generations); {} candidates, {:.3g} node evaluations\n",
      termination_name(termination), total_time_s, enumeration_time_s, enumeration_cost_completed,
      distinct_candidates, evolution_time_s, generations, candidates,
      static_cast<double>(node_evaluations));
  if (symmetry)
    s += "symmetry: the data is " + describe_symmetry(*symmetry) +
         "; searched on the half where it is >= 0, formulas reflected\n";
  return s + front_table(*this);
}

std::string front_member_line(const FrontMember& m, Loss loss) {
  return fmt::format("[{}] {}={:.3g} cost={:g}  {}", when(m.time_s), loss_name(loss), m.loss,
                     m.cost, m.formula);
}

std::string front_table(const SearchSummary& s, Loss loss) {
  std::string out = fmt::format("{:>6} {:>5} {:>10} {:>10} {:>10} {:>10}  {}\n", "cost", "nodes",
                                loss == Loss::Mse ? "mse" : std::string(loss_name(loss)), "mse",
                                "max_abs", "found", "formula");
  bool unstable = false;
  for (const FrontMember& m : s.front) {
    // "!" before the formula: float32 evaluation departs from float64 beyond the bound.
    out += fmt::format("{:>6g} {:>5} {:>10.4g} {:>10.4g} {:>10.4g} {:>10} {}{}\n", m.cost, m.nodes,
                       m.loss, m.metrics.mse, m.metrics.max_abs, when(m.time_s),
                       m.float32_stable ? " " : "!", m.formula);
    unstable = unstable || !m.float32_stable;
  }
  if (unstable)
    out +=
        "! not stable in float32: float32 and float64 differ by more than 1e-4 of the "
        "target's scale and 1% of the formula's max_abs error (docs/reliability.md)\n";
  return out;
}

}  // namespace shaderfit
