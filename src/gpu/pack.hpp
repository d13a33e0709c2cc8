// Internal: packing expressions into the flat program arrays the GPU kernels read
// (gpu/device_program.hpp), and the kernels' CPU emulation, which the tests compare with the CPU
// evaluator (always) and with the GPU (where there is one).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "gpu/normal_sums.hpp"
#include "gpu/population_sums.hpp"
#include "gpu/device_program.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/gpu/evaluator.hpp"

namespace shaderfit::gpu_detail {

struct PackedPrograms {
  std::vector<GpuNode> nodes;
  std::vector<std::uint32_t> offsets = {0};  // program p is nodes[offsets[p], offsets[p + 1])
  int max_stack = 0;                         // deepest postfix stack of any program

  [[nodiscard]] std::size_t size() const { return offsets.size() - 1; }
};

// Appends e as one program, its parameters replaced by their values (as float32). Throws
// shaderfit::Error when e is malformed (not one postfix tree, an unknown op, an index out of
// range, an exponent outside [-16, 16]), has a variable count other than num_columns, or needs a
// stack deeper than kMaxStack.
void append_program(PackedPrograms& packed, const Expression& e, std::size_t num_columns);

PackedPrograms pack_programs(std::span<const Expression* const> expressions,
                             std::size_t num_columns);

// The population kernel on the CPU: the same lanes, chunks and fold order. view.nodes etc. are
// host pointers.
std::vector<RowSums> emulate_population(const PopulationView& view, std::size_t programs);

// What GpuEvaluator returns for a program's sums (syy: the data's, see PopulationScore).
PopulationScore to_score(const RowSums& sums, Loss loss, double syy);

// The normal-equation kernel on the CPU.
NormalSums emulate_normal_sums(const PopulationView& view, int k, bool has_offset);

}  // namespace shaderfit::gpu_detail
