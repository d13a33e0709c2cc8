#include "shaderfit/eval/evaluate_in.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/expr/forward.hpp"
#include "shaderfit/expr/op.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit {

namespace {

// expr/forward.hpp's number policy for half: values are doubles that hold binary16 values, and
// each operator's result is rounded to binary16 where the generated half code rounds.
struct HalfNumbers {
  using value_type = double;
  std::span<const double> variables;
  std::span<const double> parameters;

  [[nodiscard]] double leaf(const Node& n, std::size_t /*depth*/) const {
    const auto i = static_cast<std::size_t>(n.index);
    if (n.op == Op::Var) {
      if (i >= variables.size()) throw Error("evaluate_half: a variable has no value");
      return round_to_half(variables[i]);
    }
    if (n.op == Op::Param) {
      if (i >= parameters.size()) throw Error("evaluate_half: a parameter has no value");
      return round_to_half(parameters[i]);
    }
    return round_to_half(n.value);
  }

  // apply_ipow's squaring chain, each product rounded; a negative power takes one rounded rcp.
  static double ipow(double x, int k) {
    const bool inverse = k < 0;
    unsigned n = inverse ? 0u - static_cast<unsigned>(k) : static_cast<unsigned>(k);
    double result = 1, base = x;
    bool first = true;
    while (n != 0) {
      if (n & 1u) {
        result = first ? base : round_to_half(result * base);
        first = false;
      }
      n >>= 1u;
      if (n != 0) base = round_to_half(base * base);
    }
    return inverse ? round_to_half(1.0 / result) : result;
  }

  void unary(const Node& n, double& a) const {
    a = n.op == Op::IPow ? ipow(a, n.index) : round_to_half(apply_unary(n.op, a));
  }
  void binary(Op op, double& a, const double& b) const {
    if (op == Op::Pow) {
      a = round_to_half(std::exp2(round_to_half(b * round_to_half(std::log2(a)))));
      return;
    }
    a = round_to_half(apply_binary(op, a, b));
  }
  void ternary(Op op, double& a, const double& b, const double& c) const {
    a = op == Op::Fma ? round_to_half(std::fma(a, b, c)) : apply_select(a, b, c);
  }
};

void check_columns(const Expression& e, std::span<const double* const> columns) {
  if (columns.size() != e.variables.size())
    throw Error("evaluate_in: " + std::to_string(columns.size()) + " columns for " +
                std::to_string(e.variables.size()) + " variables");
  for (const Node& n : e.nodes)
    if (n.op == Op::Var && columns[static_cast<std::size_t>(n.index)] == nullptr)
      throw Error("evaluate_in: no column for variable '" +
                  e.variables[static_cast<std::size_t>(n.index)] + "'");
}

}  // namespace

void check_fits_half(std::span<const double> values, std::string_view what,
                     const SourceLocation& where) {
  for (std::size_t r = 0; r < values.size(); ++r)
    if (!(std::abs(values[r]) <= kHalfMax))
      throw Error(std::string(what) + " overflows half precision: " + format_number(values[r]) +
                      " in row " + std::to_string(r + 1) + " (half holds at most 65504)",
                  where);
}

double evaluate_half(const Expression& e, std::span<const double> variables) {
  HalfNumbers numbers{variables, e.parameter_values};
  std::vector<double> stack;
  stack.reserve(e.nodes.size());
  return evaluate_forward(e, numbers, stack);
}

void evaluate_in(Precision p, const Expression& e, std::span<const double* const> columns,
                 std::span<double> out) {
  if (p == Precision::Double) {
    evaluate(e, columns, out, {.threads = 1});
    return;
  }
  check_columns(e, columns);
  const std::size_t rows = out.size();
  if (p == Precision::Float) {
    std::vector<std::vector<float>> cols32(columns.size());
    std::vector<const float*> ptrs(columns.size(), nullptr);
    for (std::size_t i = 0; i < columns.size(); ++i) {
      if (columns[i] == nullptr) continue;
      cols32[i].assign(columns[i], columns[i] + rows);
      ptrs[i] = cols32[i].data();
    }
    std::vector<float> y(rows);
    evaluate(e, ptrs, y, {.threads = 1});
    std::copy(y.begin(), y.end(), out.begin());
    return;
  }
  std::vector<double> row(columns.size(), 0.0), stack;
  stack.reserve(e.nodes.size());
  HalfNumbers numbers{row, e.parameter_values};
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] != nullptr) row[i] = columns[i][r];
    out[r] = evaluate_forward(e, numbers, stack);
  }
}

}  // namespace shaderfit
