// The per-cell fits of the FV tables, as one fixed-form problem with per-cell parameters A, B, C.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fv_internal.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/fit/fixed_form.hpp"
#include "shaderfit/fit/linear.hpp"
#include "shaderfit/reference/smith_ggx.hpp"

namespace shaderfit::lut_detail {

using namespace shaderfit::lut;  // the area's public names

namespace {

Expression fv_formula() {
  ParseOptions po;
  po.variables = {"f0", "x"};
  po.parameters = {"A", "B", "C"};
  return parse_formula("f0 * exp2(A*x^2 + B*x + C)", po);
}

// The cell's samples: angles at the midpoints of fit_samples intervals over [0, max angle].
// Returns an empty string, or why the reference cannot be fitted here.
std::string fill_block(const FvLutOptions& o, FvVariant v, const FvReference& ref,
                       const CellSpec& c, FitBlock* b) {
  const std::size_t m = o.fit_samples;
  const double top = max_angle_degrees(o, v, c.roughness) * std::numbers::pi / 180;
  b->label = c.label();
  b->columns.assign(2, std::vector<double>(m));
  b->target.resize(m);
  b->context = {{"f0", c.f0}, {"roughness", c.roughness}};
  for (std::size_t k = 0; k < m; ++k) {
    const double theta = top * (static_cast<double>(k) + 0.5) / static_cast<double>(m);
    const double d = std::cos(theta);
    const double y = ref(d, c.f0, c.roughness);
    if (!(y > 0) || !std::isfinite(y))
      return fmt::format("the reference is {} at dot(L,H) = {}", y, format_number(d));
    b->columns[0][k] = c.f0;
    b->columns[1][k] = 1 - d;
    b->target[k] = y;
  }
  return {};
}

}  // namespace

std::string CellSpec::label() const {
  return fmt::format("cell ({}, {}) roughness={} f0={}", i, j, format_number(roughness),
                     format_number(f0));
}

std::vector<CellSpec> square_grid(std::size_t size) {
  std::vector<CellSpec> out;
  out.reserve(size * size);
  for (std::size_t j = 0; j < size; ++j)
    for (std::size_t i = 0; i < size; ++i)
      out.push_back({i, j, cell_roughness(i, size), cell_f0(j, size)});
  return out;
}

double max_angle_degrees(const FvLutOptions& o, FvVariant v, double roughness) {
  return v == FvVariant::clamped ? clamp_angle_degrees(o, roughness) : 90.0;
}

std::vector<FvCell> fit_cells(const FvLutOptions& o, FvVariant v, const FvReference& ref,
                              std::span<const CellSpec> cells, const EndpointAdjustment& adjustment,
                              ProgressCounter& progress) {
  std::vector<FvCell> out(cells.size());
  if (v == FvVariant::endpoint) {
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const double alpha = cells[k].roughness * cells[k].roughness;
      out[k].a = adjustment(cells[k].roughness) * std::log2(4 / (alpha * alpha * cells[k].f0));
      out[k].ok = std::isfinite(out[k].a);
      if (!out[k].ok) out[k].failure = "log2(V90 / f0) is not finite";
    }
    progress.add(cells.size());
    return out;
  }
  std::vector<FitBlock> all(cells.size());
  parallel_for(
      cells.size(), 64,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
          out[k].failure = fill_block(o, v, ref, cells[k], &all[k]);
          out[k].ok = out[k].failure.empty();
        }
      },
      o.threads);
  FixedFormProblem p;
  p.formula = fv_formula();
  p.scopes.assign(3, ParameterScope::per_block);
  if (variant_is_constrained(v)) p.constraints.push_back(parse_constraint("C = 0", p.formula));
  std::vector<std::size_t> index;  // block -> cell
  for (std::size_t k = 0; k < cells.size(); ++k)
    if (out[k].ok) {
      index.push_back(k);
      p.blocks.push_back(std::move(all[k]));
    }
  all.clear();
  progress.add(cells.size() - p.blocks.size());  // failed before the fit
  if (p.blocks.empty()) return out;
  FixedFormOptions fo;
  fo.loss = Loss::Log;  // the seed's log2(FV / f0) = A x^2 + B x + C
  fo.solver = SolverKind::linear;
  fo.threads = o.threads;
  // The fit's block counts, one call at a time, passed on as cells.
  std::size_t fitted = 0;
  fo.on_progress = [&](const Progress& q) {
    if (q.done > fitted) progress.add(q.done - fitted);
    fitted = std::max(fitted, q.done);
  };
  FixedFormSummary s;
  solve_fixed_form(fo, p, &s);
  for (std::size_t b = 0; b < index.size(); ++b) {
    FvCell& c = out[index[b]];
    const BlockResult& r = s.blocks[b];
    c.ok = r.ok;
    c.failure = r.failure;
    if (r.ok) {
      c.a = r.parameters[0];
      c.b = r.parameters[1];
      c.c = r.parameters[2];
    }
  }
  return out;
}

}  // namespace shaderfit::lut_detail

namespace shaderfit::lut {

std::array<double, 2> fit_fv_constrained(double roughness, double f0) {
  if (!(roughness > 0 && roughness <= 1))
    throw Error("roughness must be in (0, 1], got " + std::to_string(roughness), {"roughness"});
  if (!(f0 > 0 && f0 < 1)) throw Error("F0 must be in (0, 1), got " + std::to_string(f0), {"f0"});
  const double alpha = roughness * roughness;
  constexpr int kSamples = 256;
  std::vector<double> x2(kSamples), x1(kSamples), y(kSamples);
  for (int s = 0; s < kSamples; ++s) {
    const double x = (s + 0.5) / kSamples;
    x2[s] = x * x;
    x1[s] = x;
    y[s] = std::log2(reference::fv_lh(1 - x, f0, alpha) / f0);
  }
  const double* cols[] = {x2.data(), x1.data()};
  const std::vector<double> c = solve_least_squares(cols, y);
  return {c[0], c[1]};
}

}  // namespace shaderfit::lut
