// shaderfit lut: bake seed 002's FV lookup tables (four variants, 128 x 128 over roughness and
// sqrt(F0)) to DDS and EXR, with error tables and images and the HLSL and GLSL that sample them;
// optionally compare with exact Fresnel x exact Smith GGX (docs/lut.md).
#include <fmt/format.h>

#include <memory>
#include <ostream>

#include "cli.hpp"
#include "progress_bar.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/lut/fv_compare.hpp"
#include "shaderfit/lut/fv_lut.hpp"
#include "shaderfit/lut/fv_output.hpp"

namespace shaderfit::cli {

namespace {

struct LutArgs {
  lut::FvLutOptions options;
  std::vector<std::string> variants;
  std::string out = "fv_lut";
  bool no_files = false;
  std::string compare;  // a variant name, or empty
  std::size_t max_failures = 20;
};

std::vector<lut::FvVariant> chosen_variants(const LutArgs& a) {
  if (a.variants.empty()) return {lut::kAllFvVariants.begin(), lut::kAllFvVariants.end()};
  std::vector<lut::FvVariant> v;
  for (const std::string& name : a.variants) {
    const auto parsed = lut::parse_variant(name);
    if (!parsed)
      throw Error("unknown variant '" + name + "' (endpoint, linear, constrained, clamped)",
                  {"--variant"});
    v.push_back(*parsed);
  }
  return v;
}

void check_options(const lut::FvLutOptions& o) {
  // Name the option for the checks FvLutOptions::is_valid makes.
  if (o.size == 0) throw Error("the grid size must be at least 1, got 0", {"--size"});
  if (o.fit_samples < 3)
    throw Error("at least 3 angle samples per cell are needed to fit A, B and C",
                {"--fit-samples"});
  if (o.eval_samples == 0)
    throw Error("at least 1 angle sample per cell is needed, got 0", {"--eval-samples"});
  if (o.endpoint_grid == 0)
    throw Error("the grid size must be at least 1, got 0", {"--endpoint-grid"});
  std::string why;
  if (!o.is_valid(&why)) throw Error(why, {"lut"});
}

void print_bake(std::ostream& out, const lut::FvBake& b, const LutArgs& a) {
  const lut::FvLutOptions& o = a.options;
  out << fmt::format(
      "shaderfit lut: {} table{} of {} x {} (u = roughness, v = sqrt(F0)), reference {}\n",
      b.tables.size(), b.tables.size() == 1 ? "" : "s", o.size, o.size, b.reference);
  out << fmt::format(
      "  {} angles per cell for the fits, {} for the errors (0..{} degrees); clamp {} degrees at "
      "roughness 0, "
      "90 from roughness {}\n",
      o.fit_samples, o.eval_samples, o.eval_max_degrees, o.clamp_degrees, o.clamp_roughness);
  const auto& c = b.adjustment.c;
  out << fmt::format(
      "  endpoint adjustment: s(r) = {:.6g} + {:.6g} u + {:.6g} u^2 + {:.6g} u^3, u = "
      "sqrt(roughness)\n\n",
      c[0], c[1], c[2], c[3]);
  out << fmt::format("  {:<12} {:>10} {:>9} {:>11} {:>11} {:>10} {:>9} {:>11} {:>10} {:>7} {:>8}\n",
                     "variant", "mean log2", "max log2", "mean |err|", "max |err|", "f16 mean",
                     "f16 max", "FV(1)/f0-1", "f16", "failed", "seconds");
  for (const lut::FvTable& t : b.tables) {
    const bool con = lut::variant_is_constrained(t.variant);
    out << fmt::format(
        "  {:<12} {:>10.4f} {:>9.3f} {:>11.4g} {:>11.4g} {:>10.4f} {:>9.3f} {:>11} {:>10} {:>7} "
        "{:>8.3f}\n",
        lut::variant_name(t.variant), t.summary.mean_log2, t.summary.max_log2, t.summary.mean_abs,
        t.summary.max_abs, t.summary_half.mean_log2, t.summary_half.max_log2,
        con ? fmt::format("{:.2g}", t.f0_deviation) : "-",
        con ? fmt::format("{:.2g}", t.f0_deviation_half) : "-", t.failures.size(), t.seconds);
  }
  out << fmt::format(
      "\n  baked {} table{} in {:.3f} s (wall, tables and cells in parallel on {} threads)\n",
      b.tables.size(), b.tables.size() == 1 ? "" : "s", b.seconds,
      o.threads > 0 ? o.threads : default_thread_pool().threads());
  for (const lut::FvTable& t : b.tables) {
    for (std::size_t k = 0; k < t.failures.size() && k < a.max_failures; ++k)
      out << fmt::format("  failed ({}): {}\n", lut::variant_name(t.variant), t.failures[k]);
    if (t.failures.size() > a.max_failures)
      out << fmt::format("  ... {} more failed cells in {} (see its errors CSV)\n",
                         t.failures.size() - a.max_failures, lut::variant_name(t.variant));
  }
}

void run_lut(LutArgs& a, Context& ctx) {
  check_options(a.options);
  const std::vector<lut::FvVariant> variants = chosen_variants(a);
  std::optional<lut::FvVariant> compare;
  if (!a.compare.empty()) {
    compare = lut::parse_variant(a.compare);
    if (!compare)
      throw Error("unknown variant '" + a.compare + "' (linear, constrained, clamped)",
                  {"--compare-exact"});
    if (*compare == lut::FvVariant::endpoint)
      throw Error("the comparison needs a fitted variant (linear, constrained, clamped)",
                  {"--compare-exact"});
  }
  lut::FvLutOptions options = a.options;
  ProgressBar bar(ctx, "lut");
  options.on_progress = bar.callback();
  const lut::FvBake bake = lut::bake_fv_luts(options, variants);
  bar.clear();
  print_bake(ctx.out, bake, a);
  if (!a.no_files) {
    const std::vector<std::string> files = lut::write_fv_bake(bake, a.options, a.out);
    ctx.out << fmt::format(
        "  wrote {} files to {}/ (textures fv_<variant>_rgba32f.dds, _rgba16f.dds, .exr; "
        "errors .csv and .png; fv_lut.hlsl, fv_lut.glsl, fv_summary.json)\n",
        files.size(), a.out);
  }
  std::size_t failed = 0;
  for (const lut::FvTable& t : bake.tables) failed += t.failures.size();
  if (compare) {
    ProgressBar compare_bar(ctx, "lut (exact comparison)");
    options.on_progress = compare_bar.callback();
    const lut::ExactComparison c = lut::compare_with_exact(options, *compare);
    compare_bar.clear();
    ctx.out << '\n' << lut::format_exact_comparison(c) << fmt::format("  ({:.3f} s)\n", c.seconds);
  }
  if (failed > 0)
    ctx.err << fmt::format("shaderfit: warning: {} cells failed to fit (listed above)\n", failed);
}

}  // namespace

void register_lut_command(CLI::App& app, Context& ctx) {
  auto a = std::make_shared<LutArgs>();
  CLI::App* cmd = app.add_subcommand(
      "lut", "Bake seed 002's Fresnel x visibility lookup tables (DDS, EXR, HLSL, GLSL)");
  lut::FvLutOptions& o = a->options;
  cmd->add_option("--size", o.size, "texels per axis (default 128)");
  cmd->add_option("--variant", a->variants,
                  "endpoint, linear, constrained, clamped (default: all four)")
      ->delimiter(',')
      ->allow_extra_args(false);
  cmd->add_option("--reference", o.reference,
                  "fv-schlick-smith-lh (the seed's, default), fv-schlick-smith, fv-exact");
  cmd->add_option("--fit-samples", o.fit_samples, "angles per cell for the fits (default 90)");
  cmd->add_option("--eval-samples", o.eval_samples,
                  "angles per cell for the error tables (default 180)");
  cmd->add_option("--eval-max-degrees", o.eval_max_degrees,
                  "largest angle of the error tables (default 90)");
  cmd->add_option("--clamp-degrees", o.clamp_degrees, "grazing clamp at roughness 0 (default 85)");
  cmd->add_option("--clamp-roughness", o.clamp_roughness,
                  "roughness from which the clamp is 90 degrees (default 0.5)");
  cmd->add_option("--endpoint-grid", o.endpoint_grid,
                  "cells per axis for the endpoint adjustment fit (default 32)");
  cmd->add_option("--threads", o.threads, "threads (0: all cores)");
  cmd->add_option("--out", a->out, "output directory (default fv_lut)");
  cmd->add_flag("--no-files", a->no_files, "bake and report, write nothing");
  cmd->add_option("--compare-exact", a->compare,
                  "also compare a fitted VARIANT with exact Fresnel x exact Smith GGX");
  cmd->footer("Example:\n  shaderfit lut --out fv_lut --compare-exact clamped");
  cmd->callback([a, &ctx] { run_lut(*a, ctx); });
}

}  // namespace shaderfit::cli
