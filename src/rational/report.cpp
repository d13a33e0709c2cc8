// Text reports of a RationalSummary.
#include <fmt/format.h>

#include <algorithm>

#include "shaderfit/rational/solve.hpp"

namespace shaderfit::rational {

namespace {

const char* metric_name(Loss by) {
  switch (by) {
    case Loss::Rmse: return "RMSE";
    case Loss::MaxAbs: return "max abs";
    case Loss::MaxRel: return "max rel";
    default: return "?";  // not a ranking (RationalOptions::is_valid)
  }
}

}  // namespace

std::string RationalSummary::brief_report(const PrintOptions& print) const {
  std::size_t usable = 0;
  for (const FormResult& r : results) usable += r.usable();
  if (usable == 0) return fmt::format("{} forms, none usable", results.size());
  const FormResult& best = results.front();
  return fmt::format("{} forms, {} usable; best by {}: {} = {} ({} {:.3g}, cost {})",
                     results.size(), usable, metric_name(rank_by), best.form.name(variable),
                     to_infix(best.expression, print), metric_name(rank_by), best.error(rank_by),
                     best.cost);
}

std::string RationalSummary::full_report(const PrintOptions& print) const {
  std::string out =
      fmt::format("{:>4}  {:<16} {:<15} {:>9} {:>10} {:>10} {:>10} {:>5}  {}\n", "rank", "form",
                  "status", "cond", "RMSE", "max abs", "max rel", "cost", "formula");
  int rank = 0;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const FormResult& r = results[i];
    const bool front = std::find(pareto.begin(), pareto.end(), i) != pareto.end();
    const std::string cond =
        r.condition_number > 0 ? fmt::format("{:.2e}", r.condition_number) : "-";
    if (r.usable()) {
      out +=
          fmt::format("{:>4}{} {:<16} {:<15} {:>9} {:>10.3e} {:>10.3e} {:>10.3e} {:>5}  {}\n",
                      ++rank, front ? '*' : ' ', r.form.name(variable), form_status_name(r.status),
                      cond, r.rmse, r.max_abs, r.max_rel, r.cost, to_infix(r.expression, print));
    } else {
      out += fmt::format("{:>4}  {:<16} {:<15} {:>9} {}\n", "-", r.form.name(variable),
                         form_status_name(r.status), cond, r.message);
    }
    if (r.minimax) {
      const Equioscillation& e = *r.minimax;
      out += fmt::format(
          "        minimax{}: levelled error {:.4e}, max error {:.4e}, {} alternation points, "
          "spread {:.2e}, {} exchanges{}\n",
          e.relative ? " (relative)" : "", e.levelled_error, e.max_error, e.points.size(), e.spread,
          e.iterations, e.converged ? "" : " (not converged)");
      std::string pts;
      for (std::size_t k = 0; k < e.points.size(); ++k)
        pts += fmt::format("{}{:.6g} ({:+.3e})", k ? ", " : "", e.points[k], e.errors[k]);
      out += "        alternation: " + pts + "\n";
    }
  }
  if (!pareto.empty()) {
    out += fmt::format("* error-cost Pareto front ({} against instruction cost):",
                       metric_name(rank_by));
    for (std::size_t i : pareto)
      out += fmt::format(" {} (cost {}, {:.3g});", results[i].form.name(variable), results[i].cost,
                         results[i].error(rank_by));
    out.back() = '\n';
  }
  return out;
}

}  // namespace shaderfit::rational
