// shaderfit batch: every function of a TOML manifest searched in one run, the cores shared
// among them, a line per finished entry, a checkpoint per entry (an interrupted batch resumes),
// and one result: headers per shading language, a JSON of every front and one HTML report
// (docs/batch.md).
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <ostream>

#include "cli.hpp"
#include "progress_bar.hpp"
#include "shaderfit/batch/batch.hpp"
#include "shaderfit/batch/manifest.hpp"
#include "shaderfit/batch/outputs.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit::cli {

namespace {

struct BatchArgs {
  std::string manifest;
  std::string out;
  bool strict = false;
  int parallel = 0;
  double rank_timeout_s = 10;
  bool quiet = false;
};

// The default result folder: the manifest's name without its extension, "-out", in the
// current folder ("lib.toml" -> "lib-out").
std::string default_out(const std::string& manifest) {
  return std::filesystem::path(manifest).stem().string() + "-out";
}

void run_batch_command(const BatchArgs& a, Context& ctx) {
  // Under MPI every rank reads the manifest; rank 0 prints, writes and hands out the entries.
  const bool leader = ctx.communicator == nullptr || ctx.communicator->rank() == 0;
  const Manifest manifest = read_manifest(a.manifest, a.strict);
  const std::string out = a.out.empty() ? default_out(a.manifest) : a.out;
  ctx.out << fmt::format("shaderfit batch: {}, {} function{}{}, results in {}\n", a.manifest,
                         manifest.entries.size(), manifest.entries.size() == 1 ? "" : "s",
                         manifest.bad.empty() ? "" : fmt::format(" ({} bad)", manifest.bad.size()),
                         out);
  for (const BadManifestEntry& b : manifest.bad)
    ctx.err << "shaderfit: error: " << b.message << '\n';

  BatchOptions o;
  // Under MPI a rank is the unit of parallelism (mpirun -np N, one per core): one entry at a
  // time per rank unless told otherwise.
  o.parallel_entries = a.parallel > 0 ? a.parallel : ctx.communicator != nullptr ? 1 : 0;
  o.rank_timeout_s = a.rank_timeout_s;
  o.checkpoint_directory = (std::filesystem::path(out) / "entries").string();
  ProgressBar bar(ctx, "batch");
  if (!a.quiet) {
    o.on_entry = [&](const BatchEntryResult& r) {
      bar.clear();
      ctx.out << batch_entry_line(r) << '\n' << std::flush;
    };
  }
  if (bar.active()) {
    o.on_progress = [&](const BatchProgress& p) {
      std::string running;
      for (const std::string& n : p.running) running += (running.empty() ? "" : ", ") + n;
      bar.update(
          p.total == 0 ? 1.0 : static_cast<double>(p.done) / static_cast<double>(p.total),
          fmt::format("{}/{} functions{}", p.done, p.total, running.empty() ? "" : ": " + running));
    };
  }
  BatchResult result;
  {
    const StopSignals stop;
    o.interrupt = stop.flag();
    result = ctx.communicator != nullptr ? run_batch_distributed(manifest, o, *ctx.communicator)
                                         : run_batch(manifest, o);
  }
  bar.clear();
  if (!leader) return;
  const std::vector<std::string> files = write_batch_outputs(result, &manifest, out);
  std::size_t met = 0, earlier = 0;
  for (const BatchEntryResult& r : result.entries) {
    met += r.goal_met ? 1 : 0;
    earlier += r.from_checkpoint ? 1 : 0;
  }
  ctx.out << fmt::format(
      "{} of {} functions done ({} finished by an earlier run), {} met their "
      "goal, in {:.1f} s\n",
      result.entries.size(), manifest.entries.size(), earlier, met, result.seconds);
  for (const BadManifestEntry& b : result.bad)
    if (std::none_of(manifest.bad.begin(), manifest.bad.end(),
                     [&](const BadManifestEntry& m) { return m.name == b.name; }))
      ctx.err << "shaderfit: error: " << b.message << '\n';
  for (const std::string& note : result.notes) ctx.out << note << '\n';
  ctx.out << "wrote";
  for (const std::string& f : files) ctx.out << ' ' << f;
  ctx.out << '\n';
  if (result.interrupted)
    ctx.err << "shaderfit: interrupted; the finished functions are kept in "
            << o.checkpoint_directory << ": run the same command again to finish the others\n";
  if (!result.bad.empty())
    throw Error(fmt::format("{} of {} functions could not be run (above)", result.bad.size(),
                            manifest.entries.size() + manifest.bad.size()),
                {a.manifest});
}

}  // namespace

void register_batch_command(CLI::App& app, Context& ctx) {
  auto args = std::make_shared<BatchArgs>();
  auto* cmd = app.add_subcommand(
      "batch",
      "Approximate every function of a TOML manifest in one run: one header per shading "
      "language, one JSON, one report (docs/batch.md)");
  cmd->add_option("manifest", args->manifest, "the manifest (TOML): [defaults] and [[function]]")
      ->required();
  cmd->add_option("--out", args->out,
                  "folder for the results and the per-function checkpoints (default: the "
                  "manifest's name with -out)");
  cmd->add_flag("--strict", args->strict, "stop at the first bad entry of the manifest");
  cmd->add_option("--parallel", args->parallel,
                  "functions searched at once (default: one per core)");
  cmd->add_flag("--quiet", args->quiet, "no line per finished function");
  cmd->add_option("--rank-timeout", args->rank_timeout_s,
                  "with shaderfit-mpi: seconds of silence after which a rank is taken for dead "
                  "and its function handed to another (default 10)");
  cmd->footer(
      "Example: shaderfit batch lib.toml --out lib-out\n"
      "  writes lib-out/fastmath.{glsl,hlsl,h,metal}, batch.json, report.html; run it again to "
      "finish an interrupted batch");
  cmd->callback([args, &ctx] { run_batch_command(*args, ctx); });
}

}  // namespace shaderfit::cli
