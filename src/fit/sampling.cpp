#include "shaderfit/fit/sampling.hpp"

#include <charconv>
#include <cmath>

#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"

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

double number(const std::string& field, const std::string& source) {
  // Constant expressions (pi/2, 85*pi/180) as well as plain numbers.
  ParseOptions po;
  po.variables = {"__none__"};
  po.source = source;
  double v = 0;
  try {
    v = evaluate_scalar(parse_formula(field, po), std::vector<double>{0.0});
  } catch (const Error& e) {
    fail("'" + field + "' is not a number: " + e.message(), source);
  }
  if (!std::isfinite(v)) fail("'" + field + "' is not a finite number", source);
  return v;
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

double SampleAxis::at(std::size_t i) const {
  const double n = static_cast<double>(count);
  if (spacing == Spacing::endpoints)
    return count == 1 ? 0.5 * (lo + hi) : lo + (hi - lo) * static_cast<double>(i) / (n - 1);
  return lo + (hi - lo) * (static_cast<double>(i) + 0.5) / n;
}

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

SampleAxis parse_sample_axis(std::string_view text, const std::string& source) {
  const Spec s = split_spec(text, source, "name=lo:hi:count[:midpoints|endpoints]");
  SampleAxis a{s.name, number(s.fields[0], source), number(s.fields[1], source),
               count(s.fields[2], source, "sample count")};
  check_range(a.name, a.lo, a.hi, source);
  if (s.fields.size() == 4) {
    if (s.fields[3] == "endpoints")
      a.spacing = Spacing::endpoints;
    else if (s.fields[3] != "midpoints")
      fail("unknown spacing '" + s.fields[3] + "' (midpoints, endpoints)", source);
  }
  return a;
}

GridAxis parse_grid_axis(std::string_view text, const std::string& source) {
  const Spec s = split_spec(text, source, "name=lo:hi:cells[:sqrt]");
  GridAxis g{s.name, number(s.fields[0], source), number(s.fields[1], source),
             count(s.fields[2], source, "grid size")};
  check_range(g.name, g.lo, g.hi, source);
  if (s.fields.size() == 4) {
    if (s.fields[3] != "sqrt") fail("unknown grid spacing '" + s.fields[3] + "' (sqrt)", source);
    if (g.lo < 0) fail("a sqrt-spaced axis needs lo >= 0", source);
    g.sqrt_spaced = true;
  }
  return g;
}

Definition parse_definition(std::string_view text, const std::vector<std::string>& known,
                            const std::string& source) {
  const std::size_t eq = text.find('=');
  if (eq == std::string_view::npos)
    fail("expected 'name = formula', got '" + std::string(text) + "'", source);
  Definition d;
  d.name = std::string(text.substr(0, eq));
  while (!d.name.empty() && d.name.back() == ' ') d.name.pop_back();
  while (!d.name.empty() && d.name.front() == ' ') d.name.erase(d.name.begin());
  if (d.name.empty()) fail("a definition needs a name before '='", source);
  ParseOptions po;
  po.variables = known;
  po.source = source;
  d.formula = parse_formula(text.substr(eq + 1), po);
  d.formula.drop_unused_variables();
  return d;
}

void add_definitions(Dataset& data, const std::vector<Definition>& definitions) {
  for (const Definition& d : definitions)
    data.add_numeric(d.name, evaluate_on(d.formula, data, {.threads = 1}));
}

std::string GridCell::label() const {
  std::string s;
  for (const auto& [name, v] : centre) s += (s.empty() ? "" : " ") + name + "=" + format_number(v);
  return s.empty() ? "all" : s;
}

std::vector<GridCell> sample_grid(const std::vector<GridAxis>& grid,
                                  const std::vector<SampleAxis>& domain,
                                  const std::vector<Definition>& definitions,
                                  std::size_t random_samples, Rng& rng) {
  std::size_t cells = 1, points = random_samples;
  for (const GridAxis& g : grid) cells *= g.cells;
  if (random_samples == 0) {
    points = 1;
    for (const SampleAxis& a : domain) points *= a.count;
  }
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
    std::vector<std::vector<double>> cols(domain.size(), std::vector<double>(points));
    for (std::size_t i = 0; i < points; ++i) {
      std::size_t r = i;
      for (std::size_t k = domain.size(); k-- > 0;) {
        if (random_samples > 0) continue;
        cols[k][i] = domain[k].at(r % domain[k].count);
        r /= domain[k].count;
      }
      if (random_samples > 0)
        for (std::size_t k = 0; k < domain.size(); ++k)
          cols[k][i] = uniform(rng, domain[k].lo, domain[k].hi);
    }
    for (std::size_t k = 0; k < domain.size(); ++k)
      cell.data.add_numeric(domain[k].name, std::move(cols[k]));
    add_definitions(cell.data, definitions);
  }
  return out;
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
