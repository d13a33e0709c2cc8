#include "search/pareto.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shaderfit::search_detail {

bool ParetoFront::dominated_locked(double cost, double loss) const {
  if (!std::isfinite(loss) || !std::isfinite(cost)) return true;  // NaN or inf never enters
  for (const FrontMember& m : members_) {
    if (m.cost > cost) break;
    if (m.loss <= loss) return true;
  }
  return false;
}

bool ParetoFront::would_enter(double cost, double loss) const {
  std::lock_guard lock(mutex_);
  return !dominated_locked(cost, loss);
}

double ParetoFront::best_loss_at(double cost) const {
  std::lock_guard lock(mutex_);
  double best = std::numeric_limits<double>::infinity();
  for (const FrontMember& m : members_) {
    if (m.cost > cost) break;
    best = std::min(best, m.loss);
  }
  return best;
}

void ParetoFront::assign(std::vector<FrontMember> members) {
  std::lock_guard lock(mutex_);
  members_ = std::move(members);
}

bool ParetoFront::offer(FrontMember member) {
  std::lock_guard lock(mutex_);
  if (dominated_locked(member.cost, member.loss)) return false;
  std::erase_if(members_, [&](const FrontMember& m) {
    return m.cost >= member.cost && m.loss >= member.loss;
  });
  auto at = std::upper_bound(members_.begin(), members_.end(), member.cost,
                             [](double c, const FrontMember& m) { return c < m.cost; });
  at = members_.insert(at, std::move(member));
  if (on_enter_) on_enter_(*at);
  return true;
}

std::vector<FrontMember> ParetoFront::members() const {
  std::lock_guard lock(mutex_);
  return members_;
}

std::size_t ParetoFront::size() const {
  std::lock_guard lock(mutex_);
  return members_.size();
}

}  // namespace shaderfit::search_detail
