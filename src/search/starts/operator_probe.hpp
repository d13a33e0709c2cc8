// Which optional operators the data asks for (internal; docs/search.md, "Operators"): `auto`
// adds a group of operators (sin and cos, ...) when a small enumeration that may use them finds
// formulas much better than the same enumeration without them.
//
//   std::vector<Op> extra = probe_operator_groups(options, problem, kProbedGroups);
#pragma once

#include <span>
#include <string_view>
#include <vector>

#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

struct OperatorGroup {
  std::string_view name;  // for messages: "trigonometric"
  std::vector<Op> ops;
  // A direct test of the data that suggests the group without the enumerations (or nullptr).
  bool (*signal)(const SearchProblem&) = nullptr;
};

// The groups `auto` probes for, in order.
std::span<const OperatorGroup> probed_operator_groups();

// A group is suggested when its signal holds on the problem, or when, among the rows (at most
// kProbeRows, evenly spread), an enumeration with `base` and the group's operators finds a formula
// that uses one of them and whose loss is at most kProbeGain times the best loss that the
// enumeration with `base` alone reaches at the same cost or less. Both enumerations have the same
// budget in candidates (deterministic: no clock), one thread, no evolution, `options`' loss, cost
// model, powers and literals. Returns the suggested groups' operators that `base` lacks, in group
// order.
inline constexpr std::size_t kProbeRows = 256;
inline constexpr double kProbeGain = 0.1;
std::vector<Op> probe_operator_groups(const SearchOptions& options, const SearchProblem& problem,
                                      const std::vector<Op>& base,
                                      std::span<const OperatorGroup> groups);

}  // namespace shaderfit::search_detail
