// Internal: random populations of formulas for the GPU tests and bench/gpu_bench.cpp.
#pragma once

#include <cstddef>
#include <iterator>
#include <span>
#include <string>
#include <vector>

#include "gpu/pack.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit::gpu_test {

// Operators of the generated formulas: all of them but copysign, or only those whose float32
// value the CPU and the GPU compute alike (+ - * / min max neg abs saturate ipow fma sqrt rcp
// rsqrt). copysign reads the sign bit of a NaN operand, which the SIMD functions, libm and CUDA
// set differently (asin and acos of |x| > 1 make NaNs often); its exact value is checked apart.
enum class OpSet { All, Exact };

namespace detail {

// Appends a formula of exactly `budget` nodes.
inline void grow(Rng& rng, Expression& e, int budget, OpSet set, bool with_param) {
  if (budget <= 1) {
    const double u = uniform01(rng);
    if (u < 0.6)
      e.nodes.push_back(Node::variable(static_cast<int>(uniform_index(rng, e.variables.size()))));
    else if (with_param && u < 0.7)
      e.nodes.push_back(Node::parameter(static_cast<int>(uniform_index(rng, e.parameters.size()))));
    else
      e.nodes.push_back(Node::constant(uniform(rng, -3.0, 3.0)));
    return;
  }
  static constexpr Op kExact[] = {Op::Add, Op::Sub,  Op::Mul,  Op::Div,  Op::Min,
                                  Op::Max, Op::Neg,  Op::IPow, Op::Abs,  Op::Saturate,
                                  Op::Fma, Op::Sqrt, Op::Rcp,  Op::Rsqrt};
  Op op = Op::Add;
  do {
    op = set == OpSet::Exact ? kExact[uniform_index(rng, std::size(kExact))]
                             : static_cast<Op>(3 + uniform_index(rng, kOpCount - 3));
  } while (arity(op) + 1 > budget || op == Op::CopySign);
  const int rest = budget - 1;  // nodes below this one
  if (arity(op) == 1) {
    grow(rng, e, rest, set, with_param);
  } else if (arity(op) == 2) {
    const int left = 1 + static_cast<int>(uniform_index(rng, static_cast<std::uint64_t>(rest - 1)));
    grow(rng, e, left, set, with_param);
    grow(rng, e, rest - left, set, with_param);
  } else {
    const int first =
        1 + static_cast<int>(uniform_index(rng, static_cast<std::uint64_t>(rest - 2)));
    const int second =
        1 + static_cast<int>(uniform_index(rng, static_cast<std::uint64_t>(rest - first - 1)));
    grow(rng, e, first, set, with_param);
    grow(rng, e, second, set, with_param);
    grow(rng, e, rest - first - second, set, with_param);
  }
  if (op == Op::IPow) {
    const int k = 2 + static_cast<int>(uniform_index(rng, 4));
    e.nodes.push_back(Node::ipow(bernoulli(rng, 0.2) ? -k : k));
  } else {
    e.nodes.push_back(Node::op_node(op));
  }
}

}  // namespace detail

// A formula over `variables` with between min_nodes and max_nodes nodes (min_nodes >= 1).
inline Expression random_formula_of_size(Rng& rng, const std::vector<std::string>& variables,
                                         std::size_t min_nodes, std::size_t max_nodes, OpSet set,
                                         bool with_param = false) {
  Expression e;
  e.variables = variables;
  if (with_param) {
    e.parameters = {"p0", "p1"};
    e.parameter_values = {uniform(rng, -2.0, 2.0), uniform(rng, -2.0, 2.0)};
  }
  const int budget = static_cast<int>(min_nodes + uniform_index(rng, max_nodes - min_nodes + 1));
  detail::grow(rng, e, budget, set, with_param);
  e.update_lengths();
  return e;
}

inline std::vector<Expression> random_population(Rng& rng, std::size_t count,
                                                 const std::vector<std::string>& variables,
                                                 std::size_t min_nodes, std::size_t max_nodes,
                                                 OpSet set, bool with_param = false) {
  std::vector<Expression> p;
  p.reserve(count);
  for (std::size_t i = 0; i < count; ++i)
    p.push_back(random_formula_of_size(rng, variables, min_nodes, max_nodes, set, with_param));
  return p;
}

inline std::vector<const Expression*> pointers_to(const std::vector<Expression>& population) {
  std::vector<const Expression*> p;
  p.reserve(population.size());
  for (const Expression& e : population) p.push_back(&e);
  return p;
}

// Input columns with values in [lo, hi] (rows each), and their pointers.
struct RandomColumns {
  std::vector<std::vector<double>> values;
  std::vector<const double*> pointers;
  RandomColumns(Rng& rng, std::size_t columns, std::size_t rows, double lo, double hi) {
    values.assign(columns, std::vector<double>(rows));
    for (auto& c : values)
      for (double& v : c) v = uniform(rng, lo, hi);
    pointers.reserve(columns);
    for (const auto& c : values) pointers.push_back(c.data());
  }
};

// A population and its data laid out as the kernels read them, on the host: what the CPU
// emulation of the kernels runs on.
struct HostPopulation {
  gpu_detail::PackedPrograms programs;
  std::vector<float> columns;  // float32, variable v of row r at v * rows + r
  std::vector<double> y, w;
  std::vector<gpu_detail::Affine> affine;
  std::size_t rows = 0;

  HostPopulation(std::span<const Expression* const> population,
                 std::span<const double* const> inputs, std::span<const double> target,
                 std::span<const double> weights = {})
      : programs(gpu_detail::pack_programs(population, inputs.size())),
        y(target.begin(), target.end()),
        w(weights.begin(), weights.end()),
        rows(target.size()) {
    for (const double* c : inputs)
      for (std::size_t r = 0; r < rows; ++r) columns.push_back(static_cast<float>(c[r]));
  }

  [[nodiscard]] gpu_detail::PopulationView view(Loss loss) const {
    gpu_detail::PopulationView v;
    v.nodes = programs.nodes.data();
    v.offsets = programs.offsets.data();
    v.affine = affine.empty() ? nullptr : affine.data();
    v.columns = columns.data();
    v.y = y.data();
    v.w = w.empty() ? nullptr : w.data();
    v.rows = rows;
    v.loss = loss;
    return v;
  }
};

}  // namespace shaderfit::gpu_test
