#include "shaderfit/cost/per_material.hpp"

#include <algorithm>

#include "cost/dag.hpp"
#include "cost/select.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit {

namespace {

std::vector<bool> uniform_variables(const Expression& e, std::span<const std::string> uniform) {
  std::vector<bool> u(e.variables.size(), false);
  for (std::size_t v = 0; v < e.variables.size(); ++v)
    u[v] = std::find(uniform.begin(), uniform.end(), e.variables[v]) != uniform.end();
  return u;
}

// Per node: whether it reads no varying input (uniform inputs, literals, parameters only), and
// whether it reads a uniform input.
struct Reads {
  std::vector<bool> only_uniform, some_uniform;
};

Reads reads_of(const Expression& e, const std::vector<bool>& uniform_var) {
  Reads r{std::vector<bool>(e.size()), std::vector<bool>(e.size())};
  std::size_t c[3];
  for (std::size_t i = 0; i < e.size(); ++i) {
    const Node& n = e.nodes[i];
    if (n.op == Op::Var) {
      r.only_uniform[i] = r.some_uniform[i] = uniform_var[static_cast<std::size_t>(n.index)];
      continue;
    }
    bool only = true, some = false;
    e.child_indices(i, {c, n.arity});
    for (int k = 0; k < n.arity; ++k) {
      only = only && r.only_uniform[c[k]];
      some = some || r.some_uniform[c[k]];
    }
    r.only_uniform[i] = only;
    r.some_uniform[i] = some;
  }
  return r;
}

// Whether the subtree at i is >= 0 (or NaN) for every value of its inputs, by its operators.
bool non_negative(const Expression& e, std::size_t i) {
  const Node& n = e.nodes[i];
  std::size_t c[3];
  e.child_indices(i, {c, n.arity});
  switch (n.op) {
    case Op::Const: return n.value >= 0;
    case Op::Param: {
      const auto k = static_cast<std::size_t>(n.index);
      return k < e.parameter_values.size() && e.parameter_values[k] >= 0;
    }
    default:
      return value_nonnegative(
          n.op, n.index, [&](int k) { return non_negative(e, c[static_cast<std::size_t>(k)]); });
  }
}

using Nodes = std::vector<Node>;

// e with U * exp2(x) written exp2(x + log2 U) wherever U is a non-negative per-material value
// (and the same for pow, exp, and divisions; see the header).
class ExpFold {
 public:
  ExpFold(const Expression& e, Reads reads) : e_(e), reads_(std::move(reads)) {}

  Expression run() {
    Expression out = e_;
    out.nodes.clear();
    emit(e_.size() - 1, out.nodes);
    out.update_lengths();
    return out;
  }
  [[nodiscard]] bool changed() const { return changed_; }

 private:
  bool material(std::size_t i) const {
    return reads_.only_uniform[i] && reads_.some_uniform[i] && non_negative(e_, i);
  }
  bool exponential(std::size_t i) const {
    const Op op = e_.nodes[i].op;
    return !reads_.only_uniform[i] && (op == Op::Exp2 || op == Op::Pow || op == Op::Exp);
  }
  void copy(std::size_t i, Nodes& out) const {
    out.insert(out.end(), e_.nodes.begin() + static_cast<std::ptrdiff_t>(e_.subtree_begin(i)),
               e_.nodes.begin() + static_cast<std::ptrdiff_t>(i) + 1);
  }
  // The exponent of the exponential at i (x of exp2(x) or exp(x), b * log2(a) of pow(a, b)).
  void exponent(std::size_t i, Nodes& out) {
    std::size_t c[2];
    e_.child_indices(i, {c, e_.nodes[i].arity});
    if (e_.nodes[i].op != Op::Pow) {
      emit(c[0], out);
      return;
    }
    emit(c[1], out);
    emit(c[0], out);
    out.push_back(Node::op_node(Op::Log2));
    out.push_back(Node::op_node(Op::Mul));
  }

  void emit(std::size_t i, Nodes& out) {
    const Node& n = e_.nodes[i];
    std::size_t c[3];
    e_.child_indices(i, {c, n.arity});
    if (n.op == Op::Mul || n.op == Op::Div) {
      // x: the exponential, u: the material value; `u_first` for u / exponential.
      std::size_t x = 0, u = 0;
      bool found = false, u_first = false;
      if (exponential(c[0]) && material(c[1])) {
        x = c[0], u = c[1], found = true;
      } else if (exponential(c[1]) && material(c[0])) {
        x = c[1], u = c[0], found = true, u_first = n.op == Op::Div;
      }
      if (found) {
        changed_ = true;
        const bool natural = e_.nodes[x].op == Op::Exp;
        const Op log = natural ? Op::Log : Op::Log2;
        if (u_first) {  // u / exp2(x) = exp2(log2 u - x)
          copy(u, out);
          out.push_back(Node::op_node(log));
          exponent(x, out);
          out.push_back(Node::op_node(Op::Sub));
        } else {
          exponent(x, out);
          copy(u, out);
          out.push_back(Node::op_node(log));
          out.push_back(Node::op_node(n.op == Op::Mul ? Op::Add : Op::Sub));
        }
        out.push_back(Node::op_node(natural ? Op::Exp : Op::Exp2));
        return;
      }
    }
    for (int k = 0; k < n.arity; ++k) emit(c[k], out);
    out.push_back(n);
  }

  const Expression& e_;
  Reads reads_;
  bool changed_ = false;
};

class Hoist {
 public:
  Hoist(const Expression& e, const std::vector<bool>& uniform_var)
      : e_(e), reads_(reads_of(e, uniform_var)), prefix_(unused_name_prefix(e, 'm')) {
    for (std::size_t v = 0; v < e.variables.size(); ++v) {
      varying_index_.push_back(uniform_var[v] ? -1 : static_cast<int>(varying_.size()));
      if (!uniform_var[v]) varying_.push_back(e.variables[v]);
    }
  }

  MaterialSplit run() {
    MaterialSplit s;
    Nodes nodes;
    emit(e_.size() - 1, nodes);
    s.per_pixel.variables = varying_;
    for (const MaterialValue& v : values_) s.per_pixel.variables.push_back(v.name);
    for (Node& n : nodes)
      if (n.op == Op::Var && n.index < 0)
        n.index =
            static_cast<std::int16_t>(varying_.size() + static_cast<std::size_t>(-1 - n.index));
    s.per_pixel.nodes = std::move(nodes);
    s.per_pixel.update_lengths();
    keep_read_parameters(s.per_pixel);
    s.values = std::move(values_);
    return s;
  }

 private:
  // The parameters e reads, renumbered in order.
  void keep_read_parameters(Expression& p) const {
    std::vector<int> remap(e_.parameters.size(), -1);
    for (const Node& n : p.nodes)
      if (n.op == Op::Param) remap[static_cast<std::size_t>(n.index)] = 0;
    for (std::size_t k = 0; k < remap.size(); ++k) {
      if (remap[k] < 0) continue;
      remap[k] = static_cast<int>(p.parameters.size());
      p.parameters.push_back(e_.parameters[k]);
      if (k < e_.parameter_values.size()) p.parameter_values.push_back(e_.parameter_values[k]);
    }
    for (Node& n : p.nodes)
      if (n.op == Op::Param)
        n.index = static_cast<std::int16_t>(remap[static_cast<std::size_t>(n.index)]);
  }

  // The index of the value v computes (added when new), as -1 - index.
  int value_of(Expression v) {
    for (std::size_t k = 0; k < values_.size(); ++k)
      if (values_[k].value == v) return -1 - static_cast<int>(k);
    std::string name;
    if (v.size() == 1) {
      name = e_.variables[static_cast<std::size_t>(v.nodes[0].index)];
    } else {
      name = prefix_ + std::to_string(computed_++);
    }
    values_.push_back({std::move(name), std::move(v)});
    return -1 - static_cast<int>(values_.size() - 1);
  }

  bool material(std::size_t i) const { return reads_.only_uniform[i] && reads_.some_uniform[i]; }

  void emit(std::size_t i, Nodes& out) {
    const Node& n = e_.nodes[i];
    if (material(i)) {
      out.push_back(Node::variable(0));
      out.back().index = static_cast<std::int16_t>(value_of(e_.subtree(i)));
      return;
    }
    std::size_t c[3];
    e_.child_indices(i, {c, n.arity});
    if (n.op == Op::Div && material(c[1])) {
      // x / U = x * (1/U), the reciprocal per material (GPUs divide by a reciprocal anyway).
      Expression r = e_.subtree(c[1]);
      r.nodes.push_back(Node::op_node(Op::Rcp));
      r.update_lengths();
      emit(c[0], out);
      out.push_back(Node::variable(0));
      out.back().index = static_cast<std::int16_t>(value_of(std::move(r)));
      out.push_back(Node::op_node(Op::Mul));
      return;
    }
    if (n.op == Op::Var) {
      out.push_back(Node::variable(varying_index_[static_cast<std::size_t>(n.index)]));
      return;
    }
    for (int k = 0; k < n.arity; ++k) emit(c[k], out);
    out.push_back(n);
  }

  const Expression& e_;
  Reads reads_;
  std::string prefix_;
  std::vector<std::string> varying_;
  std::vector<int> varying_index_;
  std::vector<MaterialValue> values_;
  int computed_ = 0;
};

std::vector<Expression> value_expressions(const MaterialSplit& s) {
  std::vector<Expression> v;
  for (const MaterialValue& m : s.values) v.push_back(m.value);
  return v;
}

// The split of e, the exp2 rewrite taken where it lowers the per-pixel count.
MaterialSplit best_split(const Expression& e, const std::vector<bool>& uniform_var,
                         InstructionTarget target) {
  MaterialSplit plain = Hoist(e, uniform_var).run();
  ExpFold fold(e, reads_of(e, uniform_var));
  const Expression folded = fold.run();
  if (!fold.changed()) return plain;
  MaterialSplit moved = Hoist(folded, uniform_var).run();
  return instruction_count(moved.per_pixel, target) < instruction_count(plain.per_pixel, target)
             ? std::move(moved)
             : std::move(plain);
}

}  // namespace

void check_uniform_inputs(std::span<const std::string> uniform, std::span<const std::string> inputs,
                          const SourceLocation& where) {
  for (std::size_t k = 0; k < uniform.size(); ++k) {
    const std::string& u = uniform[k];
    if (std::find(inputs.begin(), inputs.end(), u) == inputs.end()) {
      std::string known;
      for (const std::string& i : inputs) known += (known.empty() ? "" : ", ") + i;
      throw Error("uniform input '" + u + "' is not an input (inputs: " + known + ")", where);
    }
    if (std::find(uniform.begin(), uniform.begin() + static_cast<std::ptrdiff_t>(k), u) !=
        uniform.begin() + static_cast<std::ptrdiff_t>(k))
      throw Error("uniform input '" + u + "' is given twice", where);
  }
  if (!uniform.empty() && uniform.size() >= inputs.size())
    throw Error("every input is uniform: at least one must vary over the pixels", where);
}

bool reads_uniform(const Expression& e, std::span<const std::string> uniform) {
  if (uniform.empty()) return false;
  const std::vector<bool> u = uniform_variables(e, uniform);
  for (const Node& n : e.nodes)
    if (n.op == Op::Var && u[static_cast<std::size_t>(n.index)]) return true;
  return false;
}

MaterialSplit split_per_material(const Expression& e, std::span<const std::string> uniform) {
  if (e.empty()) throw Error("empty expression");
  if (!reads_uniform(e, uniform)) return {e, {}};
  // One split for every target, so that what each counts is what code generation prints: the
  // rewrite is chosen by the sass count (unfused, it keeps the count: a multiply becomes an add).
  return best_split(e, uniform_variables(e, uniform), InstructionTarget::Sass);
}

SplitCost split_instruction_count(const Expression& e, std::span<const std::string> uniform,
                                  InstructionTarget target) {
  if (!reads_uniform(e, uniform)) return {instruction_count(e, target), 0};
  const MaterialSplit s = split_per_material(e, uniform);
  return {instruction_count(s.per_pixel, target),
          static_cast<int>(
              cost_detail::select_for(cost_detail::lower_for(value_expressions(s), target), target, false)
                  .size())};
}

InstructionCost material_instruction_cost(const MaterialSplit& split, InstructionTarget target) {
  if (split.values.empty()) return cost_detail::tally({}, target);
  return cost_detail::tally(
      cost_detail::select_for(cost_detail::lower_for(value_expressions(split), target), target, true),
      target);
}

}  // namespace shaderfit
