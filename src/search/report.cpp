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
  return search_summary_lines(*this) + front_table(*this);
}

std::string search_summary_lines(const SearchSummary& summary) {
  std::string s = fmt::format(
      "search: {} after {:.3f} s (enumeration {:.3f} s up to cost {}, {} distinct; evolution "
      "{:.3f} s, "
      "{} generations); {} candidates, {:.3g} node evaluations\n",
      termination_name(summary.termination), summary.total_time_s, summary.enumeration_time_s,
      summary.enumeration_cost_completed, summary.distinct_candidates, summary.evolution_time_s,
      summary.generations, summary.candidates, static_cast<double>(summary.node_evaluations));
  if (summary.symmetry)
    s += "symmetry: the data is " + describe_symmetry(*summary.symmetry) +
         "; searched on the half where it is >= 0, formulas reflected\n";
  return s;
}

std::string front_member_line(const FrontMember& m, Loss loss, const PrintOptions& print) {
  return fmt::format("[{}] {}={:.3g} cost={:g}  {}", when(m.time_s), loss_name(loss), m.loss,
                     m.cost, to_infix(m.expression, print));
}

std::string front_table(const SearchSummary& s, Loss loss, const PrintOptions& print) {
  const bool loss_column = loss != Loss::Mse && loss != Loss::MaxAbs;
  std::string out = fmt::format("{:>6} {:>5}", "cost", "nodes");
  if (loss_column) out += fmt::format(" {:>10}", loss_name(loss));
  out += fmt::format(" {:>10} {:>10} {:>10}  {}\n", "mse", "max_abs", "found", "formula");
  bool unstable = false;
  for (const FrontMember& m : s.front) {
    out += fmt::format("{:>6g} {:>5}", m.cost, m.nodes);
    if (loss_column) out += fmt::format(" {:>10.4g}", m.loss);
    // "!" before the formula: float32 evaluation departs from float64 beyond the bound.
    out += fmt::format(" {:>10.4g} {:>10.4g} {:>10} {}{}\n", m.metrics.mse, m.metrics.max_abs,
                       when(m.time_s), m.float32_stable ? " " : "!", to_infix(m.expression, print));
    unstable = unstable || !m.float32_stable;
  }
  if (unstable)
    out +=
        "! not stable in float32: float32 and float64 differ by more than 1e-4 of the "
        "target's scale and 1% of the formula's max_abs error (docs/reliability.md)\n";
  return out;
}

}  // namespace shaderfit
