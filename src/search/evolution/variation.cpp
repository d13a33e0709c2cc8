#include "search/evolution/variation.hpp"

#include <algorithm>
#include <cmath>

namespace shaderfit::search_detail {

namespace {

using Nodes = std::vector<Node>;

// While an expression is edited, each Param node carries its value in Node::value, so that
// subtrees can move between expressions; finish() renumbers them and rebuilds the table.
Nodes inline_parameters(const Expression& e) {
  Nodes n = e.nodes;
  for (Node& x : n)
    if (x.op == Op::Param) x.value = e.parameter_values[static_cast<std::size_t>(x.index)];
  return n;
}

Node param_node(double value) {
  Node p = Node::parameter(0);
  p.value = value;
  return p;
}

// Folds every subtree made only of parameters and literals, with at least one parameter, into
// one parameter with the subtree's value: p * q, -p, p + 2, (p * 0.5)^2 fit as well as a single
// constant, and each one saved is a node and a parameter for something else.
Nodes fold_parameter_subtrees(const Nodes& in) {
  struct Info {
    std::size_t start;  // where the subtree begins in `out`
    bool constant;      // only parameters and literals
    bool has_param;
    double value;
  };
  Nodes out;
  std::vector<Info> stack;
  for (const Node& n : in) {
    const int a = arity(n.op);
    Info kids[3];
    for (int k = a - 1; k >= 0; --k) {
      kids[k] = stack.back();
      stack.pop_back();
    }
    const std::size_t start = a > 0 ? kids[0].start : out.size();
    bool constant = n.op == Op::Const || n.op == Op::Param || a > 0;
    bool has_param = n.op == Op::Param;
    for (int k = 0; k < a; ++k) {
      constant = constant && kids[k].constant;
      has_param = has_param || kids[k].has_param;
    }
    double value = n.value;
    if (constant && a > 0) {
      if (a == 1)
        value = apply_unary(n.op, kids[0].value, n.index);
      else if (a == 2)
        value = apply_binary(n.op, kids[0].value, kids[1].value);
      else
        value = apply_ternary(n.op, kids[0].value, kids[1].value, kids[2].value);
    }
    if (constant && has_param && a > 0 && std::isfinite(value)) {
      out.resize(start);
      out.push_back(param_node(value));
    } else {
      if (!std::isfinite(value)) constant = false;
      out.push_back(n);
    }
    stack.push_back({start, constant, has_param, value});
  }
  return out;
}

Expression finish(Nodes nodes, const VariationLimits& limits) {
  Expression e;
  if (nodes.empty()) return e;
  nodes = fold_parameter_subtrees(nodes);
  if (nodes.size() > limits.max_nodes) return e;
  e.nodes = std::move(nodes);
  e.variables = limits.variables;
  for (Node& x : e.nodes) {
    if (x.op != Op::Param) continue;
    x.index = static_cast<std::int16_t>(e.parameters.size());
    e.parameters.push_back("p" + std::to_string(e.parameters.size()));
    e.parameter_values.push_back(x.value);
    x.value = 0.0;
  }
  if (static_cast<int>(e.parameters.size()) > limits.max_parameters) return {};
  e.update_lengths();
  return e;
}

std::size_t subtree_start(const Nodes& n, std::size_t i) { return i - n[i].length; }

// Replaces the subtree rooted at i with `with`.
Nodes splice(const Nodes& n, std::size_t i, const Nodes& with) {
  Nodes out(n.begin(), n.begin() + static_cast<std::ptrdiff_t>(subtree_start(n, i)));
  out.insert(out.end(), with.begin(), with.end());
  out.insert(out.end(), n.begin() + static_cast<std::ptrdiff_t>(i) + 1, n.end());
  return out;
}

Nodes subtree_of(const Nodes& n, std::size_t i) {
  return Nodes(n.begin() + static_cast<std::ptrdiff_t>(subtree_start(n, i)),
               n.begin() + static_cast<std::ptrdiff_t>(i) + 1);
}

int count_params(const Nodes& n) {
  return static_cast<int>(
      std::count_if(n.begin(), n.end(), [](const Node& x) { return x.op == Op::Param; }));
}

Node random_leaf(Rng& rng, const VariationLimits& l, bool allow_param) {
  const double u = uniform01(rng);
  if (allow_param && u < 0.15) return param_node(uniform(rng, -1.0, 2.0));
  if (!l.literals.empty() && u < 0.4)
    return Node::constant(l.literals[uniform_index(rng, l.literals.size())]);
  return Node::variable(static_cast<int>(uniform_index(rng, l.variables.size())));
}

Node random_op(Rng& rng, const VariationLimits& l, int want_arity = -1) {
  std::vector<Op> pool;
  for (Op op : l.operators)
    if (want_arity < 0 || arity(op) == want_arity) pool.push_back(op);
  if (pool.empty()) return Node::op_node(Op::Count_);
  const Op op = pool[uniform_index(rng, pool.size())];
  if (op == Op::IPow)
    return Node::ipow(
        2 + static_cast<int>(uniform_index(rng, static_cast<std::uint64_t>(l.max_power - 1))));
  return Node::op_node(op);
}

void grow(Rng& rng, const VariationLimits& l, int depth, bool allow_param, Nodes& out) {
  if (depth <= 0 || bernoulli(rng, 0.3)) {
    out.push_back(random_leaf(rng, l, allow_param));
    return;
  }
  const Node op = random_op(rng, l);
  if (op.op == Op::Count_) {
    out.push_back(random_leaf(rng, l, allow_param));
    return;
  }
  for (int k = 0; k < arity(op.op); ++k) grow(rng, l, depth - 1, allow_param, out);
  out.push_back(op);
}

std::size_t random_node(Rng& rng, const Nodes& n, bool operators_only) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < n.size(); ++i)
    if (!operators_only || n[i].arity > 0) idx.push_back(i);
  if (idx.empty()) return n.size();
  return idx[uniform_index(rng, idx.size())];
}

}  // namespace

Expression normalize_parameters(Expression e, const VariationLimits& limits) {
  return finish(inline_parameters(e), limits);
}

Expression random_formula(Rng& rng, const VariationLimits& limits, int depth) {
  Nodes n;
  grow(rng, limits, depth, limits.max_parameters > 0, n);
  return finish(std::move(n), limits);
}

Expression with_linear_scaling(const Expression& e, double a, double b) {
  Nodes n = inline_parameters(e);
  n.insert(n.begin(), param_node(a));
  n.push_back(Node::op_node(Op::Mul));
  n.push_back(param_node(b));
  n.push_back(Node::op_node(Op::Add));
  VariationLimits unlimited;
  unlimited.variables = e.variables;
  unlimited.max_nodes = n.size();
  unlimited.max_parameters = 1 << 20;
  return finish(std::move(n), unlimited);
}

Expression with_literals_as_parameters(const Expression& e) {
  Nodes n = inline_parameters(e);
  for (Node& x : n)
    if (x.op == Op::Const) x = param_node(x.value);
  VariationLimits unlimited;
  unlimited.variables = e.variables;
  unlimited.max_nodes = n.size();
  unlimited.max_parameters = 1 << 20;
  return finish(std::move(n), unlimited);
}

std::vector<std::vector<Node>> subtree_blocks(const std::vector<const Expression*>& formulas) {
  std::vector<Nodes> out;
  for (const Expression* e : formulas) {
    const Nodes n = inline_parameters(*e);
    for (std::size_t i = 0; i < n.size() && out.size() < kMaxBlocks; ++i) {
      const std::size_t size = n[i].length + 1;
      if (size < 2 || size > kMaxBlockNodes) continue;
      Nodes t = subtree_of(n, i);
      const auto same = [&](const Nodes& b) {
        return b.size() == t.size() &&
               std::equal(b.begin(), b.end(), t.begin(), [](const Node& x, const Node& y) {
                 return x.op == y.op && x.index == y.index && x.value == y.value;
               });
      };
      if (std::none_of(out.begin(), out.end(), same)) out.push_back(std::move(t));
    }
  }
  return out;
}

Expression mutate(Rng& rng, const Expression& e, const VariationLimits& l) {
  Nodes n = inline_parameters(e);  // lengths valid: e is well formed
  const bool room_for_param = count_params(n) < l.max_parameters;
  switch (uniform_index(rng, 8)) {
    case 0: {  // another operator of the same arity, or another exponent
      const std::size_t i = random_node(rng, n, true);
      if (i == n.size()) break;
      const Node op = random_op(rng, l, n[i].arity);
      if (op.op == Op::Count_) break;
      n[i].op = op.op;
      n[i].index = op.index;
      break;
    }
    case 1: {  // another leaf
      std::vector<std::size_t> leaves;
      for (std::size_t i = 0; i < n.size(); ++i)
        if (n[i].arity == 0) leaves.push_back(i);
      const std::size_t i = leaves[uniform_index(rng, leaves.size())];
      n[i] = random_leaf(rng, l, room_for_param || n[i].op == Op::Param);
      break;
    }
    case 2: {  // a new random subtree, or a building block
      const std::size_t i = random_node(rng, n, false);
      Nodes t;
      if (!l.blocks.empty() && bernoulli(rng, 0.5))
        t = l.blocks[uniform_index(rng, l.blocks.size())];
      else
        grow(rng, l, static_cast<int>(uniform_index(rng, 3)), room_for_param, t);
      n = splice(n, i, t);
      break;
    }
    case 3: {  // hoist a child over its parent
      const std::size_t i = random_node(rng, n, true);
      if (i == n.size()) break;
      std::vector<std::size_t> kids;
      for (std::size_t j = i - 1, k = 0; k < n[i].arity; ++k) {
        kids.push_back(j);
        if (k + 1 < n[i].arity) j = subtree_start(n, j) - 1;
      }
      n = splice(n, i, subtree_of(n, kids[uniform_index(rng, kids.size())]));
      break;
    }
    case 4: {  // wrap a subtree in a new operator
      const std::size_t i = random_node(rng, n, false);
      const Node op = random_op(rng, l);
      if (op.op == Op::Count_) break;
      Nodes t = subtree_of(n, i);
      if (arity(op.op) == 2) {
        Nodes leaf{random_leaf(rng, l, room_for_param)};
        if (bernoulli(rng, 0.5))
          t.insert(t.end(), leaf.begin(), leaf.end());
        else
          t.insert(t.begin(), leaf.begin(), leaf.end());
      } else if (op.op == Op::Select) {  // select(leaf, t, leaf): t taken where leaf >= 0
        Nodes cond{random_leaf(rng, l, room_for_param)};
        t.insert(t.begin(), cond.begin(), cond.end());
        t.push_back(random_leaf(rng, l, false));
      } else if (arity(op.op) == 3) {
        break;
      }
      t.push_back(op);
      n = splice(n, i, t);
      break;
    }
    case 5: {  // a literal becomes a free parameter
      std::vector<std::size_t> consts;
      for (std::size_t i = 0; i < n.size(); ++i)
        if (n[i].op == Op::Const) consts.push_back(i);
      if (consts.empty() || !room_for_param) break;
      const std::size_t i = consts[uniform_index(rng, consts.size())];
      n[i] = param_node(n[i].value);
      break;
    }
    case 6: {  // scale or shift a subtree by a new parameter
      if (!room_for_param) break;
      const std::size_t i = random_node(rng, n, false);
      Nodes t = subtree_of(n, i);
      const bool scale = bernoulli(rng, 0.5);
      t.push_back(param_node(scale ? 1.0 : 0.0));
      t.push_back(Node::op_node(scale ? Op::Mul : Op::Add));
      n = splice(n, i, t);
      break;
    }
    default: {  // jitter a parameter (or a leaf change when there is none)
      std::vector<std::size_t> ps;
      for (std::size_t i = 0; i < n.size(); ++i)
        if (n[i].op == Op::Param) ps.push_back(i);
      if (ps.empty()) break;
      Node& p = n[ps[uniform_index(rng, ps.size())]];
      p.value = p.value * uniform(rng, 0.5, 1.5) + uniform(rng, -0.1, 0.1);
      break;
    }
  }
  return finish(std::move(n), l);
}

Expression crossover(Rng& rng, const Expression& a, const Expression& b, const VariationLimits& l) {
  const Nodes na = inline_parameters(a), nb = inline_parameters(b);
  const std::size_t i = uniform_index(rng, na.size());
  const std::size_t j = uniform_index(rng, nb.size());
  return finish(splice(na, i, subtree_of(nb, j)), l);
}

}  // namespace shaderfit::search_detail
