#include "shaderfit/search/front/front_table.hpp"

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
  if (summary.check_time_s > 0) {
    s += fmt::format(
        "checked: each member's max error searched for between the samples as well ({:.3g} s)",
        summary.check_time_s);
    if (summary.dropped_not_finite > 0)
      s += fmt::format("; {} member{} NaN or infinite between them dropped",
                       summary.dropped_not_finite, summary.dropped_not_finite == 1 ? "" : "s");
    s += "\n";
  }
  if (summary.symmetry)
    s += "symmetry: the data is " + describe_symmetry(*summary.symmetry) + " (" +
         describe_symmetry_evidence(*summary.symmetry) +
         "); searched on the half where it is >= 0, formulas reflected\n";
  return s;
}

std::string front_member_line(const FrontMember& m, Loss loss, const PrintOptions& print) {
  return fmt::format("[{}] {}={:.3g} cost={:g}  {}", when(m.time_s), loss_name(loss), m.loss,
                     m.cost, to_infix(m.expression, print));
}

std::string front_table(const SearchSummary& s, Loss loss, const PrintOptions& print) {
  // The display loss is the mse column (weighted by the display).
  const bool loss_column = loss != Loss::Mse && loss != Loss::MaxAbs && loss != Loss::Display;
  bool certified = false;
  for (const FrontMember& m : s.front) certified = certified || m.certified_max_abs.has_value();
  std::string out = fmt::format("{:>6} {:>5}", "cost", "nodes");
  if (loss_column) out += fmt::format(" {:>10}", loss_name(loss));
  out +=
      fmt::format(" {:>10} {:>10} {:>11} {:>11}", "mse", "max_abs", "f32 max_abs", "f16 max_abs");
  if (certified) out += fmt::format(" {:>11}", "certified");
  out += fmt::format(" {:>10}  {}\n", "found", "formula");
  bool unstable = false, loose = false;
  std::size_t minor = 0;
  for (const FrontMember& m : s.front) {
    if (m.minor_step) {
      ++minor;
      continue;
    }
    out += fmt::format("{:>6g} {:>5}", m.cost, m.nodes);
    if (loss_column) out += fmt::format(" {:>10.4g}", m.loss);
    out += fmt::format(" {:>10.4g} {:>10.4g} {:>11.4g} {:>11.4g}", m.metrics.mse, m.metrics.max_abs,
                       m.float32_max_abs, m.half_max_abs);
    if (certified) {
      // "*": the budget ended first; the bound holds but is looser than the tolerance.
      const bool done =
          !m.certified_max_abs || m.certified_converged || std::isinf(*m.certified_max_abs);
      out += m.certified_max_abs
                 ? fmt::format(" {:>10.4g}{}", *m.certified_max_abs, done ? " " : "*")
                 : fmt::format(" {:>11}", "-");
      loose = loose || !done;
    }
    // "!" before the formula: float32 evaluation departs from float64 beyond the bound.
    out += fmt::format(" {:>10} {}{}\n", when(m.time_s), m.float32_stable ? " " : "!",
                       to_infix(m.expression, print));
    unstable = unstable || !m.float32_stable;
  }
  if (unstable)
    out +=
        "! not stable in float32: float32 and float64 differ by more than 1e-4 of the "
        "target's scale and 1% of the formula's max_abs error (docs/reliability.md)\n";
  if (loose) out += "* the time for the bound ran out: it holds, but may be well above max_abs\n";
  if (minor > 0)
    out += fmt::format(
        "{} {} not shown: each lowers the loss of the member above it by less than the minimum "
        "step (the JSON keeps them, \"minor_step\": true)\n",
        minor, minor == 1 ? "costlier member" : "costlier members");
  return out;
}

}  // namespace shaderfit
