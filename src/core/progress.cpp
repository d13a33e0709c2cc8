#include "shaderfit/core/progress.hpp"

namespace shaderfit {

void ProgressCounter::add(std::size_t units) {
  const std::size_t done = done_.fetch_add(units, std::memory_order_relaxed) + units;
  if (!callback_) return;
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  callback_(Progress{done < total_ ? done : total_, total_, unit_});
}

}  // namespace shaderfit
