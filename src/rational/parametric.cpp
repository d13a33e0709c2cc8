#include "shaderfit/rational/parametric.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/expr/simplify.hpp"

namespace shaderfit::rational {

namespace {

double poly(const std::vector<double>& c, double x) {
  double s = 0;
  for (std::size_t i = c.size(); i-- > 0;) s = s * x + c[i];
  return s;
}

// The closest fraction with a denominator up to 24 when within 1e-10 relative, else v.
double snap(double v) {
  for (int d = 1; d <= 24; ++d) {
    const double n = std::round(v * d);
    if (std::abs(v * d - n) <= 1e-10 * std::max(1.0, std::abs(v * d))) return n / d;
  }
  return v;
}

struct Fraction {
  std::vector<double> a, b;  // numerator and denominator coefficients in the parameter
};

double deviation(const Fraction& f, const std::vector<double>& th, const std::vector<double>& c) {
  double worst = 0;
  for (std::size_t i = 0; i < th.size(); ++i)
    worst = std::max(worst, std::abs(poly(f.a, th[i]) / poly(f.b, th[i]) - c[i]));
  return std::isfinite(worst) ? worst : std::numeric_limits<double>::infinity();
}

// a(theta) - c b(theta) = 0 in the least-squares sense: the right singular vector of the
// smallest singular value, scaled so that b's first nonzero coefficient is 1.
Fraction fit_fraction(const std::vector<double>& th, const std::vector<double>& c, int da, int db) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(th.size()), da + db + 2);
  for (std::size_t i = 0; i < th.size(); ++i) {
    double p = 1;
    for (int j = 0; j <= std::max(da, db); ++j, p *= th[i]) {
      if (j <= da) m(static_cast<Eigen::Index>(i), j) = p;
      if (j <= db) m(static_cast<Eigen::Index>(i), da + 1 + j) = -c[i] * p;
    }
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(m, Eigen::ComputeFullV);
  const Eigen::VectorXd v = svd.matrixV().col(m.cols() - 1);
  Fraction f;
  f.a.assign(v.data(), v.data() + da + 1);
  f.b.assign(v.data() + da + 1, v.data() + da + db + 2);
  double lead = 0;
  for (double x : f.b)
    if (std::abs(x) > 1e-8 * v.cwiseAbs().maxCoeff()) {
      lead = x;
      break;
    }
  if (lead == 0) return f;
  for (double& x : f.a) x /= lead;
  for (double& x : f.b) x /= lead;
  return f;
}

// A law for one coefficient, or found = false.
CoefficientLaw find_law(const std::string& name, const std::string& parameter,
                        const std::vector<double>& fit_t, const std::vector<double>& fit_c,
                        const std::vector<double>& chk_t, const std::vector<double>& chk_c,
                        const ParametricOptions& o) {
  CoefficientLaw law;
  law.coefficient = name;
  double scale = 1;
  for (double v : fit_c) scale = std::max(scale, 1 + std::abs(v));
  const double tol = o.tolerance * scale;
  double best = std::numeric_limits<double>::infinity();
  for (int total = 0; total <= o.max_degree && !law.found; ++total) {
    for (int db = 0; db <= total && !law.found; ++db) {
      const int da = total - db;
      if (static_cast<int>(fit_t.size()) < da + db + 2) continue;
      Fraction f = fit_fraction(fit_t, fit_c, da, db);
      double dev = std::max(deviation(f, fit_t, fit_c), deviation(f, chk_t, chk_c));
      best = std::min(best, dev);
      if (!(dev <= tol)) continue;
      Fraction s = f;
      for (double& x : s.a) x = snap(x);
      for (double& x : s.b) x = snap(x);
      const double sdev = std::max(deviation(s, fit_t, fit_c), deviation(s, chk_t, chk_c));
      if (sdev <= tol) {
        f = s;
        dev = sdev;
      }
      for (double& x : f.a)
        if (std::abs(x) < 1e-12) x = 0;
      for (double& x : f.b)
        if (std::abs(x) < 1e-12) x = 0;
      Rational r;
      r.form = {da, db, Transform::identity()};
      r.p = f.a;
      r.q = f.b;
      law.expression = r.to_expression(parameter);
      law.law = to_infix(law.expression);
      law.max_deviation = dev;
      law.found = true;
    }
  }
  if (!law.found)
    law.law =
        fmt::format("not a rational function of {} of degree {} or less (closest within {:.2g})",
                    parameter, o.max_degree, best);
  return law;
}

// sum law_i t^i as text, t the form's variable.
std::string polynomial_text(const std::vector<const CoefficientLaw*>& laws, const std::string& t) {
  std::string s;
  for (std::size_t i = 0; i < laws.size(); ++i) {
    if (laws[i]->law == "0") continue;
    std::string term = "(" + laws[i]->law + ")";
    if (i >= 1) term += " * (" + t + ")" + (i > 1 ? "^" + std::to_string(i) : "");
    s += (s.empty() ? "" : " + ") + term;
  }
  return s.empty() ? "0" : s;
}

// The approximation with its coefficients replaced by their laws, over {variable, parameter}.
Expression law_formula(const std::vector<CoefficientLaw>& laws, const RationalForm& form,
                       const std::string& var, const std::string& parameter) {
  const std::string t = form.variable.text(var);
  std::vector<const CoefficientLaw*> pl, ql;
  static const CoefficientLaw one = [] {
    CoefficientLaw c;
    c.law = "1";
    return c;
  }();
  for (const CoefficientLaw& c : laws) (c.coefficient[0] == 'p' ? pl : ql).push_back(&c);
  if (ql.size() == static_cast<std::size_t>(form.denominator_degree)) ql.insert(ql.begin(), &one);
  std::string text = polynomial_text(pl, t);
  if (form.denominator_degree > 0) text = "(" + text + ") / (" + polynomial_text(ql, t) + ")";
  ParseOptions opts;
  opts.variables = {var, parameter};
  return simplify(parse_formula(text, opts));
}

struct Normalised {
  std::vector<CoefficientLaw> laws;
  bool all_found = true;
};

// Laws for the coefficients divided by coefficient `lead` (none: as solved, q0 = 1 left out).
Normalised normalise(const std::vector<std::vector<double>>& fit_c,
                     const std::vector<std::vector<double>>& chk_c, int m, int n,
                     std::optional<std::size_t> lead, const std::string& parameter,
                     const std::vector<double>& fit_t, const std::vector<double>& chk_t,
                     const ParametricOptions& po) {
  Normalised out;
  for (int i = 0; i <= m + n + 1; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if ((!lead && i == m + 1) || (lead && k == *lead)) continue;  // the coefficient that is 1
    auto column = [&](const std::vector<std::vector<double>>& set) {
      std::vector<double> c;
      c.reserve(set.size());
      for (const auto& row : set) c.push_back(lead ? row[k] / row[*lead] : row[k]);
      return c;
    };
    const std::string name = i <= m ? "p" + std::to_string(i) : "q" + std::to_string(i - m - 1);
    out.laws.push_back(find_law(name, parameter, fit_t, column(fit_c), chk_t, column(chk_c), po));
    out.all_found = out.all_found && out.laws.back().found;
  }
  if (lead) {  // list the coefficient fixed at 1 too, so the formula can be rebuilt
    CoefficientLaw one;
    one.coefficient = "p" + std::to_string(*lead);
    one.found = true;
    one.law = "1";
    one.expression.nodes = {Node::constant(1.0)};
    out.laws.insert(out.laws.begin() + static_cast<std::ptrdiff_t>(*lead), one);
  }
  return out;
}

}  // namespace

bool ParametricOptions::is_valid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (fit_values < 2 || check_values < 1)
    return fail("need at least 2 fit values and 1 check value");
  if (max_degree < 0 || max_degree > 8) return fail("max_degree must be in [0, 8]");
  if (!(tolerance > 0)) return fail("tolerance must be positive");
  return true;
}

std::vector<ParametricLaw> parametric_laws(const RationalOptions& options,
                                           const RationalProblem& problem,
                                           const std::string& parameter, Interval range,
                                           const std::vector<RationalForm>& forms,
                                           const ParametricOptions& po) {
  std::string why;
  if (!po.is_valid(&why)) throw Error("invalid parametric options: " + why);
  const auto it =
      std::find(problem.parameter_names.begin(), problem.parameter_names.end(), parameter);
  if (it == problem.parameter_names.end())
    throw Error("no parameter named " + parameter, {"RationalProblem::parameter_names"});
  if (!(range.lo < range.hi))
    throw Error("the parameter range is empty", {"RationalProblem::parameter_values"});
  const auto index = static_cast<std::size_t>(it - problem.parameter_names.begin());
  // Fit on Chebyshev points of the range, check on points between them.
  std::vector<double> fit_t, chk_t;
  for (int i = 0; i < po.fit_values; ++i)
    fit_t.push_back(range.lo + range.width() * 0.5 *
                                   (1 - std::cos(std::numbers::pi * i / (po.fit_values - 1))));
  for (int i = 0; i < po.check_values; ++i)
    chk_t.push_back(range.lo + range.width() * (i + 0.5) / po.check_values * 0.98 +
                    0.01 * range.width());

  std::vector<ParametricLaw> out;
  for (const RationalForm& form : forms) {
    ParametricLaw law;
    law.form = form;
    const int m = form.numerator_degree, n = form.denominator_degree;
    // Per parameter value: p0..pm, q0..qn (q0 = 1 as solved).
    std::vector<std::vector<double>> fit_c, chk_c;
    law.usable = true;
    for (int pass = 0; pass < 2 && law.usable; ++pass) {
      for (double t : pass == 0 ? fit_t : chk_t) {
        RationalProblem p = problem;
        p.parameter_values[index] = t;
        const FormResult r = solve_form(options, p, form);
        if (!r.usable()) {
          law.usable = false;
          law.note = fmt::format("{} at {} = {}: {}", form_status_name(r.status), parameter,
                                 format_number(t), r.message);
          break;
        }
        std::vector<double> c = r.rational.p;
        c.insert(c.end(), r.rational.q.begin(), r.rational.q.end());
        (pass == 0 ? fit_c : chk_c).push_back(c);
      }
    }
    if (law.usable) {
      // Two normalisations: q0 = 1 as solved, and the numerator's lowest nonzero coefficient = 1
      // (Schlick writes v / (k + (1 - k) v) rather than (v / k) / (1 + (1 - k) / k v)). The one
      // whose laws are all found and smallest is kept.
      std::optional<std::size_t> lead;
      for (int i = 0; i <= m && !lead; ++i) {
        bool nonzero = true;
        for (const auto* set : {&fit_c, &chk_c})
          for (const auto& c : *set)
            nonzero = nonzero && std::abs(c[static_cast<std::size_t>(i)]) > 1e-9;
        if (nonzero) lead = static_cast<std::size_t>(i);
      }
      std::vector<Normalised> options_n = {
          normalise(fit_c, chk_c, m, n, std::nullopt, parameter, fit_t, chk_t, po)};
      if (lead && n > 0)
        options_n.push_back(normalise(fit_c, chk_c, m, n, lead, parameter, fit_t, chk_t, po));
      // Keep the normalisation whose whole formula is smallest.
      const Normalised* best = &options_n.front();
      Expression best_e;
      for (const Normalised& c : options_n) {
        if (!c.all_found) continue;
        Expression e = law_formula(c.laws, form, problem.target.variable(), parameter);
        if (!best->all_found || best_e.empty() || e.size() < best_e.size()) {
          best = &c;
          best_e = std::move(e);
        }
      }
      law.coefficients = best->laws;
      law.all_rational = best->all_found;
      if (law.all_rational) {
        law.expression = best_e;
        law.formula = to_infix(best_e);
      }
    }
    out.push_back(std::move(law));
  }
  return out;
}

}  // namespace shaderfit::rational
