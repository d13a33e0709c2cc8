#include "search/starts/polynomial_starts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "search/evolution/constant_fit.hpp"
#include "shaderfit/fit/linear.hpp"

namespace shaderfit::search_detail {

namespace {

// A polynomial's shape: y ~ c + x^first * sum_k a_k (x^step)^k, k = 0 .. terms - 1.
struct Shape {
  bool constant;  // c is a term of its own (a point-symmetric centre)
  int first;      // 0 or 1
  int step;       // 1 or 2
  int terms;
};

std::string number(double v) { return fmt::format("{:.17g}", v); }

// "a0 + u * (a1 + u * (a2))" with u = x0 or x0^2, times x0 when first is 1, plus c.
std::string horner_text(const Shape& s, const std::vector<double>& c) {
  const std::string u = s.step == 1 ? "x0" : "x0^2";
  const std::size_t base = s.constant ? 1 : 0;
  std::string text = number(c[base + static_cast<std::size_t>(s.terms) - 1]);
  for (int k = s.terms - 2; k >= 0; --k)
    text = number(c[base + static_cast<std::size_t>(k)]) + " + " + u + " * (" + text + ")";
  if (s.first == 1) text = "x0 * (" + text + ")";
  if (s.constant) text = number(c[0]) + " + " + text;
  return text;
}

// At most kPolynomialRows rows of a one-input problem, evenly spread over ascending x, with the
// first and the last.
SearchProblem sorted_spread_rows(const SearchProblem& p) {
  const std::vector<double>& x = p.inputs[0];
  std::vector<std::size_t> order(x.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return x[a] < x[b]; });
  const std::size_t rows = order.size(), n = std::min(rows, kPolynomialRows);
  SearchProblem s;
  s.input_names = p.input_names;
  s.inputs.assign(1, {});
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = order[n == 1 ? 0 : k * (rows - 1) / (n - 1)];
    s.inputs[0].push_back(x[i]);
    s.target.push_back(p.target[i]);
    if (!p.weights.empty()) s.weights.push_back(p.weights[i]);
  }
  return s;
}

}  // namespace

std::vector<std::string> polynomial_starts(const SearchProblem& problem,
                                           const std::optional<DataSymmetry>& symmetry, Loss loss) {
  if (problem.inputs.size() != 1 || problem.target.empty()) return {};
  const SearchProblem rows = sorted_spread_rows(problem);
  const std::vector<double>& x = rows.inputs[0];
  const std::vector<double>& y = rows.target;
  const std::size_t n = x.size();
  // The rows' weights for the loss: minimax ones, or those of the least squares in its terms
  // (rel, and log to first order, weigh by 1 / y^2).
  const bool minimax = fits_minimax(loss);
  std::vector<double> w = minimax ? minimax_weights(loss, y, rows.weights) : rows.weights;
  if (!minimax && (loss == Loss::Relative || loss == Loss::Log)) {
    w.resize(n, 1.0);
    for (std::size_t r = 0; r < n; ++r) w[r] = y[r] != 0 ? w[r] / (y[r] * y[r]) : 0;
  }

  std::vector<Shape> shapes;
  for (int d = 2; d <= kPolynomialMaxDegree; ++d) shapes.push_back({false, 0, 1, d + 1});
  if (symmetry && symmetry->input == 0)
    for (int t = 2; t <= kSymmetricMaxTerms; ++t) switch (symmetry->kind) {
        case SymmetryKind::Even: shapes.push_back({false, 0, 2, t}); break;
        case SymmetryKind::Odd: shapes.push_back({false, 1, 2, t}); break;
        case SymmetryKind::Point: shapes.push_back({true, 1, 2, t}); break;
      }

  // The fit's error in the loss's terms on the rows read: max w |r| for minimax, sum w r^2.
  const auto fit_error = [&](const std::vector<const double*>& columns) {
    const std::vector<double> c =
        minimax ? solve_minimax_linear(columns, y, w, kPolynomialMinimaxIterations)
                : solve_least_squares(columns, y, w);
    double error = 0;
    for (std::size_t r = 0; r < n; ++r) {
      double g = 0;
      for (std::size_t j = 0; j < columns.size(); ++j) g += c[j] * columns[j][r];
      const double e = (w.empty() ? 1.0 : w[r]) * std::abs(g - y[r]);
      error = minimax ? std::max(error, e) : error + e * std::abs(g - y[r]);
    }
    return std::make_pair(c, error);
  };
  // A polynomial that does not halve the best constant's error explains nothing the front
  // needs (x^16 from 1e-32 under the rel loss: every fit is ~0).
  const std::vector<double> ones(n, 1.0);
  const double constant_error = fit_error({ones.data()}).second;

  std::vector<std::string> out;
  for (const Shape& s : shapes) {
    const std::size_t count = static_cast<std::size_t>(s.terms) + (s.constant ? 1 : 0);
    if (count >= n) continue;  // no more constants than rows
    std::vector<std::vector<double>> columns;
    if (s.constant) columns.emplace_back(n, 1.0);
    for (int k = 0; k < s.terms; ++k) {
      std::vector<double> col(n);
      for (std::size_t r = 0; r < n; ++r) {
        double v = s.first == 1 ? x[r] : 1.0;
        for (int p = 0; p < k * s.step; ++p) v *= x[r];
        col[r] = v;
      }
      columns.push_back(std::move(col));
    }
    std::vector<const double*> pointers;
    for (const auto& col : columns) pointers.push_back(col.data());
    const auto [c, error] = fit_error(pointers);
    if (!std::all_of(c.begin(), c.end(), [](double v) { return std::isfinite(v); })) continue;
    if (!(error <= kPolynomialMinGain * constant_error)) continue;
    out.push_back(horner_text(s, c));
  }
  return out;
}

}  // namespace shaderfit::search_detail
