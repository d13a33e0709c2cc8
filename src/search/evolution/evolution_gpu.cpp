// The evolution's GPU path: a batch of children scored on the fit rows in one launch
// (docs/gpu.md). It computes what Evolution::evaluate does, with the formula in float32 and the
// sums in float64 on the device: the loss of the formula, its optimal linear scaling from the
// returned sums, then (second launch) the exact loss of the scaled formulas.
#include <cmath>

#include "search/evolution/evolution.hpp"

namespace shaderfit::search_detail {

void Evolution::evaluate_on_gpu(std::vector<Individual>& batch, Island& island) const {
  if (batch.empty()) return;
  const Loss loss = ctx_.options.loss;
  std::vector<const Expression*> population;
  std::size_t nodes = 0;
  for (Individual& ind : batch) {
    ++island.evaluated;
    fit_constants(ind);  // on the CPU: Levenberg-Marquardt steps, few per child
    population.push_back(&ind.expr);
    nodes += ind.expr.size();
  }
  const std::vector<PopulationScore> raw = gpu_->evaluate_population(population, loss);
  ctx_.node_evaluations.fetch_add(nodes * fit_.size(), std::memory_order_relaxed);

  std::vector<std::size_t> to_scale;
  std::vector<const Expression*> scaled_population;
  std::vector<LinearScaling> scalings;
  for (std::size_t i = 0; i < batch.size(); ++i) {
    Individual& ind = batch[i];
    ind.raw_loss = ind.loss = raw[i].loss;
    ind.raw_cost = ind.cost = formula_cost(ind.expr, ctx_.options);
    ind.hash = structural_hash(ind.expr);
    ind.scaled = false;
    if (!ctx_.options.linear_scaling || !std::isfinite(ind.loss)) continue;
    const LinearScaling ls = raw[i].linear_scaling();
    if (!std::isfinite(ls.mse) || ls.a == 0.0) continue;
    to_scale.push_back(i);
    scaled_population.push_back(&ind.expr);
    scalings.push_back(ls);
  }
  if (to_scale.empty()) return;
  const std::vector<PopulationScore> scaled =
      gpu_->evaluate_population(scaled_population, loss, scalings);
  for (std::size_t j = 0; j < to_scale.size(); ++j) {
    Individual& ind = batch[to_scale[j]];
    if (!(scaled[j].loss < ind.loss)) continue;
    ind.loss = scaled[j].loss;
    ind.cost += scaling_cost_;
    ind.scaled = true;
    ind.a = scalings[j].a;
    ind.b = scalings[j].b;
  }
}

}  // namespace shaderfit::search_detail
