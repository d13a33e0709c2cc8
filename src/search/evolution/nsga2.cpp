#include "search/evolution/nsga2.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace shaderfit::search_detail {

namespace {

bool dominates(const Objectives& a, const Objectives& b) {
  return a.loss <= b.loss && a.cost <= b.cost && (a.loss < b.loss || a.cost < b.cost);
}

}  // namespace

void rank_and_crowding(const std::vector<Objectives>& p, std::vector<int>* rank_out,
                       std::vector<double>* crowd_out) {
  const std::size_t n = p.size();
  std::vector<int>& rank = *rank_out;
  std::vector<double>& crowd = *crowd_out;
  rank.assign(n, -1);
  crowd.assign(n, 0.0);
  // Fast non-dominated sort: who each point dominates, and by how many it is dominated.
  std::vector<std::vector<std::size_t>> dominated(n);
  std::vector<int> count(n, 0);
  std::vector<std::size_t> front;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      if (dominates(p[i], p[j]))
        dominated[i].push_back(j);
      else if (dominates(p[j], p[i]))
        ++count[i];
    }
    if (count[i] == 0) front.push_back(i);
  }
  for (int r = 0; !front.empty(); ++r) {
    for (std::size_t i : front) rank[i] = r;
    // Crowding within this front, on both objectives normalised by their range.
    for (int obj = 0; obj < 2; ++obj) {
      auto key = [&](std::size_t i) { return obj == 0 ? p[i].loss : p[i].cost; };
      std::vector<std::size_t> f = front;
      std::sort(f.begin(), f.end(), [&](std::size_t a, std::size_t b) {
        return key(a) < key(b) || (key(a) == key(b) && a < b);
      });
      const double range = key(f.back()) - key(f.front());
      crowd[f.front()] = crowd[f.back()] = std::numeric_limits<double>::infinity();
      if (!(range > 0)) continue;
      for (std::size_t k = 1; k + 1 < f.size(); ++k)
        crowd[f[k]] += (key(f[k + 1]) - key(f[k - 1])) / range;
    }
    std::vector<std::size_t> next;
    for (std::size_t i : front)
      for (std::size_t j : dominated[i])
        if (--count[j] == 0) next.push_back(j);
    std::sort(next.begin(), next.end());
    front = std::move(next);
  }
}

std::vector<std::size_t> nsga2_select(const std::vector<Objectives>& points, std::size_t count) {
  std::vector<int> rank;
  std::vector<double> crowd;
  rank_and_crowding(points, &rank, &crowd);
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (rank[a] != rank[b]) return rank[a] < rank[b];
    if (crowd[a] != crowd[b]) return crowd[a] > crowd[b];
    return a < b;
  });
  order.resize(std::min(count, order.size()));
  return order;
}

}  // namespace shaderfit::search_detail
