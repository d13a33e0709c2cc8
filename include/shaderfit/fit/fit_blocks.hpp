// Building the blocks of a fixed-form fit: sampling a domain per cell of a grid over conditioning
// variables, derived columns computed by a reference program, and splitting a data set by group
// or by grid cell.
//
//   GridAxis r = parse_grid_axis("roughness=0:1:16", "grid");            // 16 cells, centres
//   GridAxis f = parse_grid_axis("f0=0:1:16:sqrt", "grid");              // centres in sqrt(f0)
//   reference::DomainAxis t = reference::parse_domain_axis("theta=0:pi/2:90", "domain");
//   Rng rng(1);
//   std::vector<GridCell> cells = sample_grid({r, f}, {t}, 0, 0, rng);  // 90 midpoints a cell
//   reference::Program p = reference::compile_reference(
//       {.formula = "0", .variables = {"roughness", "f0", "theta"},
//        .definitions = {"dot_lh = cos(theta)"}});
//   add_program_columns(cells[0].data, p);                               // adds dot_lh
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "shaderfit/core/random.hpp"
#include "shaderfit/data/dataset.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/fit/fixed_form.hpp"
#include "shaderfit/reference/domain.hpp"
#include "shaderfit/reference/program.hpp"

namespace shaderfit {

// A conditioning variable divided into `cells` equal cells over [lo, hi]; with sqrt_spaced the
// cells are equal in sqrt(value) (finer near 0, as an F0 axis wants) and lo, hi must be >= 0.
struct GridAxis {
  std::string name;
  double lo = 0, hi = 1;
  std::size_t cells = 0;
  bool sqrt_spaced = false;
  [[nodiscard]] double centre(std::size_t i) const;
  // The cell holding value v, or -1 outside [lo, hi].
  [[nodiscard]] long cell_of(double v) const;
};

// "name=lo:hi:cells[:sqrt]". Throws Error located at `source` for a bad shape, a number that does
// not parse, lo >= hi, or a grid size of zero.
GridAxis parse_grid_axis(std::string_view text, const std::string& source);

struct GridCell {
  std::vector<std::size_t> index;                      // per grid axis
  std::vector<std::pair<std::string, double>> centre;  // grid variable = cell centre
  Dataset data;  // the samples: grid variables (constant), then the domain's variables
  [[nodiscard]] std::string label() const;  // "roughness=0.03125 f0=0.0009765625"
};

// Every cell of the grid (one cell when there are no grid axes), in row-major order with the last
// axis fastest. Each cell holds the same samples of the domain: sample_domain(domain, samples)
// (data/sampling.hpp: the Cartesian product of the axes' regular grids when every axis has a
// count, else the default design), or, when random_samples > 0, that many points uniform in the
// axes' [lo, hi] boxes, drawn cell by cell, axis by axis, from rng. Without domain axes a cell
// has one row. Throws sample_domain's errors, located at `where`.
std::vector<GridCell> sample_grid(const std::vector<GridAxis>& grid,
                                  const std::vector<reference::DomainAxis>& domain,
                                  std::size_t samples, std::size_t random_samples, Rng& rng,
                                  const SourceLocation& where = {"domain"});

// Adds to `data` the outputs of `program` (reference/program.hpp) that are neither its inputs nor
// its reference (reference/language.hpp's kReferenceOutput): the definitions, in order, each
// evaluated on every row with the program's inputs read from the numeric columns of the same
// names. Returns the reference output's values (empty when the program has none). Throws as
// Dataset::numeric for a missing or text column, and as Dataset::add_numeric for a name taken.
std::vector<double> add_program_columns(Dataset& data, const reference::Program& program);

// A block from the rows `rows` of `data` (every row when empty): the formula's variables read from
// the columns of the same names, the target and the weights (empty: all 1) taken at those rows.
FitBlock make_block(const Dataset& data, const Expression& formula, std::span<const double> target,
                    std::span<const double> weights, std::span<const std::size_t> rows,
                    std::string label);

}  // namespace shaderfit
