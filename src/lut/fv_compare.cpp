#include "shaderfit/lut/fv_compare.hpp"

#include <fmt/format.h>

#include <chrono>
#include <iterator>

#include "fv_internal.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/reference/fresnel.hpp"

namespace shaderfit::lut {

namespace {

struct Metal {
  const char* name;
  double n, k;
};
// Seed 001's metals.
constexpr Metal kMetals[] = {{"metal 0.3+3i", 0.3, 3},         {"metal 0.15+4i", 0.15, 4},
                             {"metal 0.3+3.35i", 0.3, 3.35},   {"metal 1.4+7i", 1.4, 7},
                             {"metal 1.84+3.73i", 1.84, 3.73}, {"metal 2.1+4i", 2.1, 4},
                             {"metal 2.9+3.1i", 2.9, 3.1}};

lut_detail::FvReference function_ref(FvFunction f) {
  lut_detail::FvReference r;
  r.function = f;
  return r;
}

ExactComparisonRow compare_row(const FvLutOptions& o, FvVariant v,
                               const lut_detail::FvReference& truth,
                               std::span<const lut_detail::CellSpec> cells,
                               ProgressCounter& progress) {
  const lut_detail::FvReference seed = function_ref(
      [](double d, double f0, double r) { return reference::fv_schlick_smith_lh(d, f0, r); });
  const lut_detail::FvReference peak = function_ref(
      [](double d, double f0, double r) { return reference::fv_schlick_smith_peak(d, f0, r); });
  const EndpointAdjustment unused;
  const std::vector<FvCell> seed_cells = lut_detail::fit_cells(o, v, seed, cells, unused, progress);
  const std::vector<FvCell> exact_cells =
      lut_detail::fit_cells(o, v, truth, cells, unused, progress);
  const std::size_t n = cells.size();
  std::vector<CellError> e_lh(n), e_peak(n), e_seed(n), e_exact(n);
  std::vector<FvCell> usable(n);
  ExactComparisonRow row;
  for (std::size_t k = 0; k < n; ++k) {
    usable[k].ok = seed_cells[k].ok && exact_cells[k].ok;
    row.failed += usable[k].ok ? 0 : 1;
  }
  const std::vector<double> cosines = lut_detail::eval_cosines(o);
  parallel_for(
      n, 64,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
          if (!usable[k].ok) continue;
          e_lh[k] = lut_detail::reference_error(truth, cosines, cells[k], seed);
          e_peak[k] = lut_detail::reference_error(truth, cosines, cells[k], peak);
          e_seed[k] = lut_detail::model_error(truth, cosines, cells[k], seed_cells[k]);
          e_exact[k] = lut_detail::model_error(truth, cosines, cells[k], exact_cells[k]);
        }
      },
      o.threads);
  row.schlick_lh = lut_detail::summarize(e_lh, usable);
  row.schlick_peak = lut_detail::summarize(e_peak, usable);
  row.seed_fit = lut_detail::summarize(e_seed, usable);
  row.exact_fit = lut_detail::summarize(e_exact, usable);
  return row;
}

}  // namespace

ExactComparison compare_with_exact(const FvLutOptions& options, FvVariant variant) {
  std::string why;
  if (!options.is_valid(&why)) throw Error(why, {"lut options"});
  if (variant == FvVariant::endpoint)
    throw Error(
        "the comparison with the exact reference needs a fitted variant (linear, constrained, "
        "clamped)",
        {"compare_with_exact"});
  const auto t0 = std::chrono::steady_clock::now();
  ExactComparison c;
  c.variant = variant;
  // Two fits per cell: of the seed's reference and of the ground truth.
  ProgressCounter progress(options.on_progress,
                           2 * options.size * (options.size + std::size(kMetals)), "cells");
  {
    const lut_detail::FvReference truth = function_ref(
        [](double d, double f0, double r) { return reference::fv_exact_dielectric(d, f0, r); });
    ExactComparisonRow row =
        compare_row(options, variant, truth, lut_detail::square_grid(options.size), progress);
    row.material = "dielectrics (grid)";
    c.rows.push_back(row);
  }
  for (const Metal& m : kMetals) {
    lut_detail::FvReference truth;
    truth.kind = lut_detail::FvReference::Kind::conductor;
    truth.n = m.n;
    truth.k = m.k;
    const double f0 = reference::r0_from_complex_ior(m.n, m.k);
    std::vector<lut_detail::CellSpec> cells;
    for (std::size_t i = 0; i < options.size; ++i)
      cells.push_back({i, 0, cell_roughness(i, options.size), f0});
    ExactComparisonRow row = compare_row(options, variant, truth, cells, progress);
    row.material = m.name;
    row.f0 = f0;
    c.rows.push_back(row);
  }
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

std::string format_exact_comparison(const ExactComparison& c) {
  std::string s = fmt::format(
      "Against exact Fresnel x exact Smith GGX (n = h), variant {}: log2 error, mean over cells / "
      "max\n"
      "  {:<20} {:>7}  {:>17}  {:>17}  {:>17}  {:>17}\n",
      variant_name(c.variant), "material", "f0", "Schlick x V(l.h)", "Schlick x S-Smith",
      "fit to Schlick", "fit to exact");
  auto cell = [](const ErrorSummary& e) {
    return fmt::format("{:>8.4f} / {:<7.3f}", e.mean_log2, e.max_log2);
  };
  for (const ExactComparisonRow& r : c.rows) {
    s += fmt::format("  {:<20} {:>7}  {}  {}  {}  {}", r.material,
                     r.f0 > 0 ? fmt::format("{:.4f}", r.f0) : "grid", cell(r.schlick_lh),
                     cell(r.schlick_peak), cell(r.seed_fit), cell(r.exact_fit));
    s += r.failed ? fmt::format("  ({} cells failed)\n", r.failed) : "\n";
  }
  return s;
}

}  // namespace shaderfit::lut
