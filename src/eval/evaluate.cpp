#include "shaderfit/eval/evaluate.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "eval/interpreter.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/expr/forward.hpp"

namespace shaderfit {

namespace eval_detail {

namespace {

std::string node_name(const Expression& e, std::size_t i) {
  return "node " + std::to_string(i) + " ('" + std::string(op_info(e.nodes[i].op).name) + "')";
}

// Checks everything evaluation relies on and returns the deepest postfix stack.
std::size_t check_expression(const Expression& e, std::size_t num_columns) {
  if (num_columns != e.variables.size()) {
    throw Error("evaluate: " + std::to_string(num_columns) + " columns given for " +
                std::to_string(e.variables.size()) + " variables");
  }
  if (e.nodes.empty()) throw Error("malformed expression: no nodes");
  std::size_t depth = 0, max_depth = 0;
  for (std::size_t i = 0; i < e.nodes.size(); ++i) {
    const Node& n = e.nodes[i];
    if (static_cast<int>(n.op) >= kOpCount) {
      throw Error("malformed expression: node " + std::to_string(i) + " has unknown op " +
                  std::to_string(static_cast<int>(n.op)));
    }
    const int a = arity(n.op);
    if (n.op == Op::Var && (n.index < 0 || static_cast<std::size_t>(n.index) >= e.variables.size()))
      throw Error("malformed expression: " + node_name(e, i) + " reads a missing variable");
    if (n.op == Op::Param &&
        (n.index < 0 || static_cast<std::size_t>(n.index) >= e.parameter_values.size()))
      throw Error("malformed expression: " + node_name(e, i) + " reads a parameter with no value");
    if (n.op == Op::IPow && (n.index < kMinIntegerPower || n.index > kMaxIntegerPower))
      throw Error("malformed expression: " + node_name(e, i) + " has exponent " +
                  std::to_string(n.index) + " outside [-16, 16]");
    if (depth < static_cast<std::size_t>(a))
      throw Error("malformed expression: " + node_name(e, i) + " lacks operands");
    depth = depth - static_cast<std::size_t>(a) + 1;
    max_depth = std::max(max_depth, depth);
  }
  if (depth != 1) throw Error("malformed expression: not a single tree");
  return max_depth;
}

}  // namespace

template <typename T>
Plan<T> compile_plan(const Expression& e, std::size_t num_columns) {
  const std::size_t max_depth = check_expression(e, num_columns);
  Plan<T> plan;
  plan.num_vars = static_cast<std::uint32_t>(e.variables.size());
  std::vector<bool> used(e.variables.size(), false);
  std::size_t leaves = 0;
  for (const Node& n : e.nodes) {
    if (n.op == Op::Var) used[static_cast<std::size_t>(n.index)] = true;
    if (n.op == Op::Const || n.op == Op::Param) ++leaves;
  }
  for (std::uint32_t v = 0; v < plan.num_vars; ++v)
    if (used[v]) plan.used_vars.push_back(v);
  plan.const_base = plan.num_vars;
  plan.stack_base = plan.const_base + static_cast<std::uint32_t>(leaves);
  // The root's own stack slot is never needed: it writes to the output.
  plan.out_index = plan.stack_base + static_cast<std::uint32_t>(max_depth);

  plan.constants.reserve(leaves);
  plan.code.reserve(e.nodes.size() - leaves);
  std::vector<std::uint32_t> stack;  // source index of each value on the postfix stack
  stack.reserve(max_depth);
  for (std::size_t i = 0; i < e.nodes.size(); ++i) {
    const Node& n = e.nodes[i];
    switch (n.op) {
      case Op::Var: stack.push_back(static_cast<std::uint32_t>(n.index)); continue;
      case Op::Const:
      case Op::Param: {
        const double v =
            n.op == Op::Const ? n.value : e.parameter_values[static_cast<std::size_t>(n.index)];
        stack.push_back(plan.const_base + static_cast<std::uint32_t>(plan.constants.size()));
        plan.constants.push_back(static_cast<T>(v));
        continue;
      }
      default: break;
    }
    Instr ins;
    ins.op = n.op;
    ins.k = n.index;
    const int a = arity(n.op);
    for (int j = a - 1; j >= 0; --j) {
      ins.arg[j] = stack.back();
      stack.pop_back();
    }
    const bool root = i + 1 == e.nodes.size();
    ins.out = root ? plan.out_index : plan.stack_base + static_cast<std::uint32_t>(stack.size());
    stack.push_back(ins.out);
    plan.code.push_back(ins);
  }
  plan.root = stack.back();
  return plan;
}

template Plan<float> compile_plan<float>(const Expression&, std::size_t);
template Plan<double> compile_plan<double>(const Expression&, std::size_t);

namespace {

template <typename T>
void evaluate_impl(const Expression& e, std::span<const T* const> columns, std::span<T> out,
                   const EvalOptions& options, TaskFn<T> task) {
  if (options.threads < 0) throw Error("evaluate: threads must be >= 0");
  const Plan<T> plan = compile_plan<T>(e, columns.size());
  const std::size_t rows = out.size();
  if (rows == 0) return;
  for (std::uint32_t v : plan.used_vars)
    if (columns[v] == nullptr) throw Error("evaluate: column for '" + e.variables[v] + "' is null");

  if (plan.code.empty()) {  // the root is a leaf: copy or fill
    if (plan.root < plan.num_vars)
      std::copy_n(columns[plan.root], rows, out.data());
    else
      std::fill(out.begin(), out.end(), plan.constants[plan.root - plan.const_base]);
    return;
  }

  // Tasks are whole batches, so a task boundary never splits a batch.
  constexpr std::size_t B = kBatchRows<T>;
  const std::size_t batches = (rows - 1) / B + 1;
  const std::size_t grain = std::max<std::size_t>(1, (options.min_rows_per_task + B - 1) / B);
  const T* const* cols = columns.data();
  T* const dst = out.data();
  const int threads = options.threads > 0 ? options.threads : default_thread_pool().threads();
  if (threads == 1 || batches <= grain) {
    task(plan, cols, dst, 0, rows);
    return;
  }
  parallel_for(
      batches, grain,
      [&](std::size_t b0, std::size_t b1) {
        task(plan, cols, dst, b0 * B, std::min(rows, b1 * B));
      },
      threads);
}

}  // namespace

void evaluate_with_backend(const Expression& e, std::span<const float* const> columns,
                           std::span<float> out, const EvalOptions& options, Backend backend) {
  evaluate_impl<float>(e, columns, out, options, task_function_f32(backend));
}

void evaluate_with_backend(const Expression& e, std::span<const double* const> columns,
                           std::span<double> out, const EvalOptions& options, Backend backend) {
  evaluate_impl<double>(e, columns, out, options, task_function_f64(backend));
}

}  // namespace eval_detail

void evaluate(const Expression& e, std::span<const float* const> columns, std::span<float> out,
              const EvalOptions& options) {
  eval_detail::evaluate_with_backend(e, columns, out, options, eval_detail::Backend::Simd);
}

void evaluate(const Expression& e, std::span<const double* const> columns, std::span<double> out,
              const EvalOptions& options) {
  eval_detail::evaluate_with_backend(e, columns, out, options, eval_detail::Backend::Simd);
}

double evaluate_scalar(const Expression& e, std::span<const double> variables) {
  eval_detail::check_expression(e, variables.size());
  return evaluate_at<double>(e, variables, e.parameter_values);
}

}  // namespace shaderfit
