#include "shaderfit/cost/cost_model.hpp"

#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/cost/per_material.hpp"

namespace shaderfit {

double expression_cost(const Expression& e, CostTarget target) {
  switch (target) {
    case CostTarget::Nodes: return static_cast<double>(e.nodes.size());
    case CostTarget::Instructions:
      return static_cast<double>(instruction_count(e, InstructionTarget::Sass));
  }
  return 0.0;
}

double expression_cost(const Expression& e, CostTarget target,
                       std::span<const std::string> uniform) {
  if (!reads_uniform(e, uniform)) return expression_cost(e, target);
  return expression_cost(split_per_material(e, uniform).per_pixel, target);
}

std::optional<CostTarget> cost_target_from_name(std::string_view name) {
  if (name == "nodes") return CostTarget::Nodes;
  if (name == "instructions") return CostTarget::Instructions;
  return std::nullopt;
}

std::string_view cost_target_name(CostTarget target) {
  return target == CostTarget::Nodes ? "nodes" : "instructions";
}

}  // namespace shaderfit
