// The Pareto front of (loss, cost), shared by the search strategies (internal).
#pragma once

#include <functional>
#include <mutex>
#include <vector>

#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

// Thread-safe. A member enters when its cost and loss are finite and no member has cost <= its
// cost and loss <= its loss; it evicts the members it dominates. Kept sorted by cost, so losses
// strictly decrease along it.
class ParetoFront {
 public:
  // Called under the front's lock for each member that enters, so calls never overlap.
  explicit ParetoFront(std::function<void(const FrontMember&)> on_enter = {})
      : on_enter_(std::move(on_enter)) {}

  // Whether a member with this cost and loss would enter (the front may change before offer).
  [[nodiscard]] bool would_enter(double cost, double loss) const;
  // The lowest loss among members of cost <= `cost`; +infinity when there is none.
  [[nodiscard]] double best_loss_at(double cost) const;
  // Inserts when not dominated; returns whether it entered.
  bool offer(FrontMember member);
  // Becomes `members` (a front, cheapest first), without calling on_enter: how the ranks of a
  // distributed search take rank 0's front.
  void assign(std::vector<FrontMember> members);

  [[nodiscard]] std::vector<FrontMember> members() const;
  [[nodiscard]] std::size_t size() const;

 private:
  [[nodiscard]] bool dominated_locked(double cost, double loss) const;

  mutable std::mutex mutex_;
  std::vector<FrontMember> members_;
  std::function<void(const FrontMember&)> on_enter_;
};

}  // namespace shaderfit::search_detail
