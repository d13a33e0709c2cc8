#include "shaderfit/fit/fit_blocks.hpp"

#include <charconv>
#include <cmath>

#include "shaderfit/core/error.hpp"
#include "shaderfit/data/sampling.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/reference/language.hpp"

namespace shaderfit {

namespace {

[[noreturn]] void fail(const std::string& message, const std::string& source) {
  throw Error(message, SourceLocation{source});
}

struct Spec {
  std::string name;
  std::vector<std::string> fields;
};

// "name=a:b:c[:d]" into the name and the fields.
Spec split_spec(std::string_view text, const std::string& source, const char* shape) {
  const std::size_t eq = text.find('=');
  if (eq == std::string_view::npos || eq == 0)
    fail("expected '" + std::string(shape) + "', got '" + std::string(text) + "'", source);
  Spec s;
  s.name = std::string(text.substr(0, eq));
  while (!s.name.empty() && s.name.back() == ' ') s.name.pop_back();
  std::string_view rest = text.substr(eq + 1);
  while (true) {
    const std::size_t c = rest.find(':');
    std::string f(rest.substr(0, c));
    while (!f.empty() && f.front() == ' ') f.erase(f.begin());
    while (!f.empty() && f.back() == ' ') f.pop_back();
    s.fields.push_back(f);
    if (c == std::string_view::npos) break;
    rest.remove_prefix(c + 1);
  }
  if (s.fields.size() < 3 || s.fields.size() > 4)
    fail("expected '" + std::string(shape) + "', got '" + std::string(text) + "'", source);
  return s;
}

// lo < hi, and hi - lo a finite double, so that positions along the axis are finite too.
void check_range(const std::string& name, double lo, double hi, const std::string& source) {
  if (!(lo < hi)) fail("the range of '" + name + "' is empty: lo must be below hi", source);
  if (!std::isfinite(hi - lo)) fail("the range of '" + name + "' is too wide for a double", source);
}

std::size_t count(const std::string& field, const std::string& source, const char* what) {
  long long v = -1;
  const auto r = std::from_chars(field.data(), field.data() + field.size(), v);
  if (r.ec != std::errc() || r.ptr != field.data() + field.size() || v < 0)
    fail(std::string(what) + " '" + field + "' is not a whole number", source);
  if (v == 0) fail(std::string(what) + " must be at least 1, got 0", source);
  return static_cast<std::size_t>(v);
}

}  // namespace

double GridAxis::centre(std::size_t i) const {
  const double t = (static_cast<double>(i) + 0.5) / static_cast<double>(cells);
  if (!sqrt_spaced) return lo + (hi - lo) * t;
  const double s = std::sqrt(lo) + (std::sqrt(hi) - std::sqrt(lo)) * t;
  return s * s;
}

long GridAxis::cell_of(double v) const {
  if (!(v >= lo && v <= hi)) return -1;
  // Halves, so that a range wider than the largest double (-1e308 to 1e308) still gives t in
  // [0, 1]; halving is exact, so ordinary ranges give the same t as (v - lo) / (hi - lo).
  const double t = sqrt_spaced ? (std::sqrt(v) - std::sqrt(lo)) / (std::sqrt(hi) - std::sqrt(lo))
                               : (0.5 * v - 0.5 * lo) / (0.5 * hi - 0.5 * lo);
  // Clamped as a double before the conversion: converting NaN (an infinite bound set in code) or
  // a value out of range to long is undefined.
  const double c = t * static_cast<double>(cells);
  if (!(c >= 0)) return 0;
  if (c >= static_cast<double>(cells - 1)) return static_cast<long>(cells) - 1;
  return static_cast<long>(c);
}

GridAxis parse_grid_axis(std::string_view text, const std::string& source) {
  const Spec s = split_spec(text, source, "name=lo:hi:cells[:sqrt]");
  // Bounds are constants of the reference language (pi/2, 85*pi/180), as a domain's are.
  GridAxis g{s.name, reference::evaluate_constant(s.fields[0], source),
             reference::evaluate_constant(s.fields[1], source),
             count(s.fields[2], source, "grid size")};
  check_range(g.name, g.lo, g.hi, source);
  if (s.fields.size() == 4) {
    if (s.fields[3] != "sqrt") fail("unknown grid spacing '" + s.fields[3] + "' (sqrt)", source);
    if (g.lo < 0) fail("a sqrt-spaced axis needs lo >= 0", source);
    g.sqrt_spaced = true;
  }
  return g;
}

std::string GridCell::label() const {
  std::string s;
  for (const auto& [name, v] : centre) s += (s.empty() ? "" : " ") + name + "=" + format_number(v);
  return s.empty() ? "all" : s;
}

std::vector<GridCell> sample_grid(const std::vector<GridAxis>& grid,
                                  const std::vector<reference::DomainAxis>& domain,
                                  std::size_t samples, std::size_t random_samples, Rng& rng,
                                  const SourceLocation& where) {
  std::size_t cells = 1;
  for (const GridAxis& g : grid) cells *= g.cells;
  // The design is the same in every cell: sampled once.
  SampleColumns design;
  if (random_samples == 0 && !domain.empty()) design = sample_domain(domain, samples, 1, where);
  const std::size_t points =
      random_samples > 0 ? random_samples : (design.empty() ? 1 : design.front().size());
  std::vector<GridCell> out(cells);
  for (std::size_t c = 0; c < cells; ++c) {
    GridCell& cell = out[c];
    cell.index.resize(grid.size());
    std::size_t rest = c;
    for (std::size_t k = grid.size(); k-- > 0;) {
      cell.index[k] = rest % grid[k].cells;
      rest /= grid[k].cells;
    }
    cell.data.source = "samples";
    for (std::size_t k = 0; k < grid.size(); ++k) {
      const double v = grid[k].centre(cell.index[k]);
      cell.centre.emplace_back(grid[k].name, v);
      cell.data.add_numeric(grid[k].name, std::vector<double>(points, v));
    }
    if (random_samples > 0) {
      std::vector<std::vector<double>> cols(domain.size(), std::vector<double>(points));
      for (std::size_t i = 0; i < points; ++i)
        for (std::size_t k = 0; k < domain.size(); ++k)
          cols[k][i] = uniform(rng, domain[k].lo, domain[k].hi);
      for (std::size_t k = 0; k < domain.size(); ++k)
        cell.data.add_numeric(domain[k].name, std::move(cols[k]));
    } else {
      for (std::size_t k = 0; k < domain.size(); ++k)
        cell.data.add_numeric(domain[k].name, c + 1 == cells ? std::move(design[k]) : design[k]);
    }
  }
  return out;
}

std::vector<double> add_program_columns(Dataset& data, const reference::Program& program) {
  std::vector<std::span<const double>> inputs;
  for (const std::string& name : program.inputs) inputs.emplace_back(data.numeric(name).values);
  // A program without inputs gives one row; the data may have any number.
  const std::size_t rows = data.rows();
  std::vector<std::vector<double>> outputs;
  if (inputs.empty()) {
    outputs = program.evaluate_columns({});
    for (std::vector<double>& o : outputs) o.assign(rows, o.front());
  } else {
    outputs = program.evaluate_columns(inputs);
  }
  std::vector<double> reference;
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    const std::string& name = program.output_names[k];
    if (name == reference::kReferenceOutput)
      reference = std::move(outputs[k]);
    else if (program.find_input(name) < 0)
      data.add_numeric(name, std::move(outputs[k]));
  }
  return reference;
}

FitBlock make_block(const Dataset& data, const Expression& formula, std::span<const double> target,
                    std::span<const double> weights, std::span<const std::size_t> rows,
                    std::string label) {
  FitBlock b;
  b.label = std::move(label);
  const std::size_t n = rows.empty() ? data.rows() : rows.size();
  auto row = [&](std::size_t i) { return rows.empty() ? i : rows[i]; };
  for (const std::string& v : formula.variables) {
    const std::vector<double>& col = data.numeric(v).values;
    std::vector<double> c(n);
    for (std::size_t i = 0; i < n; ++i) c[i] = col[row(i)];
    b.columns.push_back(std::move(c));
  }
  b.target.resize(n);
  for (std::size_t i = 0; i < n; ++i) b.target[i] = target[row(i)];
  if (!weights.empty()) {
    b.weights.resize(n);
    for (std::size_t i = 0; i < n; ++i) b.weights[i] = weights[row(i)];
  }
  return b;
}

}  // namespace shaderfit
