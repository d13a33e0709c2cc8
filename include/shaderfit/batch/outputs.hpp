// The one result of a batch (batch/batch.hpp, docs/batch.md): the chosen function of every entry
// in each shading language, the JSON of every entry and one HTML report.
//
//   BatchResult result = run_batch(manifest, options);
//   for (const std::string& path : write_batch_outputs(result, &manifest, "out"))
//     std::cout << "wrote " << path << "\n";
//   // out/fastmath.glsl fastmath.hlsl fastmath.h fastmath.metal batch.json report.html
//
// Each function is the entry's chosen front member (BatchEntryResult::chosen) under the entry's
// name, its fitted constants baked in, with a comment above it: what it approximates and where,
// the formula, its measured error, its cost and the baseline's. Bad entries are listed, not
// printed.
#pragma once

#include <string>
#include <vector>

#include "shaderfit/batch/batch.hpp"
#include "shaderfit/batch/manifest.hpp"
#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/report/html.hpp"

namespace shaderfit {

// Every chosen function in `language`, as a file that compiles on its own (generate_source),
// under a first comment line "shaderfit batch: MANIFEST, N functions". A shader still needs its
// entry point. Throws shaderfit::Error as generate_source does (e.g. an entry name reserved in
// the language), and for a run JSON that does not parse, located at the entry.
std::string batch_header(const BatchResult& result, Language language);

// fastmath.h: one header for C++ (C++17) and CUDA, under #pragma once: under __CUDACC__ the CUDA
// functions (__device__), otherwise the C++ ones. Throws as batch_header.
std::string batch_cpp_cuda_header(const BatchResult& result);

// {"schema": "shaderfit.batch/1", "manifest", "seconds", "interrupted", "entries": [{"name",
// "hash", "description", "inputs", "target", "loss" (its name), "cost" (its name), "goal"
// (batch_goal_text's words), "goal_met", "why", "chosen" (index into run.front), "baseline":
// {"formula", "cost", "loss", "max_abs", "max_rel", "float32_max_abs"} or null, "seconds",
// "from_checkpoint", "rank", "run": the entry's search JSON (report/search_json.hpp) or null}],
// "bad": [{"name", "line", "message"}]}. Numbers that are not finite are null. Throws
// shaderfit::Error located at the entry for a run JSON that does not parse.
std::string batch_json(const BatchResult& result);

// The report: a sortable table of every entry (bad ones too, "not run"), each row linking to
// the entry's section, then per entry its section: its problem, goal and why, then its search
// report (report/search_report.hpp) with its baseline and the goal's choice rule. `manifest`
// (may be nullptr) gives each entry's loaded problem, by name, for scores, curves and maps.
// Throws shaderfit::Error for a run JSON that does not parse or whose search report fails (e.g.
// gnuplot missing: plot/chart.hpp).
void add_batch_report(HtmlReport& report, const BatchResult& result, const Manifest* manifest);

// Writes fastmath.glsl, fastmath.hlsl, fastmath.h, fastmath.metal, batch.json and report.html
// into `directory` (created if missing), in that order, and returns their paths. Throws
// shaderfit::Error located at the file (or directory) it cannot make or write, with the reason.
std::vector<std::string> write_batch_outputs(const BatchResult& result, const Manifest* manifest,
                                             const std::string& directory);

}  // namespace shaderfit
