#include "rational/remez.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace shaderfit::rational_detail {

using namespace shaderfit::rational;  // the area's public names

namespace {

void chebyshev_values(double s, int d, std::vector<double>& out) {
  out.resize(static_cast<std::size_t>(d) + 1);
  out[0] = 1.0;
  if (d >= 1) out[1] = s;
  for (int j = 2; j <= d; ++j) out[j] = 2 * s * out[j - 1] - out[j - 2];
}

// Monomial coefficients in t (lowest first, `size` entries) of T_j(alpha t + beta).
std::vector<double> chebyshev_in_t(int j, double alpha, double beta, int size) {
  std::vector<std::vector<double>> T = {{1.0}, {0.0, 1.0}};
  for (int k = 2; k <= j; ++k) {
    std::vector<double> next(static_cast<std::size_t>(k) + 1, 0.0);
    for (std::size_t i = 0; i < T[k - 1].size(); ++i) next[i + 1] += 2 * T[k - 1][i];
    for (std::size_t i = 0; i < T[k - 2].size(); ++i) next[i] -= T[k - 2][i];
    T.push_back(next);
  }
  // Horner in polynomials: sum_k c_k (alpha t + beta)^k.
  std::vector<double> out(static_cast<std::size_t>(size), 0.0);
  const std::vector<double>& c = T[static_cast<std::size_t>(j)];
  for (std::size_t k = c.size(); k-- > 0;) {
    std::vector<double> next(out.size(), 0.0);
    for (std::size_t i = 0; i < out.size(); ++i) {
      next[i] += beta * out[i];
      if (i + 1 < out.size()) next[i + 1] += alpha * out[i];
    }
    next[0] += c[k];
    out = next;
  }
  return out;
}

struct Setup {
  const Target* target;
  std::span<const double> params;
  Interval domain;
  bool relative = false;
  std::vector<int> pj, qj;  // Chebyshev indices of the P and Q bases
  double s_lo = -1, s_hi = 1;
  int parity = 0;          // -1 odd, +1 even (polynomials only)
  Eigen::MatrixXd cb;      // constraints in basis coordinates
  Eigen::MatrixXd mp, mq;  // basis -> monomials in t

  [[nodiscard]] double x_of(double s) const {
    return 0.5 * (domain.lo + domain.hi) + 0.5 * domain.width() * s;
  }
  [[nodiscard]] double f(double s) const { return target->value(x_of(s), params); }
  [[nodiscard]] double w(double fs) const { return relative ? 1.0 / std::abs(fs) : 1.0; }
  [[nodiscard]] int degree() const {
    return std::max(pj.empty() ? 0 : pj.back(), qj.empty() ? 0 : qj.back());
  }
};

struct Solution {
  Eigen::VectorXd a, b;
  double e = 0;
};

double basis_sum(const std::vector<int>& idx, const Eigen::VectorXd& c,
                 const std::vector<double>& t) {
  double s = 0;
  for (std::size_t j = 0; j < idx.size(); ++j) s += c(static_cast<Eigen::Index>(j)) * t[idx[j]];
  return s;
}

// Weighted error at s given f(s).
double error_at(const Setup& su, const Solution& sol, double s, double fs) {
  std::vector<double> t;
  chebyshev_values(s, su.degree(), t);
  return su.w(fs) * (fs - basis_sum(su.pj, sol.a, t) / basis_sum(su.qj, sol.b, t));
}

bool denominator_ok(const Setup& su, const Eigen::VectorXd& b) {
  std::vector<double> t;
  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  int sign = 0;
  for (int i = 0; i <= 512; ++i) {
    chebyshev_values(-1.0 + 2.0 * i / 512, su.degree(), t);
    const double q = basis_sum(su.qj, b, t);
    const int sg = q > 0 ? 1 : (q < 0 ? -1 : 0);
    if (sg == 0 || (sign != 0 && sg != sign)) return false;
    sign = sg;
    lo = std::min(lo, std::abs(q));
    hi = std::max(hi, std::abs(q));
  }
  return lo > 1e-9 * hi;
}

bool solve_reference(const Setup& su, const std::vector<double>& ref, Solution& sol) {
  const auto np = static_cast<Eigen::Index>(su.pj.size()),
             nq = static_cast<Eigen::Index>(su.qj.size());
  const Eigen::Index k = su.cb.rows(), nr = static_cast<Eigen::Index>(ref.size());
  std::vector<double> t;
  if (nq == 1) {  // polynomial: q0 = 1, unknowns a and E
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(np + 1, np + 1);
    Eigen::VectorXd rhs(np + 1);
    for (Eigen::Index i = 0; i < nr; ++i) {
      chebyshev_values(ref[i], su.degree(), t);
      const double fs = su.f(ref[i]);
      for (Eigen::Index j = 0; j < np; ++j) m(i, j) = t[su.pj[j]];
      m(i, np) = (i % 2 == 0 ? 1.0 : -1.0) / su.w(fs);
      rhs(i) = fs;
    }
    for (Eigen::Index r = 0; r < k; ++r) {
      m.row(nr + r).head(np) = su.cb.row(r).head(np);
      rhs(nr + r) = -su.cb(r, np);
    }
    Eigen::FullPivLU<Eigen::MatrixXd> lu(m);
    if (!lu.isInvertible()) return false;
    const Eigen::VectorXd x = lu.solve(rhs);
    sol.a = x.head(np);
    sol.b = Eigen::VectorXd::Ones(1);
    sol.e = x(np);
    return x.allFinite();
  }
  const Eigen::Index n = np + nq;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n), b = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < nr; ++i) {
    chebyshev_values(ref[i], su.degree(), t);
    const double fs = su.f(ref[i]);
    const double sw = (i % 2 == 0 ? 1.0 : -1.0) / su.w(fs);
    for (Eigen::Index j = 0; j < np; ++j) a(i, j) = t[su.pj[j]];
    for (Eigen::Index j = 0; j < nq; ++j) {
      a(i, np + j) = -fs * t[su.qj[j]];
      b(i, np + j) = sw * t[su.qj[j]];
    }
  }
  for (Eigen::Index r = 0; r < k; ++r) a.row(nr + r) = su.cb.row(r);
  // (A + E B) u = 0: E = -lambda for the pencil A u = lambda B u.
  Eigen::GeneralizedEigenSolver<Eigen::MatrixXd> ges(a, b, false);
  if (ges.info() != Eigen::Success) return false;
  std::vector<double> candidates;
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::complex<double> al = ges.alphas()(i);
    const double be = ges.betas()(i);
    if (std::abs(be) <= 1e-13 * (std::abs(al) + 1e-300)) continue;
    if (std::abs(al.imag()) > 1e-9 * std::abs(al)) continue;
    candidates.push_back(-al.real() / be);
  }
  std::sort(candidates.begin(), candidates.end(),
            [](double x, double y) { return std::abs(x) < std::abs(y); });
  for (double e : candidates) {
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(a + e * b, Eigen::ComputeFullV);
    const Eigen::VectorXd u = svd.matrixV().col(n - 1);
    const Eigen::VectorXd qb = u.tail(nq);
    if (!u.allFinite() || !denominator_ok(su, qb)) continue;
    sol.a = u.head(np);
    sol.b = qb;
    sol.e = e;
    return true;
  }
  return false;
}

// Local extrema of the error on the grid, refined by golden-section search.
std::vector<Extremum> find_extrema(const Setup& su, const Solution& sol,
                                   const std::vector<double>& grid, const std::vector<double>& fg) {
  const std::size_t g = grid.size();
  std::vector<double> e(g);
  for (std::size_t i = 0; i < g; ++i) e[i] = error_at(su, sol, grid[i], fg[i]);
  std::vector<Extremum> out;
  const double golden = 0.5 * (std::sqrt(5.0) - 1);
  for (std::size_t i = 0; i < g; ++i) {
    if (e[i] == 0.0 || !std::isfinite(e[i])) continue;
    const double sg = e[i] > 0 ? 1.0 : -1.0;
    if ((i > 0 && sg * e[i - 1] > sg * e[i]) || (i + 1 < g && sg * e[i + 1] > sg * e[i])) continue;
    double lo = grid[i > 0 ? i - 1 : i], hi = grid[i + 1 < g ? i + 1 : i];
    auto val = [&](double s) { return sg * error_at(su, sol, s, su.f(s)); };
    Extremum best{grid[i], e[i]};
    for (int it = 0; it < 60 && hi - lo > 1e-15; ++it) {
      const double c = hi - golden * (hi - lo), d = lo + golden * (hi - lo);
      if (val(c) > val(d))
        hi = d;
      else
        lo = c;
    }
    const double s = 0.5 * (lo + hi), v = val(s);
    if (v > sg * best.e) best = {s, sg * v};
    out.push_back(best);
  }
  return out;
}

std::vector<double> initial_reference(const Setup& su, std::size_t nr) {
  std::vector<double> r(nr);
  const double pi = std::numbers::pi;
  const double n = static_cast<double>(nr);
  for (std::size_t i = 0; i < nr; ++i) {
    const double k = static_cast<double>(i);
    if (su.parity < 0)
      r[i] = std::cos(pi * k / (2 * n - 1));
    else if (su.parity > 0)
      r[i] = nr == 1 ? 1.0 : std::cos(pi * k / (2 * n - 2));
    else if (su.cb.rows() > 0)
      r[i] = -std::cos(pi * (k + 0.5) / n);
    else
      r[i] = nr == 1 ? 0.0 : -std::cos(pi * k / (n - 1));
  }
  std::sort(r.begin(), r.end());
  return r;
}

// Odd (-1) or even (+1) target on a symmetric domain, 0 otherwise.
int detect_parity(const Setup& su) {
  const double c = 0.5 * (su.domain.lo + su.domain.hi);
  if (std::abs(c) > 1e-14 * su.domain.width()) return 0;
  bool odd = true, even = true;
  for (int i = 1; i <= 17; ++i) {
    const double x = su.domain.hi * i / 17.0;
    const double a = su.target->value(x, su.params), b = su.target->value(-x, su.params);
    const double tol = 1e-13 * (std::abs(a) + std::abs(b)) + 1e-300;
    odd = odd && std::abs(a + b) <= tol;
    even = even && std::abs(a - b) <= tol;
  }
  return odd ? -1 : (even ? 1 : 0);
}

}  // namespace

MinimaxOutcome remez(const Target& target, std::span<const double> params, Interval domain,
                     const RationalForm& form, const Eigen::MatrixXd& constraints, bool relative,
                     const MinimaxOptions& options) {
  MinimaxOutcome out;
  const int m = form.numerator_degree, n = form.denominator_degree;
  Setup su{&target, params, domain, relative};
  if (constraints.rows() == 0 && n == 0) su.parity = detect_parity(su);
  for (int j = 0; j <= m; ++j)
    if (su.parity == 0 || (j % 2 == 0) == (su.parity > 0)) su.pj.push_back(j);
  for (int j = 0; j <= n; ++j) su.qj.push_back(j);
  if (su.parity != 0) su.s_lo = 0.0;
  // s = alpha t + beta maps the form's variable onto [-1, 1].
  const Transform& tr = form.variable;
  const double alpha = 2.0 / (tr.scale * domain.width());
  const double beta = (-2.0 * tr.offset / tr.scale - domain.lo - domain.hi) / domain.width();
  su.mp = Eigen::MatrixXd::Zero(m + 1, static_cast<Eigen::Index>(su.pj.size()));
  su.mq = Eigen::MatrixXd::Zero(n + 1, n + 1);
  for (std::size_t j = 0; j < su.pj.size(); ++j) {
    const auto c = chebyshev_in_t(su.pj[j], alpha, beta, m + 1);
    for (int i = 0; i <= m; ++i)
      su.mp(i, static_cast<Eigen::Index>(j)) = c[static_cast<std::size_t>(i)];
  }
  for (int j = 0; j <= n; ++j) {
    const auto c = chebyshev_in_t(j, alpha, beta, n + 1);
    for (int i = 0; i <= n; ++i) su.mq(i, j) = c[static_cast<std::size_t>(i)];
  }
  Eigen::MatrixXd blocks = Eigen::MatrixXd::Zero(m + n + 2, su.mp.cols() + su.mq.cols());
  blocks.topLeftCorner(m + 1, su.mp.cols()) = su.mp;
  blocks.bottomRightCorner(n + 1, su.mq.cols()) = su.mq;
  su.cb = constraints.rows() ? Eigen::MatrixXd(constraints * blocks)
                             : Eigen::MatrixXd(0, blocks.cols());

  const std::size_t nr = su.pj.size() + su.qj.size() - static_cast<std::size_t>(constraints.rows());
  const int gsize = options.grid > 0
                        ? options.grid
                        : std::max(1000, 60 * static_cast<int>(su.pj.size() + su.qj.size()));
  std::vector<double> grid(static_cast<std::size_t>(gsize)), fg(grid.size());
  double fscale = 0;
  for (int i = 0; i < gsize; ++i) {
    const double u = 0.5 * (1 - std::cos(std::numbers::pi * i / (gsize - 1)));
    grid[i] = su.s_lo + (su.s_hi - su.s_lo) * u;
    fg[i] = su.f(grid[i]);
    if (relative && fg[i] == 0.0) {
      out.message = "relative minimax needs a target with no zero on the domain";
      return out;
    }
    fscale = std::max(fscale, std::abs(fg[i] * su.w(fg[i])));
  }
  // Rounding noise in the weighted error (f and the basis sums in double): below it the
  // alternation cannot level further.
  const double floor = 1e-15 * fscale;
  const double noise = 8 * std::numeric_limits<double>::epsilon() * fscale;
  double best_spread = std::numeric_limits<double>::infinity();
  int stalled = 0;

  std::vector<double> ref = initial_reference(su, nr);
  Solution sol;
  Equioscillation& eq = out.equioscillation;
  eq.relative = relative;
  eq.symmetric = su.parity != 0;
  out.status = FormStatus::NotConverged;
  for (int it = 1; it <= options.max_iterations; ++it) {
    if (!solve_reference(su, ref, sol)) {
      out.status = it == 1 ? FormStatus::Singular : FormStatus::NotConverged;
      out.message =
          n > 0 ? "no pole-free solution on the reference (iteration " + std::to_string(it) + ")"
                : "singular reference system (iteration " + std::to_string(it) + ")";
      if (it == 1) return out;
      break;
    }
    const std::vector<Extremum> cands = find_extrema(su, sol, grid, fg);
    double max_err = 0;
    for (const Extremum& c : cands) max_err = std::max(max_err, std::abs(c.e));
    eq.iterations = it;
    eq.levelled_error = std::abs(sol.e);
    eq.max_error = max_err;
    if (max_err <= 10 * floor) {  // exact up to rounding: nothing left to level
      eq.points = ref;
      eq.errors.assign(ref.size(), 0.0);
      eq.spread = 0;
      out.status = FormStatus::Ok;
      break;
    }
    const std::vector<Extremum> chosen = choose_reference(cands, nr);
    if (chosen.empty()) {
      out.message = "the error alternates at fewer than " + std::to_string(nr) + " points";
      break;
    }
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (const Extremum& c : chosen) {
      lo = std::min(lo, std::abs(c.e));
      hi = std::max(hi, std::abs(c.e));
    }
    eq.spread = (hi - lo) / hi;
    eq.points.clear();
    eq.errors.clear();
    for (const Extremum& c : chosen) {
      eq.points.push_back(c.s);
      eq.errors.push_back(c.e);
    }
    if (eq.spread <= std::max(options.tolerance, noise / max_err)) {
      out.status = FormStatus::Ok;
      break;
    }
    // Stalled at the rounding level: the spread stopped shrinking though it is already small.
    stalled = eq.spread < 0.9 * best_spread ? 0 : stalled + 1;
    best_spread = std::min(best_spread, eq.spread);
    if (stalled >= 4 && eq.spread < 1e-3) {
      out.status = FormStatus::Ok;
      break;
    }
    ref.clear();
    for (const Extremum& c : chosen) ref.push_back(c.s);
  }
  eq.converged = out.status == FormStatus::Ok;
  if (!eq.converged && out.message.empty())
    out.message = "no equioscillation after " + std::to_string(eq.iterations) +
                  " exchanges (spread " + std::to_string(eq.spread) + ")";
  // Alternation points in x; mirrored onto the other half for a symmetric solve.
  std::vector<std::pair<double, double>> pts;
  for (std::size_t i = 0; i < eq.points.size(); ++i) {
    pts.emplace_back(su.x_of(eq.points[i]), eq.errors[i]);
    if (su.parity != 0)
      pts.emplace_back(su.x_of(-eq.points[i]), su.parity < 0 ? -eq.errors[i] : eq.errors[i]);
  }
  std::sort(pts.begin(), pts.end());
  eq.points.clear();
  eq.errors.clear();
  for (const auto& [x, e] : pts) {
    eq.points.push_back(x);
    eq.errors.push_back(e);
  }
  // Back to monomials in the form's variable, q0 = 1.
  const Eigen::VectorXd p = su.mp * sol.a, q = su.mq * sol.b;
  if (!(std::abs(q(0)) > 1e-12 * q.cwiseAbs().maxCoeff())) {
    out.status = FormStatus::Failed;
    out.message = "the minimax denominator vanishes at " + form.variable.text("x") +
                  " = 0, so it cannot be normalised with q0 = 1 in this variable";
    return out;
  }
  out.rational.form = form;
  for (Eigen::Index i = 0; i <= m; ++i) out.rational.p.push_back(p(i) / q(0));
  for (Eigen::Index i = 0; i <= n; ++i) out.rational.q.push_back(q(i) / q(0));
  out.rational.q[0] = 1.0;
  return out;
}

}  // namespace shaderfit::rational_detail
