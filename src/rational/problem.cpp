// Validation of problems and options, and small accessors.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/rational/solve.hpp"

namespace shaderfit::rational {

void RationalProblem::validate() const {
  if (parameter_names.size() != parameter_values.size())
    throw Error(fmt::format("{} parameter names but {} values", parameter_names.size(),
                            parameter_values.size()));
  for (std::size_t i = 0; i < parameter_names.size(); ++i)
    if (!std::isfinite(parameter_values[i]))
      throw Error("parameter " + parameter_names[i] + " is not a finite number",
                  {"RationalProblem::parameter_values"});
  (void)target_parameter_values();
  if (!std::isfinite(domain.lo) || !std::isfinite(domain.hi) || !(domain.lo < domain.hi))
    throw Error(fmt::format("the domain [{}, {}] is empty or not finite", domain.lo, domain.hi),
                {"RationalProblem::domain"});
  const std::string dom = "[" + format_number(domain.lo) + ", " + format_number(domain.hi) + "]";
  for (const Condition& c : conditions) {
    if (c.order < 0 || c.order > kMaxDerivativeOrder)
      throw Error(fmt::format("condition '{}': derivative order {} outside [0, {}]", c.text,
                              c.order, kMaxDerivativeOrder),
                  c.point_location());
    if (!domain.contains(c.a))
      throw Error(fmt::format("condition '{}': the point {} is outside the domain {}", c.text,
                              format_number(c.a), dom),
                  c.point_location());
    if (c.is_integral() && !domain.contains(c.b))
      throw Error(fmt::format("condition '{}': the bound {} is outside the domain {}", c.text,
                              format_number(c.b), dom),
                  c.point_location());
    if (!c.from_reference) {
      for (const Node& n : c.value.nodes)
        if (n.op == Op::Param && static_cast<std::size_t>(n.index) >= parameter_values.size())
          throw Error("condition '" + c.text + "' uses a parameter with no value", c.where);
    }
  }
}

std::vector<double> RationalProblem::target_parameter_values() const {
  std::vector<double> out;
  for (const std::string& name : target.parameters()) {
    auto it = std::find(parameter_names.begin(), parameter_names.end(), name);
    if (it == parameter_names.end())
      throw Error(fmt::format("target {} needs a value for its parameter {} "
                              "(RationalProblem::parameter_names {}=...)",
                              target.name(), name, name),
                  {"RationalProblem::parameter_values"});
    out.push_back(parameter_values[static_cast<std::size_t>(it - parameter_names.begin())]);
  }
  return out;
}

bool MinimaxOptions::is_valid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (max_iterations < 1) return fail("minimax.max_iterations must be at least 1");
  if (!(tolerance > 0 && tolerance < 1)) return fail("minimax.tolerance must be in (0, 1)");
  if (grid != 0 && grid < 16) return fail("minimax.grid must be 0 (automatic) or at least 16");
  return true;
}

bool RationalOptions::is_valid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (rank_by != Loss::Rmse && rank_by != Loss::MaxAbs && rank_by != Loss::MaxRel)
    return fail("rank_by must be rmse, max_abs or max_rel");
  if (coefficient_count < 0) return fail("coefficient_count must be 0 or more");
  if (coefficient_count > 2 * kMaxIntegerPower + 1) return fail("coefficient_count is above 33");
  if (samples < 16) return fail("samples must be at least 16");
  if (!(ill_conditioned > 1)) return fail("ill_conditioned must be above 1");
  for (const Transform& t : transforms)
    if (!(t.scale != 0) || !std::isfinite(t.scale) || !std::isfinite(t.offset))
      return fail("a transform needs a finite nonzero scale");
  return minimax.is_valid(why);
}

const char* form_status_name(FormStatus s) {
  switch (s) {
    case FormStatus::Ok: return "ok";
    case FormStatus::IllConditioned: return "ill-conditioned";
    case FormStatus::Singular: return "singular";
    case FormStatus::PoleInDomain: return "pole";
    case FormStatus::NotConverged: return "not converged";
    case FormStatus::Failed: return "failed";
  }
  return "?";
}

double FormResult::error(Loss by) const {
  switch (by) {
    case Loss::Rmse: return rmse;
    case Loss::MaxAbs: return max_abs;
    case Loss::MaxRel: return max_rel;
    case Loss::Mse:
    case Loss::Relative:
    case Loss::Log:
    case Loss::Display: break;
  }
  throw Error("forms are ranked by rmse, max_abs or max_rel, not " + std::string(loss_name(by)),
              {"RationalOptions::rank_by"});
}

}  // namespace shaderfit::rational
