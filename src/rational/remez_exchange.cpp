#include <algorithm>
#include <cmath>

#include "rational/remez.hpp"

namespace shaderfit::rational_detail {

using namespace shaderfit::rational;  // the area's public names

std::vector<Extremum> choose_reference(const std::vector<Extremum>& c, std::size_t count) {
  std::vector<Extremum> merged;
  for (const Extremum& x : c) {
    if (x.e == 0.0) continue;
    if (!merged.empty() && (merged.back().e > 0) == (x.e > 0)) {
      if (std::abs(x.e) > std::abs(merged.back().e)) merged.back() = x;
    } else {
      merged.push_back(x);
    }
  }
  if (merged.size() < count) return {};
  while (merged.size() > count) {
    if (merged.size() - count == 1) {
      // One too many: only an end can go without breaking the alternation.
      if (std::abs(merged.front().e) < std::abs(merged.back().e))
        merged.erase(merged.begin());
      else
        merged.pop_back();
      continue;
    }
    std::size_t i = 0;
    for (std::size_t k = 1; k < merged.size(); ++k)
      if (std::abs(merged[k].e) < std::abs(merged[i].e)) i = k;
    if (i == 0 || i + 1 == merged.size()) {
      merged.erase(merged.begin() + static_cast<std::ptrdiff_t>(i));
    } else {
      // Drop i with its smaller neighbour: the two remaining around them still alternate.
      const std::size_t j = std::abs(merged[i - 1].e) < std::abs(merged[i + 1].e) ? i - 1 : i;
      merged.erase(merged.begin() + static_cast<std::ptrdiff_t>(j),
                   merged.begin() + static_cast<std::ptrdiff_t>(j + 2));
    }
  }
  return merged;
}

}  // namespace shaderfit::rational_detail
