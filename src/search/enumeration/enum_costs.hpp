// The enumeration's additive costs, derived from the cost model (internal).
//
// The cost of an enumerated candidate is the sum of its operands' costs plus an increment for
// its operator. Each increment is read off the cost model on the smallest formula that uses the
// operator (cost(a op b) - cost(a) - cost(b)), so the enumeration follows the cost model when it
// changes. With sharing and fusion the model's count of a whole formula can be lower than this
// sum, never higher (for the Instructions model): the level is an upper bound, and the front
// records the model's count of the formula itself.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "search/enumeration/enumerator.hpp"

namespace shaderfit::search_detail {

struct LiteralGroup {
  EKind kind = EKind::AddSub;
  int increment = 0;               // literal cost + operator increment
  std::vector<std::uint32_t> ids;  // literal classes
  Enumerator::Variant variants[2];
  int variant_count = 1;
};

struct Enumerator::Costs {
  int leaf = 0;                             // an input variable
  int literal = 0;                          // a literal constant
  std::array<int, kOpCount> unary{};        // -1: not enumerated
  std::vector<std::pair<int, int>> powers;  // (k, increment)
  // By Op::Add (for AddSub), Mul, Div, Min, Max, Pow, CopySign; -1: off.
  std::array<int, kOpCount> binary{};
  int fused = -1;  // m +- b over cost(m) + cost(b); -1: fusion saves nothing
  std::vector<LiteralGroup> literal_groups;  // filled once the literal classes exist

  Costs(const SearchOptions& options);
  // Increment for `op` with a literal operand (on the left when `left`).
  [[nodiscard]] static int literal_increment(const SearchOptions& options, Op op, double literal,
                                             bool left);
  [[nodiscard]] bool eager_fusion() const {
    return fused >= 0 && leaf + fused == 0 && literal + fused == 0;
  }
};

// Which unary operators give different classes for a and -a (neither odd nor even).
bool sign_sensitive(Op op);

}  // namespace shaderfit::search_detail
