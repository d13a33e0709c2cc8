// Baking the FV tables: options, variants, the endpoint adjustment, and the parallel bake.
#include "shaderfit/lut/fv_lut.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "fv_internal.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/fit/fixed_form.hpp"

namespace shaderfit::lut {

namespace {

constexpr std::array<std::string_view, 4> kNames = {"endpoint", "linear", "constrained", "clamped"};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

FvTable bake_table(const FvLutOptions& o, FvVariant v, const lut_detail::FvReference& ref,
                   std::span<const lut_detail::CellSpec> cells, EndpointAdjustment* adjustment,
                   ProgressCounter& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  FvTable t;
  t.variant = v;
  t.size = o.size;
  if (v == FvVariant::endpoint) *adjustment = derive_endpoint_adjustment(o);
  t.cells = lut_detail::fit_cells(o, v, ref, cells, *adjustment, progress);
  const std::size_t n = cells.size();
  t.texels.resize(4 * n);
  t.texels_half.resize(4 * n);
  t.errors.resize(n);
  t.errors_half.resize(n);
  const std::vector<double> cosines = lut_detail::eval_cosines(o);
  parallel_for(
      n, 64,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
          lut_detail::fold_texel(t.cells[k], cells[k].f0, &t.texels[4 * k], &t.texels_half[4 * k]);
          if (t.cells[k].ok)
            lut_detail::texel_errors(ref, cosines, cells[k], &t.texels[4 * k],
                                     &t.texels_half[4 * k], &t.errors[k], &t.errors_half[k]);
        }
      },
      o.threads);
  for (std::size_t k = 0; k < n; ++k)
    if (!t.cells[k].ok) t.failures.push_back(cells[k].label() + ": " + t.cells[k].failure);
  for (std::size_t k = 0; k < n; ++k) {
    if (!t.cells[k].ok) continue;
    t.f0_deviation =
        std::max(t.f0_deviation, lut_detail::f0_deviation(&t.texels[4 * k], cells[k].f0));
    t.f0_deviation_half =
        std::max(t.f0_deviation_half, lut_detail::f0_deviation(&t.texels_half[4 * k], cells[k].f0));
  }
  t.summary = lut_detail::summarize(t.errors, t.cells);
  t.summary_half = lut_detail::summarize(t.errors_half, t.cells);
  t.seconds = seconds_since(t0);
  return t;
}

}  // namespace

std::string_view variant_name(FvVariant v) { return kNames[static_cast<std::size_t>(v)]; }

std::optional<FvVariant> parse_variant(std::string_view name) {
  for (std::size_t k = 0; k < kNames.size(); ++k)
    if (kNames[k] == name) return static_cast<FvVariant>(k);
  return std::nullopt;
}

bool variant_is_constrained(FvVariant v) { return v != FvVariant::linear; }

double cell_roughness(std::size_t i, std::size_t size) {
  return (static_cast<double>(i) + 0.5) / static_cast<double>(size);
}

double cell_f0(std::size_t j, std::size_t size) {
  const double s = (static_cast<double>(j) + 0.5) / static_cast<double>(size);
  return s * s;
}

double clamp_angle_degrees(const FvLutOptions& o, double roughness) {
  const double t = std::clamp(roughness / o.clamp_roughness, 0.0, 1.0);
  return o.clamp_degrees + (90.0 - o.clamp_degrees) * t;
}

double EndpointAdjustment::operator()(double roughness) const {
  const double u = std::sqrt(roughness);
  return ((c[3] * u + c[2]) * u + c[1]) * u + c[0];
}

FvFunction reference_function(const FvLutOptions& o) {
  if (o.function != nullptr) return o.function;
  if (o.reference == "fv-schlick-smith-lh")
    return [](double d, double f0, double r) { return reference::fv_schlick_smith_lh(d, f0, r); };
  if (o.reference == "fv-schlick-smith")
    return [](double d, double f0, double r) { return reference::fv_schlick_smith_peak(d, f0, r); };
  if (o.reference == "fv-exact")
    return [](double d, double f0, double r) { return reference::fv_exact_dielectric(d, f0, r); };
  return nullptr;
}

bool FvLutOptions::is_valid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why != nullptr) *why = m;
    return false;
  };
  if (size == 0) return fail("the grid size must be at least 1, got 0");
  if (size > 8192) return fail("the grid size must be at most 8192");
  if (fit_samples < 3)
    return fail("at least 3 angle samples per cell are needed to fit A, B and C");
  if (eval_samples == 0) return fail("the error tables need at least 1 angle sample per cell");
  if (endpoint_grid == 0) return fail("the endpoint adjustment grid must be at least 1");
  if (!(clamp_degrees > 0 && clamp_degrees <= 90))
    return fail("the grazing clamp must be in (0, 90] degrees");
  if (!(clamp_roughness > 0)) return fail("the clamp roughness must be positive");
  if (!(eval_max_degrees > 0 && eval_max_degrees <= 90))
    return fail("the error tables' largest angle must be in (0, 90] degrees");
  if (threads < 0) return fail("threads must not be negative");
  if (reference_function(*this) == nullptr)
    return fail("unknown FV reference '" + reference +
                "' (fv-schlick-smith-lh, fv-schlick-smith, fv-exact)");
  return true;
}

EndpointAdjustment derive_endpoint_adjustment(const FvLutOptions& o) {
  const FvFunction ref = reference_function(o);
  const std::size_t g = o.endpoint_grid, m = o.fit_samples;
  FitBlock b;
  b.label = "endpoint adjustment";
  b.columns.resize(4);  // f0, roughness, u = sqrt(roughness), x
  for (std::size_t j = 0; j < g; ++j)
    for (std::size_t i = 0; i < g; ++i) {
      const double r = cell_roughness(i, g), f0 = cell_f0(j, g);
      const double top = clamp_angle_degrees(o, r) * std::numbers::pi / 180;
      for (std::size_t k = 0; k < m; ++k) {
        const double d = std::cos(top * (static_cast<double>(k) + 0.5) / static_cast<double>(m));
        const double y = ref(d, f0, r);
        if (!(y > 0) || !std::isfinite(y)) continue;
        b.columns[0].push_back(f0);
        b.columns[1].push_back(r);
        b.columns[2].push_back(std::sqrt(r));
        b.columns[3].push_back(1 - d);
        b.target.push_back(y);
      }
    }
  FixedFormProblem p;
  ParseOptions po;
  po.variables = {"f0", "roughness", "u", "x"};
  po.parameters = {"s0", "s1", "s2", "s3"};
  po.parameter_values = {1, 0, 0, 0};
  p.formula = parse_formula(
      "f0 * exp2((s0 + s1*u + s2*u^2 + s3*u^3) * log2(4 / (roughness^4 * f0)) * x^2)", po);
  p.blocks.push_back(std::move(b));
  FixedFormOptions fo;
  fo.loss = Loss::Log;
  fo.threads = o.threads;
  FixedFormSummary s;
  solve_fixed_form(fo, p, &s);
  EndpointAdjustment a;
  for (std::size_t k = 0; k < 4; ++k) a.c[k] = s.blocks[0].parameters[k];
  return a;
}

FvBake bake_fv_luts(const FvLutOptions& options, std::span<const FvVariant> variants) {
  std::string why;
  if (!options.is_valid(&why)) throw Error(why, {"lut options"});
  const auto t0 = std::chrono::steady_clock::now();
  FvBake bake;
  bake.reference = options.function != nullptr ? "custom" : options.reference;
  lut_detail::FvReference ref;
  ref.function = reference_function(options);
  const std::vector<lut_detail::CellSpec> cells = lut_detail::square_grid(options.size);
  bake.tables.resize(variants.size());
  ProgressCounter progress(options.on_progress, variants.size() * cells.size(), "cells");
  // The four tables at once; each also spreads its cells over the pool (nested loops are safe).
  parallel_for(
      variants.size(), 1,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k)
          bake.tables[k] = bake_table(options, variants[k], ref, cells, &bake.adjustment, progress);
      },
      options.threads);
  bake.seconds = seconds_since(t0);
  return bake;
}

}  // namespace shaderfit::lut
