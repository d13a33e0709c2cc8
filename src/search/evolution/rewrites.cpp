#include "search/evolution/rewrites.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/expr/simplify.hpp"

namespace shaderfit::search_detail {

namespace {

using Nodes = std::vector<Node>;
using Column = std::vector<double>;

// The subtree at i with each chain of products (a quotient's denominator a factor 1 / d) and
// each chain of sums (a subtrahend a term -t) regrouped by the inputs its parts read: the parts
// that read the same inputs combined first, those that read none first of all, then those that
// read only `uniform` inputs. So a part of one or two inputs, such as (1 - x)^2 (1 - x)^2 (1 - x)
// in ((t (1 - x)^2) (1 - x)^2) (1 - x), or the per-material part, becomes one subexpression.
Nodes grouped_factors(const Expression& e, std::size_t i, const std::vector<bool>& uniform) {
  const Node& n = e.nodes[i];
  std::size_t kids[3];
  e.child_indices(i, std::span<std::size_t>(kids, n.arity));
  Nodes out;
  const bool product = n.op == Op::Mul || n.op == Op::Div;
  const bool sum = n.op == Op::Add || n.op == Op::Sub;
  if (!product && !sum) {
    for (std::size_t k = 0; k < n.arity; ++k) {
      Nodes c = grouped_factors(e, kids[k], uniform);
      out.insert(out.end(), c.begin(), c.end());
    }
    out.push_back(n);
    return out;
  }
  const Op join = product ? Op::Mul : Op::Add, inverse_join = product ? Op::Div : Op::Sub;
  // The parts, each with whether it is inverted (a denominator, a subtrahend).
  std::vector<std::pair<std::size_t, bool>> parts, todo{{i, false}};
  while (!todo.empty()) {
    const auto [f, inverse] = todo.back();
    todo.pop_back();
    const Op op = e.nodes[f].op;
    if (op == join || op == inverse_join) {
      std::size_t fk[2];
      e.child_indices(f, fk);
      todo.push_back({fk[1], (op == inverse_join) != inverse});
      todo.push_back({fk[0], inverse});
    } else {
      parts.push_back({f, inverse});
    }
  }
  // Key: (reads an input that is not uniform, the inputs read).
  std::map<std::pair<bool, std::vector<int>>, std::vector<std::pair<Nodes, bool>>> groups;
  for (const auto& [f, inverse] : parts) {
    std::set<int> vars;
    for (std::size_t k = e.subtree_begin(f); k <= f; ++k)
      if (e.nodes[k].op == Op::Var) vars.insert(e.nodes[k].index);
    const bool varying = std::any_of(vars.begin(), vars.end(), [&](int v) {
      return !uniform[static_cast<std::size_t>(v)];
    });
    groups[{varying, {vars.begin(), vars.end()}}].push_back(
        {grouped_factors(e, f, uniform), inverse});
  }
  // Each group combined, then the groups; an inverted first part as 1 / p or -p.
  bool first = true;
  for (const auto& [key, group] : groups) {
    bool first_in_group = true;
    for (const auto& [g, inverse] : group) {
      out.insert(out.end(), g.begin(), g.end());
      if (first_in_group && inverse) out.push_back(Node::op_node(product ? Op::Rcp : Op::Neg));
      if (!first_in_group) out.push_back(Node::op_node(inverse ? inverse_join : join));
      first_in_group = false;
    }
    if (!first) out.push_back(Node::op_node(join));
    first = false;
  }
  return out;
}

// Per variable of e: whether it is one of the `uniform` inputs.
std::vector<bool> uniform_flags(const Expression& e, const std::vector<std::string>& uniform) {
  std::vector<bool> out(e.variables.size());
  for (std::size_t v = 0; v < e.variables.size(); ++v)
    out[v] = std::find(uniform.begin(), uniform.end(), e.variables[v]) != uniform.end();
  return out;
}

Expression grouped_factors(const Expression& e, const std::vector<bool>& uniform) {
  Expression r = e;
  r.nodes = grouped_factors(e, e.nodes.size() - 1, uniform);
  r.update_lengths();
  return simplify(r);
}

// The values of e's subtree at node i on the rows.
Column subtree_values(const Expression& e, std::size_t i, const SearchProblem& rows) {
  Expression s = e.subtree(i);
  std::vector<const double*> cols;
  for (const Column& c : rows.inputs) cols.push_back(c.data());
  Column out(rows.target.size());
  evaluate(s, cols, out);
  return out;
}

bool all_finite(const Column& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

// Least squares y ~ sum_k c_k x_k, row r weighted by scale[r]^2 when given; nullopt when a
// coefficient is not finite.
std::optional<std::vector<double>> least_squares(const std::vector<Column>& x, const Column& y,
                                                 const Column* scale = nullptr) {
  const auto rows = static_cast<Eigen::Index>(y.size());
  const auto n = static_cast<Eigen::Index>(x.size());
  Eigen::MatrixXd a(rows, n);
  Eigen::VectorXd b(rows);
  for (Eigen::Index r = 0; r < rows; ++r) {
    const double w = scale != nullptr ? (*scale)[static_cast<std::size_t>(r)] : 1.0;
    b(r) = w * y[static_cast<std::size_t>(r)];
    for (Eigen::Index k = 0; k < n; ++k)
      a(r, k) = w * x[static_cast<std::size_t>(k)][static_cast<std::size_t>(r)];
  }
  const Eigen::VectorXd c = a.colPivHouseholderQr().solve(b);
  std::vector<double> out(static_cast<std::size_t>(n));
  for (Eigen::Index k = 0; k < n; ++k) {
    if (!std::isfinite(c(k))) return std::nullopt;
    out[static_cast<std::size_t>(k)] = c(k);
  }
  return out;
}

Column ones(std::size_t n) { return Column(n, 1.0); }
Column times(const Column& a, const Column& b) {
  Column out(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out[i] = a[i] * b[i];
  return out;
}

// A replacement for a subexpression: nodes over the expression's variables and parameters, its
// own parameters numbered from `base` (the expression's parameter count) with their values.
struct Fragment {
  Nodes nodes;
  std::vector<double> values;
};

class FragmentBuilder {
 public:
  explicit FragmentBuilder(std::size_t base) : base_(base) {}
  FragmentBuilder& param(double v) {
    f_.nodes.push_back(Node::parameter(static_cast<int>(base_ + f_.values.size())));
    f_.values.push_back(v);
    return *this;
  }
  FragmentBuilder& nodes(const Nodes& n) {
    f_.nodes.insert(f_.nodes.end(), n.begin(), n.end());
    return *this;
  }
  FragmentBuilder& op(Op o) {
    f_.nodes.push_back(Node::op_node(o));
    return *this;
  }
  Fragment done() { return std::move(f_); }

 private:
  std::size_t base_;
  Fragment f_;
};

// e with every subtree whose hash is h replaced by `with` (its parameters appended to e's), the
// parameters no node reads dropped and the rest renumbered p0, p1, ... in order of appearance.
Expression replace_all(const Expression& e, const std::vector<std::uint64_t>& hashes,
                       std::uint64_t h, const Fragment& with) {
  Nodes out;
  const auto emit = [&](const auto& self, std::size_t i) -> void {
    if (hashes[i] == h) {
      out.insert(out.end(), with.nodes.begin(), with.nodes.end());
      return;
    }
    std::size_t kids[3];
    const std::size_t a = e.nodes[i].arity;
    e.child_indices(i, std::span<std::size_t>(kids, a));
    for (std::size_t k = 0; k < a; ++k) self(self, kids[k]);
    out.push_back(e.nodes[i]);
  };
  emit(emit, e.nodes.size() - 1);
  std::vector<double> values = e.parameter_values;
  values.insert(values.end(), with.values.begin(), with.values.end());
  Expression r;
  r.variables = e.variables;
  std::map<int, int> renumbered;
  for (Node& n : out) {
    if (n.op != Op::Param) continue;
    auto [it, fresh] = renumbered.emplace(n.index, static_cast<int>(r.parameters.size()));
    if (fresh) {
      r.parameters.push_back("p" + std::to_string(r.parameters.size()));
      r.parameter_values.push_back(values[static_cast<std::size_t>(n.index)]);
    }
    n.index = static_cast<std::int16_t>(it->second);
  }
  r.nodes = std::move(out);
  r.update_lengths();
  return r;
}

Nodes subtree_nodes(const Expression& e, std::size_t i) {
  return Nodes(e.nodes.begin() + static_cast<std::ptrdiff_t>(e.subtree_begin(i)),
               e.nodes.begin() + static_cast<std::ptrdiff_t>(i) + 1);
}

// The variables the subtree at i reads, in index order.
std::vector<int> variables_read(const Expression& e, std::size_t i) {
  std::set<int> vars;
  for (std::size_t k = e.subtree_begin(i); k <= i; ++k)
    if (e.nodes[k].op == Op::Var) vars.insert(e.nodes[k].index);
  return {vars.begin(), vars.end()};
}

double mean(const Column& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / static_cast<double>(v.size());
}

// How deep below a subexpression the base of its power form is looked for.
constexpr int kPowerDepth = 5;

// e with each product a exp2(u) whose factor a reads only uniform inputs and is positive on the
// rows written exp2(u + log2 a), log2 a computed once per material; then regrouped
// (grouped_factors), so that u + log2 a is one addition. e itself when there is none.
Expression absorbed_scales(const Expression& e, const std::vector<bool>& uniform,
                           const SearchProblem& rows) {
  const Expression g = grouped_factors(e, uniform);
  bool changed = false;
  Nodes out;
  const auto emit = [&](const auto& self, std::size_t i) -> void {
    const Node& n = g.nodes[i];
    std::size_t kids[3];
    g.child_indices(i, std::span<std::size_t>(kids, n.arity));
    if (n.op == Op::Mul) {
      for (int side = 0; side < 2; ++side) {
        const std::size_t a = kids[side], x = kids[1 - side];
        if (g.nodes[x].op != Op::Exp2) continue;
        const std::vector<int> vars = variables_read(g, a);
        if (std::any_of(vars.begin(), vars.end(),
                        [&](int v) { return !uniform[static_cast<std::size_t>(v)]; }))
          continue;
        const Column av = subtree_values(g, a, rows);
        if (!std::all_of(av.begin(), av.end(), [](double t) { return t > 0; })) continue;
        std::size_t u[1];
        g.child_indices(x, u);
        self(self, u[0]);
        self(self, a);
        out.push_back(Node::op_node(Op::Log2));
        out.push_back(Node::op_node(Op::Add));
        out.push_back(Node::op_node(Op::Exp2));
        changed = true;
        return;
      }
    }
    for (std::size_t k = 0; k < n.arity; ++k) self(self, kids[k]);
    out.push_back(n);
  };
  emit(emit, g.nodes.size() - 1);
  if (!changed) return e;
  Expression r = g;
  r.nodes = std::move(out);
  r.update_lengths();
  return grouped_factors(r, uniform);
}

// Replacements for a subexpression with values s on the rows: a constant; a + b y for each
// operand y and each input it reads; an operand alone; a lower power; and where it reads one or
// two inputs, the fitted forms of the header.
std::vector<Fragment> replacements(const Expression& e, std::size_t i, const Column& s,
                                   const SearchProblem& rows) {
  const std::size_t base = e.parameters.size();
  const std::size_t n = s.size();
  std::vector<Fragment> out;
  out.push_back(FragmentBuilder(base).param(mean(s)).done());
  // a + b y for y an operand or an input read.
  std::vector<std::pair<Nodes, Column>> ys;
  const Node& node = e.nodes[i];
  std::size_t kids[3];
  e.child_indices(i, std::span<std::size_t>(kids, node.arity));
  for (std::size_t k = 0; k < node.arity; ++k) {
    const Node& c = e.nodes[kids[k]];
    if (c.op == Op::Const || c.op == Op::Param) continue;
    Nodes cn = subtree_nodes(e, kids[k]);
    out.push_back(Fragment{cn, {}});  // the operand alone: a term, factor or operation dropped
    ys.emplace_back(std::move(cn), subtree_values(e, kids[k], rows));
  }
  if (node.op == Op::Div && e.nodes[kids[1]].op != Op::Const) {
    Nodes r = subtree_nodes(e, kids[1]);
    r.push_back(Node::op_node(Op::Rcp));
    out.push_back(Fragment{r, {}});  // the numerator dropped
  }
  if (node.op == Op::IPow && node.index > 2) {
    for (int j = 2; j < node.index; ++j) {
      Nodes p = subtree_nodes(e, kids[0]);
      p.push_back(Node::ipow(j));
      out.push_back(Fragment{p, {}});
    }
  }
  // The operands' operands too: (c + y) - d is a + b y.
  for (std::size_t k = 0; k < node.arity; ++k) {
    std::size_t grand[3];
    const Node& c = e.nodes[kids[k]];
    e.child_indices(kids[k], std::span<std::size_t>(grand, c.arity));
    for (std::size_t g = 0; g < c.arity; ++g) {
      const Node& gc = e.nodes[grand[g]];
      if (gc.op == Op::Const || gc.op == Op::Param || gc.op == Op::Var) continue;
      ys.emplace_back(subtree_nodes(e, grand[g]), subtree_values(e, grand[g], rows));
    }
  }
  const std::vector<int> vars = variables_read(e, i);
  for (int v : vars)
    if (node.arity != 1 || e.nodes[kids[0]].op != Op::Var)
      ys.emplace_back(Nodes{Node::variable(v)}, rows.inputs[static_cast<std::size_t>(v)]);
  // exp2(a + p log2 y), a power of a part y of the subexpression (up to kPowerDepth levels
  // below it): s = 2^a y^p, as rsqrt(y)^3 = y^-1.5.
  const bool s_positive = std::all_of(s.begin(), s.end(), [](double t) { return t > 0; });
  std::vector<std::pair<Nodes, Column>> parts;
  if (s_positive) {
    std::vector<std::pair<std::size_t, int>> todo{{i, 0}};
    std::set<std::uint64_t> seen;
    while (!todo.empty()) {
      const auto [at, depth] = todo.back();
      todo.pop_back();
      if (depth >= kPowerDepth) continue;
      std::size_t ck[3];
      e.child_indices(at, std::span<std::size_t>(ck, e.nodes[at].arity));
      for (std::size_t k = 0; k < e.nodes[at].arity; ++k) {
        const Op op = e.nodes[ck[k]].op;
        if (op == Op::Const || op == Op::Param) continue;
        Nodes yn = subtree_nodes(e, ck[k]);
        Expression y = e.subtree(ck[k]);
        if (seen.insert(structural_hash(y)).second)
          parts.emplace_back(std::move(yn), subtree_values(e, ck[k], rows));
        todo.push_back({ck[k], depth + 1});
      }
    }
  }
  for (const auto& [yn, yv] : parts) {
    if (!s_positive || !std::all_of(yv.begin(), yv.end(), [](double t) { return t > 0; }))
      continue;
    Column ls(n), ly(n);
    for (std::size_t r = 0; r < n; ++r) {
      ls[r] = std::log2(s[r]);
      ly[r] = std::log2(yv[r]);
    }
    if (auto c = least_squares({ones(n), ly}, ls, &s))
      out.push_back(FragmentBuilder(base).param((*c)[0]).nodes(yn).op(Op::Log2).param((*c)[1])
                        .op(Op::Mul).op(Op::Add).op(Op::Exp2).done());
  }
  for (const auto& [yn, yv] : ys)
    if (auto c = least_squares({ones(n), yv}, s))
      out.push_back(
          FragmentBuilder(base).param((*c)[0]).nodes(yn).param((*c)[1]).op(Op::Mul).op(Op::Add).done());

  // Fitted forms of one input, for a subexpression of two operations or more.
  if (node.length < 3) return out;
  if (vars.size() == 1) {
    const Node x = Node::variable(vars[0]);
    const Column& v = rows.inputs[static_cast<std::size_t>(vars[0])];
    const Column v2 = times(v, v);
    // p0 + x (p1 + x p2) and p0 + x (p1 + x (p2 + x p3)).
    if (auto c = least_squares({ones(n), v, v2}, s))
      out.push_back(FragmentBuilder(base).param((*c)[0]).nodes({x}).param((*c)[1]).nodes({x})
                        .param((*c)[2]).op(Op::Mul).op(Op::Add).op(Op::Mul).op(Op::Add).done());
    if (auto c = least_squares({ones(n), v, v2, times(v2, v)}, s))
      out.push_back(FragmentBuilder(base).param((*c)[0]).nodes({x}).param((*c)[1]).nodes({x})
                        .param((*c)[2]).nodes({x}).param((*c)[3]).op(Op::Mul).op(Op::Add)
                        .op(Op::Mul).op(Op::Add).op(Op::Mul).op(Op::Add).done());
    // (p0 + p1 x) / (1 + p2 x): s = p0 + p1 x - p2 x s.
    if (auto c = least_squares({ones(n), v, times(v, s)}, s)) {
      const double lo = *std::min_element(v.begin(), v.end());
      const double hi = *std::max_element(v.begin(), v.end());
      if (1 - (*c)[2] * lo > 0 && 1 - (*c)[2] * hi > 0)
        out.push_back(FragmentBuilder(base).param((*c)[0]).nodes({x}).param((*c)[1]).op(Op::Mul)
                          .op(Op::Add).param(1.0).nodes({x}).param(-(*c)[2]).op(Op::Mul)
                          .op(Op::Add).op(Op::Div).done());
    }
    const bool positive = std::all_of(s.begin(), s.end(), [](double t) { return t >= 0; }) &&
                          std::any_of(s.begin(), s.end(), [](double t) { return t > 0; });
    if (positive) {
      // exp2(p0 + p1 x) and exp2(p0 + x (p1 + p2 x)), fitted in log2 with weights s^2 (close
      // to the fit in s itself; rows where s = 0 left out).
      Column l(n);
      for (std::size_t r = 0; r < n; ++r) l[r] = s[r] > 0 ? std::log2(s[r]) : 0.0;
      const Column& scale = s;
      if (auto c = least_squares({ones(n), v}, l, &scale))
        out.push_back(FragmentBuilder(base).param((*c)[0]).nodes({x}).param((*c)[1]).op(Op::Mul)
                          .op(Op::Add).op(Op::Exp2).done());
      if (auto c = least_squares({ones(n), v, v2}, l, &scale))
        out.push_back(FragmentBuilder(base).param((*c)[0]).nodes({x}).param((*c)[1]).nodes({x})
                          .param((*c)[2]).op(Op::Mul).op(Op::Add).op(Op::Mul).op(Op::Add)
                          .op(Op::Exp2).done());
      // pow(p0 + p1 x, p) for p on a grid: s^(1/p) = p0 + p1 x, the best p by its error in s.
      double best = HUGE_VAL;
      std::optional<Fragment> best_pow;
      for (double p : {-3.0, -2.0, -1.5, -1.0, -0.5, 0.5, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0}) {
        Column root(n);
        for (std::size_t r = 0; r < n; ++r) root[r] = std::pow(s[r], 1 / p);
        const auto c = least_squares({ones(n), v}, root);
        if (!c) continue;
        double err = 0;
        bool ok = true;
        for (std::size_t r = 0; r < n && ok; ++r) {
          const double base_r = (*c)[0] + (*c)[1] * v[r];
          ok = base_r > 0;
          const double d = std::pow(base_r, p) - s[r];
          err += d * d;
        }
        if (!ok || !(err < best)) continue;
        best = err;
        best_pow = FragmentBuilder(base).param((*c)[0]).nodes({x}).param((*c)[1]).op(Op::Mul)
                       .op(Op::Add).param(p).op(Op::Pow).done();
      }
      if (best_pow) out.push_back(std::move(*best_pow));
    }
  } else if (vars.size() == 2) {
    const Node x = Node::variable(vars[0]), y = Node::variable(vars[1]);
    const Column& u = rows.inputs[static_cast<std::size_t>(vars[0])];
    const Column& w = rows.inputs[static_cast<std::size_t>(vars[1])];
    // p0 + p1 x + y (p2 + p3 x).
    if (auto c = least_squares({ones(n), u, w, times(u, w)}, s))
      out.push_back(FragmentBuilder(base).param((*c)[0]).nodes({x}).param((*c)[1]).op(Op::Mul)
                        .op(Op::Add).nodes({y}).param((*c)[2]).nodes({x}).param((*c)[3])
                        .op(Op::Mul).op(Op::Add).op(Op::Mul).op(Op::Add).done());
    // p0 + x (p1 + y) and p0 + x (p1 x + y), x either input: two instructions, the least
    // squares fit s ~ c0 + c1 x + c2 x y (or c1 x^2) divided by c2, since the screening and the
    // refit take the scale (a f + b). As the phase functions' 1 + g^2 - 2 g cos.
    for (int swap = 0; swap < 2; ++swap) {
      const Node a = swap ? y : x, b = swap ? x : y;
      const Column& av = swap ? w : u;
      const Column ab = times(u, w);
      for (bool square : {false, true}) {
        const auto c = least_squares({ones(n), square ? times(av, av) : av, ab}, s);
        if (!c || !((*c)[2] != 0)) continue;
        FragmentBuilder f(base);
        f.param((*c)[0] / (*c)[2]).nodes({a});
        if (square) f.param((*c)[1] / (*c)[2]).nodes({a}).op(Op::Mul);
        else f.param((*c)[1] / (*c)[2]);
        out.push_back(f.nodes({b}).op(Op::Add).op(Op::Mul).op(Op::Add).done());
      }
    }
    // p0 + p1 x y.
    if (auto c = least_squares({ones(n), times(u, w)}, s))
      out.push_back(FragmentBuilder(base).param((*c)[0]).nodes({x}).nodes({y}).op(Op::Mul)
                        .param((*c)[1]).op(Op::Mul).op(Op::Add).done());
    if (std::all_of(s.begin(), s.end(), [](double t) { return t >= 0; }) &&
        std::any_of(s.begin(), s.end(), [](double t) { return t > 0; })) {
      Column l(n);
      for (std::size_t r = 0; r < n; ++r) l[r] = s[r] > 0 ? std::log2(s[r]) : 0.0;
      if (auto c = least_squares({ones(n), u, w}, l, &s))
        out.push_back(FragmentBuilder(base).param((*c)[0]).nodes({x}).param((*c)[1]).op(Op::Mul)
                          .op(Op::Add).nodes({y}).param((*c)[2]).op(Op::Mul).op(Op::Add)
                          .op(Op::Exp2).done());
    }
  }
  return out;
}

// The cheapest of x, x simplified with its calls merged, with its parts regrouped, and with its
// per-material scales moved into exponentials; its cost in *cost. A form that is x again (often)
// is not costed again.
Expression cheapest_form(Expression x, const SearchOptions& options,
                         const std::vector<bool>& uniform, const SearchProblem& rows,
                         double* cost) {
  const auto same = [](const Expression& a, const Expression& b) {
    return a == b && a.parameter_values == b.parameter_values;
  };
  *cost = formula_cost(x, options);
  const Expression given = x;
  for (Expression y :
       {simplify(x, {.merge_calls = true}), grouped_factors(x, uniform),
        absorbed_scales(x, uniform, rows)}) {
    if (same(y, given) || same(y, x)) continue;
    const double c = formula_cost(y, options);
    if (c < *cost) {
      x = std::move(y);
      *cost = c;
    }
  }
  return x;
}

}  // namespace

namespace {

// The rows' loss of e for `loss`, of a e + b (a, b fitted by least squares) when `scaled`; +inf
// when e is not finite on the rows.
double loss_on_rows(const Expression& e, Loss loss, const SearchProblem& rows, bool scaled) {
  std::vector<const double*> cols;
  for (const Column& c : rows.inputs) cols.push_back(c.data());
  Column p(rows.target.size());
  evaluate(e, cols, p);
  if (!all_finite(p)) return HUGE_VAL;
  if (scaled)
    if (auto c = least_squares({ones(p.size()), p}, rows.target))
      for (double& v : p) v = (*c)[0] + (*c)[1] * v;
  const double l = loss_of(loss, p, rows.target, rows.weights);
  return std::isfinite(l) ? l : HUGE_VAL;
}

}  // namespace

double scaled_rows_loss(const Expression& e, Loss loss, const SearchProblem& rows) {
  return loss_on_rows(e, loss, rows, true);
}

double rows_loss(const Expression& e, Loss loss, const SearchProblem& rows) {
  return loss_on_rows(e, loss, rows, false);
}

SearchProblem descent_rows(const SearchProblem& problem, std::size_t count) {
  const std::size_t rows = problem.target.size();
  if (rows <= count) return problem;
  SearchProblem out;
  out.input_names = problem.input_names;
  out.inputs.resize(problem.inputs.size());
  for (std::size_t k = 0; k < count; ++k) {
    // Evenly spread, both ends kept.
    const std::size_t r = k * (rows - 1) / (count - 1);
    for (std::size_t c = 0; c < problem.inputs.size(); ++c)
      out.inputs[c].push_back(problem.inputs[c][r]);
    out.target.push_back(problem.target[r]);
    if (!problem.weights.empty()) out.weights.push_back(problem.weights[r]);
  }
  return out;
}

Expression with_shared_literal_parameters(const Expression& e) {
  const std::vector<std::uint64_t> hashes = subtree_hashes(e);
  std::vector<std::uint64_t> parent(e.nodes.size(), 0);
  for (std::size_t i = 0; i < e.nodes.size(); ++i) {
    std::size_t kids[3];
    e.child_indices(i, std::span<std::size_t>(kids, e.nodes[i].arity));
    for (std::size_t k = 0; k < e.nodes[i].arity; ++k) parent[kids[k]] = hashes[i] + k;
  }
  Expression r = e;
  std::map<std::pair<double, std::uint64_t>, int> shared;
  for (std::size_t i = 0; i < r.nodes.size(); ++i) {
    Node& n = r.nodes[i];
    if (n.op != Op::Const) continue;
    auto [it, fresh] =
        shared.emplace(std::make_pair(n.value, parent[i]), static_cast<int>(r.parameters.size()));
    if (fresh) {
      r.parameters.push_back("p" + std::to_string(r.parameters.size()));
      r.parameter_values.push_back(n.value);
    }
    n = Node::parameter(it->second);
  }
  r.update_lengths();
  return r;
}

std::vector<Expression> cheaper_rewrites(const Expression& e, const SearchOptions& options,
                                         const SearchProblem& rows,
                                         const std::function<bool()>& stop) {
  const double cost = formula_cost(e, options);
  std::vector<Expression> out;
  std::set<std::uint64_t> seen{structural_hash(e)};
  const auto keep_costed = [&](Expression x, double x_cost) {
    if (x.empty() || !(x_cost < cost)) return;
    if (seen.insert(structural_hash(x)).second) out.push_back(std::move(x));
  };
  const auto keep = [&](Expression x) {
    if (!x.empty()) keep_costed(x, formula_cost(x, options));
  };
  // Constants folded and calls merged, where that alone saves an instruction.
  keep(simplify(e, {.regroup_constants = true,
                    .merge_calls = true,
                    .cost = [&](const Expression& x) { return formula_cost(x, options); }}));
  // The rewrites of e as written and with its products regrouped (grouped_factors).
  const std::vector<bool> uniform = uniform_flags(e, options.uniform);
  const Expression grouped = grouped_factors(e, uniform);
  keep(grouped);
  std::set<std::uint64_t> done;
  for (const Expression* from : {&e, &grouped}) {
    const std::vector<std::uint64_t> hashes = subtree_hashes(*from);
    for (std::size_t i = from->nodes.size(); i-- > 0;) {
      const Node& n = from->nodes[i];
      if (n.arity == 0 || !done.insert(hashes[i]).second) continue;
      if (stop && stop()) return out;
      const Column s = subtree_values(*from, i, rows);
      if (!all_finite(s)) continue;
      for (const Fragment& f : replacements(*from, i, s, rows)) {
        Expression x = replace_all(*from, hashes, hashes[i], f);
        if (x.nodes.size() == 1 && x.nodes[0].op == Op::Param) continue;  // the root a constant
        double x_cost = 0;
        x = cheapest_form(std::move(x), options, uniform, rows, &x_cost);
        keep_costed(std::move(x), x_cost);
      }
    }
  }
  return out;
}

Expression cheapest_form(Expression e, const SearchOptions& options, const SearchProblem& rows) {
  const std::vector<bool> uniform = uniform_flags(e, options.uniform);
  double cost = 0;
  return cheapest_form(std::move(e), options, uniform, rows, &cost);
}

Expression random_rewrite(Rng& rng, const Expression& e, const SearchOptions& options,
                          const SearchProblem& rows) {
  std::vector<std::size_t> operators;
  for (std::size_t i = 0; i < e.nodes.size(); ++i)
    if (e.nodes[i].arity > 0) operators.push_back(i);
  if (operators.empty()) return {};
  const std::size_t i = operators[uniform_index(rng, operators.size())];
  const Column s = subtree_values(e, i, rows);
  if (!all_finite(s)) return {};
  const std::vector<Fragment> forms = replacements(e, i, s, rows);
  if (forms.empty()) return {};
  const std::vector<std::uint64_t> hashes = subtree_hashes(e);
  Expression x = replace_all(e, hashes, hashes[i], forms[uniform_index(rng, forms.size())]);
  if (x.nodes.size() == 1 && x.nodes[0].op == Op::Param) return {};
  double cost = 0;
  return cheapest_form(std::move(x), options, uniform_flags(e, options.uniform), rows, &cost);
}

}  // namespace shaderfit::search_detail
