// NSGA-II selection on two objectives, loss and cost, both minimised (internal).
#pragma once

#include <cstddef>
#include <vector>

namespace shaderfit::search_detail {

struct Objectives {
  double loss = 0;
  double cost = 0;
};

// Pareto rank (0 = non-dominated) and crowding distance of each point.
void rank_and_crowding(const std::vector<Objectives>& points, std::vector<int>* rank,
                       std::vector<double>* crowding);

// Indices of the `count` points NSGA-II keeps: whole fronts by rank, the last one cut by
// decreasing crowding distance (ties by index, so the choice is deterministic).
std::vector<std::size_t> nsga2_select(const std::vector<Objectives>& points, std::size_t count);

}  // namespace shaderfit::search_detail
