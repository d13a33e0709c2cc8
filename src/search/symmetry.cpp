#include "shaderfit/search/symmetry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "shaderfit/core/error.hpp"
#include "shaderfit/search/options.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {

namespace {

constexpr std::size_t kMinPairs = 8;

struct Pairs {
  std::vector<std::pair<std::size_t, std::size_t>> mirrored;  // (row with -x, row with x), x > 0
  std::vector<std::size_t> zero;                              // rows with x = 0
};

// The rows of `problem` matched in mirrored pairs in input k, or nullopt when some row has no
// mirror or two rows are alike.
std::optional<Pairs> mirrored_pairs(const SearchProblem& problem, std::size_t k) {
  const auto& inputs = problem.inputs;
  const std::vector<double>& x = inputs[k];
  // Cheap first: as many rows below 0 as above (most data fails here, before any sorting).
  const auto below = std::count_if(x.begin(), x.end(), [](double v) { return v < 0; });
  const auto above = std::count_if(x.begin(), x.end(), [](double v) { return v > 0; });
  if (below != above || static_cast<std::size_t>(below) < kMinPairs) return std::nullopt;
  std::vector<std::size_t> order(x.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  // By the other inputs, then |x|, then x: a row and its mirror end up side by side.
  auto less = [&](std::size_t a, std::size_t b) {
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      if (i == k) continue;
      if (inputs[i][a] != inputs[i][b]) return inputs[i][a] < inputs[i][b];
    }
    if (std::abs(x[a]) != std::abs(x[b])) return std::abs(x[a]) < std::abs(x[b]);
    return x[a] < x[b];
  };
  std::sort(order.begin(), order.end(), less);
  auto same_rest = [&](std::size_t a, std::size_t b) {
    for (std::size_t i = 0; i < inputs.size(); ++i)
      if (i != k && inputs[i][a] != inputs[i][b]) return false;
    return true;
  };
  Pairs p;
  std::size_t j = 0;
  while (j < order.size()) {
    const std::size_t a = order[j];
    if (x[a] == 0) {
      if (j + 1 < order.size() && x[order[j + 1]] == 0 && same_rest(a, order[j + 1]))
        return std::nullopt;  // two rows alike
      p.zero.push_back(a);
      j += 1;
      continue;
    }
    if (j + 1 >= order.size()) return std::nullopt;
    const std::size_t b = order[j + 1];
    if (!(x[a] < 0 && x[b] == -x[a] && same_rest(a, b))) return std::nullopt;
    if (j + 2 < order.size() && same_rest(b, order[j + 2]) && std::abs(x[order[j + 2]]) == x[b])
      return std::nullopt;  // a third row at +-x
    p.mirrored.emplace_back(a, b);
    j += 2;
  }
  return p;
}

// The kind, m and sign (DataSymmetry) of the target on the pairs, or nullopt.
std::optional<SymmetryKind> target_symmetry(const SearchProblem& problem, const Pairs& p,
                                            double tolerance, double* center, int* sign) {
  const std::vector<double>& y = problem.target;
  const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
  const double tol = tolerance * (*hi - *lo);
  if (!(tol > 0)) return std::nullopt;  // a constant target
  auto all_pairs = [&](auto ok) {
    return std::all_of(p.mirrored.begin(), p.mirrored.end(),
                       [&](const auto& ab) { return ok(y[ab.first], y[ab.second]); });
  };
  auto all_zero = [&](auto ok) {
    return std::all_of(p.zero.begin(), p.zero.end(), [&](std::size_t r) { return ok(y[r]); });
  };
  *center = 0;
  *sign = 1;
  // The sign of y - m on the half (x > 0: the pairs' second rows; x = 0, where it is ~0).
  auto half_sign = [&](double m) {
    auto all_half = [&](auto ok) {
      return std::all_of(p.mirrored.begin(), p.mirrored.end(),
                         [&](const auto& ab) { return ok(y[ab.second] - m); });
    };
    if (all_half([&](double t) { return t >= -tol; })) return 1;
    if (all_half([&](double t) { return t <= tol; })) return -1;
    return 0;
  };
  if (all_pairs([&](double n, double q) { return std::abs(n - q) <= tol; }))
    return SymmetryKind::Even;
  if (all_pairs([&](double n, double q) { return std::abs(n + q) <= tol; }) &&
      all_zero([&](double v) { return std::abs(v) <= tol; })) {
    *sign = half_sign(0);
    return SymmetryKind::Odd;
  }
  // m: the target at x = 0 where the data has it (acos(0) = pi/2 to the last bit), else the
  // mean of the pairs' midpoints (as offsets from the first, to keep the rounding small).
  const auto& zero = p.zero;
  const double base =
      zero.empty() ? 0.5 * (y[p.mirrored[0].first] + y[p.mirrored[0].second]) : y[zero[0]];
  double sum = 0;
  if (zero.empty())
    for (const auto& [n, q] : p.mirrored) sum += 0.5 * (y[n] + y[q]) - base;
  else
    for (std::size_t r : zero) sum += y[r] - base;
  const double m = base + sum / static_cast<double>(zero.empty() ? p.mirrored.size() : zero.size());
  if (all_pairs([&](double n, double q) { return std::abs(n + q - 2 * m) <= tol; }) &&
      all_zero([&](double v) { return std::abs(v - m) <= tol; })) {
    *center = m;
    *sign = half_sign(m);
    return SymmetryKind::Point;
  }
  return std::nullopt;
}

bool weights_mirrored(const SearchProblem& problem, const Pairs& p) {
  if (problem.weights.empty()) return true;
  const std::vector<double>& w = problem.weights;
  return std::all_of(p.mirrored.begin(), p.mirrored.end(), [&](const auto& ab) {
    return std::abs(w[ab.first] - w[ab.second]) <= 1e-12 * std::max(w[ab.first], w[ab.second]);
  });
}

}  // namespace

std::string_view symmetry_kind_name(SymmetryKind kind) {
  switch (kind) {
    case SymmetryKind::Even: return "even";
    case SymmetryKind::Odd: return "odd";
    case SymmetryKind::Point: return "point";
  }
  return "even";
}

std::optional<SymmetryKind> symmetry_kind_from_name(std::string_view name) {
  for (SymmetryKind k : {SymmetryKind::Even, SymmetryKind::Odd, SymmetryKind::Point})
    if (symmetry_kind_name(k) == name) return k;
  return std::nullopt;
}

std::optional<DataSymmetry> search_symmetry(const SearchOptions& options,
                                            const SearchProblem& problem) {
  if (!options.symmetry) return std::nullopt;
  const bool ratio_loss =
      options.loss == Loss::Relative || options.loss == Loss::MaxRel || options.loss == Loss::Log;
  if (!ratio_loss) return detect_symmetry(problem);
  const std::optional<DataSymmetry> s = detect_symmetry(problem);
  return s.has_value() && s->kind == SymmetryKind::Point ? std::nullopt : s;
}

std::optional<DataSymmetry> detect_symmetry(const SearchProblem& problem, double tolerance) {
  for (std::size_t k = 0; k < problem.inputs.size(); ++k) {
    const std::optional<Pairs> p = mirrored_pairs(problem, k);
    if (!p || p->mirrored.size() < kMinPairs || !weights_mirrored(problem, *p)) continue;
    double center = 0;
    int sign = 1;
    if (const auto kind = target_symmetry(problem, *p, tolerance, &center, &sign))
      return DataSymmetry{k, problem.input_names[k], *kind, center, sign};
  }
  return std::nullopt;
}

SearchProblem symmetric_half(const SearchProblem& problem, const DataSymmetry& symmetry) {
  SearchProblem half;
  half.input_names = problem.input_names;
  half.inputs.resize(problem.inputs.size());
  const std::vector<double>& x = problem.inputs[symmetry.input];
  for (std::size_t r = 0; r < x.size(); ++r) {
    if (!(x[r] >= 0)) continue;
    for (std::size_t i = 0; i < problem.inputs.size(); ++i)
      half.inputs[i].push_back(problem.inputs[i][r]);
    const double y = problem.target[r];
    half.target.push_back(symmetry.kind == SymmetryKind::Odd && symmetry.sign < 0 ? -y : y);
    if (!problem.weights.empty()) half.weights.push_back(problem.weights[r]);
  }
  return half;
}

namespace {

// g's nodes with `input_names` as variables and |x| for x, but for the leaf at `keep` (and x
// under an even integer power or abs, which ignore its sign).
Expression with_abs_input(const Expression& g, const DataSymmetry& symmetry,
                          const std::vector<std::string>& input_names,
                          std::size_t keep = static_cast<std::size_t>(-1)) {
  Expression e;
  e.variables = input_names;
  e.parameters = g.parameters;
  e.parameter_values = g.parameter_values;
  const int x = static_cast<int>(symmetry.input);
  for (std::size_t k = 0; k < g.size(); ++k) {
    const Node& n = g.nodes[k];
    if (n.op != Op::Var) {
      e.nodes.push_back(n);
      continue;
    }
    const auto at = std::find(input_names.begin(), input_names.end(),
                              g.variables.at(static_cast<std::size_t>(n.index)));
    if (at == input_names.end())
      throw Error("the formula names '" + g.variables[static_cast<std::size_t>(n.index)] +
                      "', which is not an input",
                  {"reflect_expression"});
    const int i = static_cast<int>(at - input_names.begin());
    e.nodes.push_back(Node::variable(i));
    // No |x| where the next node (whose operand this leaf is) ignores x's sign already.
    const bool sign_free =
        k + 1 < g.size() && ((g.nodes[k + 1].op == Op::IPow && g.nodes[k + 1].index % 2 == 0) ||
                             g.nodes[k + 1].op == Op::Abs);
    if (i == x && !sign_free && k != keep) e.nodes.push_back(Node::op_node(Op::Abs));
  }
  return e;
}

bool is_input(const Expression& g, const Node& n, const DataSymmetry& symmetry) {
  return n.op == Op::Var &&
         g.variables.at(static_cast<std::size_t>(n.index)) == symmetry.input_name;
}

}  // namespace

Expression reflect_expression(const Expression& g, const DataSymmetry& symmetry,
                              const std::vector<std::string>& input_names) {
  Expression e = with_abs_input(g, symmetry, input_names);
  const int x = static_cast<int>(symmetry.input);
  const bool point = symmetry.kind == SymmetryKind::Point;
  const auto op = [&](Op o) { e.nodes.push_back(Node::op_node(o)); };
  const auto center = [&] { e.nodes.push_back(Node::constant(symmetry.center)); };
  if (symmetry.kind == SymmetryKind::Even) {
    e.update_lengths();
    return e;
  }
  if (point) {  // the value relative to m: G - m, or m - G where y <= m on the half
    if (symmetry.sign < 0) {
      e.nodes.insert(e.nodes.begin(), Node::constant(symmetry.center));
    } else {
      center();
    }
    op(Op::Sub);
  }
  e.nodes.push_back(Node::variable(x));
  if (symmetry.sign == 0) {  // H * sign(x)
    op(Op::Sign);
    op(Op::Mul);
  } else {  // copysign(H, x), or copysign(H, -x) for odd data negative on the half
    if (symmetry.sign < 0 && !point) op(Op::Neg);
    op(Op::CopySign);
  }
  if (point) {  // m + that, or m - that
    e.nodes.insert(e.nodes.begin(), Node::constant(symmetry.center));
    op(symmetry.sign < 0 ? Op::Sub : Op::Add);
  }
  e.update_lengths();
  return e;
}

Expression unreflected_expression(const Expression& g, const DataSymmetry& symmetry) {
  Expression e = g;
  if (symmetry.kind == SymmetryKind::Odd && symmetry.sign < 0) {
    e.nodes.push_back(Node::op_node(Op::Neg));
    e.update_lengths();
  }
  return e;
}

std::optional<Expression> factored_expression(const Expression& g, const DataSymmetry& symmetry,
                                              const std::vector<std::string>& input_names) {
  if (symmetry.kind != SymmetryKind::Odd || g.size() < 3) return std::nullopt;
  const std::size_t root = g.size() - 1;
  const Op op = g.nodes[root].op;
  const std::size_t right = root - 1;  // the right operand's root; the left one ends before it
  const bool left_leaf = g.nodes[right].length + 3 == g.size();  // the left operand is node 0
  std::size_t keep;
  if ((op == Op::Mul || op == Op::Div) && left_leaf && is_input(g, g.nodes[0], symmetry))
    keep = 0;
  else if (op == Op::Mul && g.nodes[right].length == 0 && is_input(g, g.nodes[right], symmetry))
    keep = right;
  else
    return std::nullopt;
  Expression e = with_abs_input(g, symmetry, input_names, keep);
  e.update_lengths();
  return unreflected_expression(e, symmetry);
}

std::string describe_symmetry(const DataSymmetry& symmetry) {
  const std::string& x = symmetry.input_name;
  switch (symmetry.kind) {
    case SymmetryKind::Even: return "even in " + x;
    case SymmetryKind::Odd: return "odd in " + x;
    case SymmetryKind::Point:
      return fmt::format("point-symmetric in {} about {}", x, symmetry.center);
  }
  return {};
}

}  // namespace shaderfit
