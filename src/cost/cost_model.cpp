#include "shaderfit/cost/cost_model.hpp"

#include <utility>

#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/cost/per_material.hpp"

namespace shaderfit {

std::optional<InstructionTarget> instruction_target_of(CostTarget target) {
  switch (target) {
    case CostTarget::Nodes: return std::nullopt;
    case CostTarget::Instructions: return InstructionTarget::Sass;
    case CostTarget::Rdna2: return InstructionTarget::Rdna2;
    case CostTarget::Rdna3: return InstructionTarget::Rdna3;
  }
  return std::nullopt;
}

double expression_cost(const Expression& e, CostTarget target) {
  if (const auto t = instruction_target_of(target))
    return static_cast<double>(instruction_count(e, *t));
  return static_cast<double>(e.nodes.size());
}

double expression_cost(const Expression& e, CostTarget target,
                       std::span<const std::string> uniform) {
  if (!reads_uniform(e, uniform)) return expression_cost(e, target);
  return expression_cost(split_per_material(e, uniform).per_pixel, target);
}

namespace {
constexpr std::pair<CostTarget, std::string_view> kCostTargetNames[] = {
    {CostTarget::Instructions, "instructions"},
    {CostTarget::Nodes, "nodes"},
    {CostTarget::Rdna2, "rdna2"},
    {CostTarget::Rdna3, "rdna3"}};
}  // namespace

std::optional<CostTarget> cost_target_from_name(std::string_view name) {
  for (const auto& [t, n] : kCostTargetNames)
    if (n == name) return t;
  return std::nullopt;
}

std::string_view cost_target_name(CostTarget target) {
  for (const auto& [t, n] : kCostTargetNames)
    if (t == target) return n;
  return "instructions";
}

}  // namespace shaderfit
