#include "gpu/pack.hpp"

#include <algorithm>
#include <string>

#include "shaderfit/core/error.hpp"

namespace shaderfit::gpu_detail {

namespace {

[[noreturn]] void malformed(std::size_t node, const std::string& why) {
  throw Error("GPU program: node " + std::to_string(node) + ": " + why);
}

}  // namespace

void append_program(PackedPrograms& packed, const Expression& e, std::size_t num_columns) {
  if (e.variables.size() != num_columns)
    throw Error("GPU program: the formula has " + std::to_string(e.variables.size()) +
                " variables but the data " + std::to_string(num_columns) + " columns");
  if (e.nodes.empty()) throw Error("GPU program: the formula has no nodes");
  std::vector<GpuNode> code;
  code.reserve(e.nodes.size());
  int depth = 0, max_depth = 0;
  for (std::size_t i = 0; i < e.nodes.size(); ++i) {
    const Node& n = e.nodes[i];
    if (static_cast<int>(n.op) >= kOpCount) malformed(i, "unknown operator");
    const int a = arity(n.op);
    GpuNode g;
    g.op = n.op;
    g.arity = static_cast<std::uint8_t>(a);
    switch (n.op) {
      case Op::Const: g.value = static_cast<float>(n.value); break;
      case Op::Param:
        if (n.index < 0 || static_cast<std::size_t>(n.index) >= e.parameter_values.size())
          malformed(i, "a parameter with no value");
        g.value = static_cast<float>(e.parameter_values[static_cast<std::size_t>(n.index)]);
        break;
      case Op::Var:
        if (n.index < 0 || static_cast<std::size_t>(n.index) >= num_columns)
          malformed(i, "a missing variable");
        g.index = n.index;
        break;
      case Op::IPow:
        if (n.index < kMinIntegerPower || n.index > kMaxIntegerPower)
          malformed(i, "exponent " + std::to_string(n.index) + " outside [-16, 16]");
        g.index = n.index;
        break;
      default: break;
    }
    if (depth < a) malformed(i, "missing operands");
    depth = depth - a + 1;
    max_depth = std::max(max_depth, depth);
    if (max_depth > kMaxStack)
      throw Error("GPU program: the formula needs a stack deeper than " +
                  std::to_string(kMaxStack));
    code.push_back(g);
  }
  if (depth != 1) throw Error("GPU program: the nodes are not one postfix tree");
  packed.nodes.insert(packed.nodes.end(), code.begin(), code.end());
  packed.offsets.push_back(static_cast<std::uint32_t>(packed.nodes.size()));
  packed.max_stack = std::max(packed.max_stack, max_depth);
}

PackedPrograms pack_programs(std::span<const Expression* const> expressions,
                             std::size_t num_columns) {
  PackedPrograms p;
  std::size_t total = 0;
  for (const Expression* e : expressions) total += e != nullptr ? e->size() : 0;
  p.nodes.reserve(total);
  p.offsets.reserve(expressions.size() + 1);
  for (const Expression* e : expressions) {
    if (e == nullptr) throw Error("GPU program: a null formula");
    append_program(p, *e, num_columns);
  }
  return p;
}

PopulationScore to_score(const RowSums& s, Loss loss, double syy) {
  PopulationScore o;
  o.loss = loss_from_sums(loss, s);
  o.finite = s.bad_prediction == 0;
  o.sum_w = s.w;
  o.syy = syy;
  if (s.w > 0) {
    const double md = s.wd / s.w;  // mean of f - shift
    o.mean_f = s.shift + md;
    o.mean_y = s.wy / s.w;
    o.sff = std::max(s.wdd - s.wd * md, 0.0);
    o.sfy = s.wdy - s.wd * o.mean_y;  // sum w (f - mean_f) y = sum w (f - mean_f)(y - mean_y)
  }
  return o;
}

std::vector<RowSums> emulate_population(const PopulationView& view, std::size_t programs) {
  const std::size_t chunks = chunk_count(view.rows);
  std::vector<RowSums> out(programs);
  for (std::size_t e = 0; e < programs; ++e) {
    for (std::size_t c = 0; c < chunks; ++c) {
      RowSums lanes[kWarpLanes];
      for (unsigned l = 0; l < kWarpLanes; ++l)
        lanes[l] = lane_sums(view, static_cast<std::uint32_t>(e), c, l);
      warp_fold(lanes);
      if (c == 0)
        out[e] = lanes[0];
      else
        out[e].merge(lanes[0]);
    }
  }
  return out;
}

NormalSums emulate_normal_sums(const PopulationView& view, int k, bool has_offset) {
  const std::size_t chunks = chunk_count(view.rows);
  NormalSums total;
  total.k = k;
  for (std::size_t c = 0; c < chunks; ++c) {
    NormalSums lanes[kWarpLanes];
    for (unsigned l = 0; l < kWarpLanes; ++l)
      lanes[l] = lane_normal_sums(view, k, has_offset, c, l);
    warp_fold(lanes);
    if (c == 0)
      total = lanes[0];
    else
      total.merge(lanes[0]);
  }
  return total;
}

}  // namespace shaderfit::gpu_detail
