// Building the blocks of a fixed-form fit: sampling a domain (per cell of a grid over
// conditioning variables), derived columns, and splitting a data set by group or by grid cell.
//
//   GridAxis r = parse_grid_axis("roughness=0:1:16", "grid");       // 16 cells, centres
//   GridAxis f = parse_grid_axis("f0=0:1:16:sqrt", "grid");         // centres in sqrt(f0)
//   SampleAxis t = parse_sample_axis("theta=0:1.5707963:90", "domain");  // 90 midpoints
//   Definition d = parse_definition("dot_lh = cos(theta)", {"theta"}, "define");
//   Rng rng(1);
//   std::vector<GridCell> cells = sample_grid({r, f}, {t}, {d}, 0, rng);
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

namespace shaderfit {

enum class Spacing { midpoints, endpoints };

// A sampled variable: `count` points over [lo, hi], at the midpoints of equal intervals (never
// the ends) or from lo to hi inclusive.
struct SampleAxis {
  std::string name;
  double lo = 0, hi = 1;
  std::size_t count = 0;
  Spacing spacing = Spacing::midpoints;
  [[nodiscard]] double at(std::size_t i) const;
};

// A conditioning variable divided into `cells` equal cells over [lo, hi]; with sqrt_spaced the
// cells are equal in sqrt(value) (seed 002's F0 axis) and lo, hi must be >= 0.
struct GridAxis {
  std::string name;
  double lo = 0, hi = 1;
  std::size_t cells = 0;
  bool sqrt_spaced = false;
  [[nodiscard]] double centre(std::size_t i) const;
  // The cell holding value v, or -1 outside [lo, hi].
  [[nodiscard]] long cell_of(double v) const;
};

// "name=lo:hi:count[:midpoints|endpoints]". Throws Error located at `source` for a bad shape, a
// number that does not parse, lo >= hi, or a count of zero.
SampleAxis parse_sample_axis(std::string_view text, const std::string& source);
// "name=lo:hi:cells[:sqrt]". Throws as above (a grid size of zero is an error).
GridAxis parse_grid_axis(std::string_view text, const std::string& source);

// A derived column: name = formula over earlier columns.
struct Definition {
  std::string name;
  Expression formula;
};
// "name = formula"; the formula may use the names in `known` only.
Definition parse_definition(std::string_view text, const std::vector<std::string>& known,
                            const std::string& source);

struct GridCell {
  std::vector<std::size_t> index;                      // per grid axis
  std::vector<std::pair<std::string, double>> centre;  // grid variable = cell centre
  Dataset data;  // the samples: grid variables (constant), domain axes, definitions
  [[nodiscard]] std::string label() const;  // "roughness=0.03125 f0=0.0009765625"
};

// Every cell of the grid (one cell when there are no grid axes), in row-major order with the last
// axis fastest. A cell holds the Cartesian product of the domain axes, or, when random_samples > 0,
// that many points uniform in the axes' [lo, hi] boxes (drawn cell by cell, axis by axis, from
// rng). Definitions are then evaluated in order.
std::vector<GridCell> sample_grid(const std::vector<GridAxis>& grid,
                                  const std::vector<SampleAxis>& domain,
                                  const std::vector<Definition>& definitions,
                                  std::size_t random_samples, Rng& rng);

// Adds the definitions' columns to a data set, in order.
void add_definitions(Dataset& data, const std::vector<Definition>& definitions);

// A block from the rows `rows` of `data` (every row when empty): the formula's variables read from
// the columns of the same names, the target and the weights (empty: all 1) taken at those rows.
FitBlock make_block(const Dataset& data, const Expression& formula, std::span<const double> target,
                    std::span<const double> weights, std::span<const std::size_t> rows,
                    std::string label);

}  // namespace shaderfit
