// Internals of solve_fixed_form shared by its translation units: the prepared model and blocks,
// constraint rows, constraint elimination and rank-checked least-squares solves.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "shaderfit/fit/fixed_form.hpp"
#include "shaderfit/fit/least_squares.hpp"

namespace shaderfit::fit_detail {

enum class FailureKind { none, contradiction, singular, nonfinite, no_rows, not_linear, too_large };

struct Failure {
  FailureKind kind = FailureKind::none;
  std::string message;
  explicit operator bool() const { return kind != FailureKind::none; }
};

// A constraint resolved for one block: the point's value for every formula variable and the
// value the right-hand side takes there.
struct ConstraintInstance {
  const Constraint* constraint = nullptr;
  std::size_t index = 0;      // in Model::constraints
  std::vector<double> point;  // one per formula variable (Kind::value, Kind::derivative)
  double target = 0;
};

struct Model {
  Expression formula;  // the user's formula, parameter order = everywhere else
  Expression fitted;   // the quantity residuals compare: formula, T(formula) or log2(formula)
  std::optional<Expression>
      transform;  // T over "y" and formula variables (log2(y) for the log loss)
  std::vector<std::string> fitted_columns;  // = fitted.variables; each is a formula variable
  std::vector<Constraint> constraints;
  // For each Kind::derivative constraint: the formula with the differentiated variable turned
  // into an extra parameter (index = parameter count), so its Jacobian column is df/dv.
  std::vector<Expression> derivative_forms;
  std::vector<bool> constraint_linear;
  std::vector<ParameterScope> scopes;
  Loss loss = Loss::Mse;
  bool linear = false;               // the fitted quantity is linear in the parameters
  bool structurally_linear = false;  // ... and that was proven symbolically, not sampled
  std::size_t parameters() const { return formula.parameters.size(); }
};

struct PreparedBlock {
  const FitBlock* block = nullptr;
  std::vector<const double*> columns;  // one per fitted.variables entry
  std::vector<double> target;          // in the fitted space
  std::vector<double> weights;         // never empty
  std::vector<ConstraintInstance> constraints;
  std::size_t rows() const { return target.size(); }
};

// Values (rows) and Jacobian (column-major, rows x parameters) of the fitted quantity.
struct Linearization {
  std::vector<double> values, jacobian;
};
void linearize(const Model& m, const PreparedBlock& b, std::span<const double> p,
               Linearization* out);
// Fitted-space values only.
void values(const Model& m, const PreparedBlock& b, std::span<const double> p,
            std::vector<double>* out);

// Loss of residuals values - target with per-row weights (Loss::MaxAbs: max w |r|; otherwise the
// weighted mean square). Infinite when a weighted residual is not finite.
double fit_cost(Loss loss, std::span<const double> values, std::span<const double> target,
                std::span<const double> weights);

// c(p) = lhs(p) - rhs and its gradient over the block's parameters.
void constraint_row(const Model& m, const ConstraintInstance& c, std::span<const double> p,
                    double* value, std::span<double> gradient);

// Linear equality constraints C p = d, written p = p0 + Z q over the free parameters by
// Gauss-Jordan elimination with pivoting. A row that reduces to 0 = nonzero contradicts the rows
// before it; one that reduces to 0 = 0 is redundant and dropped.
struct Elimination {
  Eigen::VectorXd p0;
  Eigen::MatrixXd Z;      // parameters x free
  std::vector<int> free;  // the free parameters (Z's identity rows)
};
Failure eliminate(const Eigen::MatrixXd& C, const Eigen::VectorXd& d,
                  std::span<const std::string> row_names, double tolerance, Elimination* out);

// min || A q - b || with A's columns scaled to unit length and checked for rank; a dependent
// column names the parameter (column_names) the data do not determine.
Failure solve_design(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                     std::span<const std::string> column_names, double rank_tolerance,
                     Eigen::VectorXd* q);

// H q = rhs for a symmetric positive semidefinite H (normal equations), rank-checked after
// symmetric diagonal scaling (pivots below rank_tolerance^2 of the largest are dependent).
Failure solve_normal(const Eigen::MatrixXd& H, const Eigen::VectorXd& rhs,
                     std::span<const std::string> column_names, double rank_tolerance,
                     Eigen::VectorXd* q);

// The Levenberg-Marquardt settings of the block and coupled solvers.
LeastSquaresOptions lm_options(const FixedFormOptions& o);

// Moves p onto the constraints (Gauss-Newton on c(p) = 0, minimum-norm steps). Failure when
// they cannot be met.
Failure project(const Model& m, const PreparedBlock& b, const FixedFormOptions& o,
                std::vector<double>* p);

// Solves one block on its own (every parameter is the block's). Used when there are no global
// parameters, or a single block.
// *kind (when given) says how it failed.
BlockResult solve_block(const Model& m, const PreparedBlock& b, const FixedFormOptions& o,
                        std::span<const double> start, FailureKind* kind = nullptr);

// Solves all blocks jointly: global parameters shared, per-block ones per block. A failure of
// the joint system fails every block (returned in *failure).
std::vector<BlockResult> solve_coupled(const Model& m, std::span<const PreparedBlock> blocks,
                                       const FixedFormOptions& o,
                                       std::span<const std::vector<double>> starts,
                                       Failure* failure);

// The one choice of solver, for a single block (block_solver.cpp) and for coupled blocks
// (coupled_solver.cpp) alike. The max-abs loss runs Lawson's reweighting (`lawson`), each of
// whose steps is a weighted least-squares solve; every other loss is one least-squares solve in
// the fitted space. A least-squares solve is linear (exact in one step) when the model is and the
// options allow it; otherwise, or when the linear solve finds the block not linear after all,
// Levenberg-Marquardt, unless the options ask for the linear solver alone, which then fails.
struct SolverChoice {
  bool minimax = false;      // Lawson's reweighting around least-squares solves
  bool try_linear = false;   // a least-squares solve tries the linear solve first
  bool linear_only = false;  // ... and fails rather than fall back to Levenberg-Marquardt

  static SolverChoice of(const Model& m, const FixedFormOptions& o) {
    return {m.loss == Loss::MaxAbs, m.linear && o.solver != SolverKind::levenberg_marquardt,
            o.solver == SolverKind::linear};
  }
  // The loss the solver minimises (and the initial and final costs are stated in).
  [[nodiscard]] Loss loss() const { return minimax ? Loss::MaxAbs : Loss::Mse; }

  // One least-squares solve: `linear()` and `levenberg_marquardt()` each return a Failure.
  template <typename Linear, typename LevenbergMarquardt>
  Failure least_squares(Linear&& linear, LevenbergMarquardt&& levenberg_marquardt) const {
    if (try_linear) {
      Failure f = linear();
      if (f.kind != FailureKind::not_linear) return f;
      if (linear_only)
        return {FailureKind::not_linear,
                "the fitted quantity is not linear in the parameters (use the LM solver)"};
    }
    return levenberg_marquardt();
  }
};

// Lawson's reweighting for Loss::MaxAbs over rows with weights w (minimax.cpp). `solve` runs a
// least-squares solve with the given per-row weights, `residuals` writes |r| per row at its
// solution, `keep` remembers the current solution as the best so far, `restore` returns to it.
struct LawsonSteps {
  std::function<Failure(std::span<const double>)> solve;
  std::function<void(std::vector<double>*)> residuals;
  std::function<void()> keep, restore;
};
Failure lawson(std::span<const double> w, int iterations, const LawsonSteps& steps,
               std::string* termination);

// Residual statistics (rms, max |r|) of a block at p, in the fitted space.
void residual_stats(const Model& m, const PreparedBlock& b, std::span<const double> p,
                    BlockResult* r);

}  // namespace shaderfit::fit_detail
