#include "shaderfit/batch/outputs.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/files.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/report/search_report.hpp"
#include "shaderfit/search/front/choice.hpp"

namespace shaderfit {

namespace {

using json = nlohmann::json;

// Numbers for people: 3 significant digits ("0.00123", "1.23e-05", "6"); "n/a" for NaN.
std::string short_number(double v) {
  if (std::isnan(v)) return "n/a";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{:.3g}", v);
}

// The entry's chosen member, or nullptr when its search found none.
const FrontMember* chosen_member(const BatchEntryResult& e) {
  return e.chosen < e.front.size() ? &e.front[e.chosen] : nullptr;
}

// The entry's search JSON, parsed; null when the entry has none.
json run_of(const BatchEntryResult& e) {
  if (e.run_json.empty()) return nullptr;
  try {
    return json::parse(e.run_json);
  } catch (const json::exception& ex) {
    throw Error("entry '" + e.name + "': its search JSON does not parse: " + ex.what(),
                SourceLocation{e.name});
  }
}

// The per-material inputs the run recorded ("uniform" in its JSON), else the member's.
std::vector<std::string> uniform_of(const json& run, const FrontMember& m) {
  if (run.is_object() && run.contains("uniform") && run["uniform"].is_array()) {
    std::vector<std::string> out;
    for (const json& v : run["uniform"])
      if (v.is_string()) out.push_back(v.get<std::string>());
    return out;
  }
  return m.uniform;
}

// A comment line that stays one line in every language: no line breaks, and no backslash that
// could splice the next line into a C or C++ comment.
std::string comment_line(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    if (c == '\\') c = '/';
  }
  return text;
}

// The baseline's formula with its constants as short as float32 allows, when it parses over the
// entry's inputs; as written otherwise (it is only shown).
std::string baseline_text(const BatchEntryResult& e) {
  ParseOptions po;
  po.variables = e.inputs;
  try {
    return to_infix(parse_formula(e.baseline->formula, po), PrintOptions::for_people());
  } catch (const Error&) {
    return e.baseline->formula;
  }
}

// What the comment above an entry's function says: what it approximates and where, the
// formula, its measured error, its cost, the baseline's, and the goal.
std::vector<std::string> function_comment(const BatchEntryResult& e, const FrontMember& m,
                                          const std::vector<std::string>& uniform) {
  std::vector<std::string> lines;
  lines.push_back(e.name + ": approximates " + e.description);
  lines.push_back("formula: " + to_infix(m.expression, PrintOptions::for_people()));
  std::string error = fmt::format("error: {} {}; max |error| {}", e.loss_name, short_number(m.loss),
                                  short_number(m.metrics.max_abs));
  if (m.checked_between_samples) error += " (at and between the samples)";
  error += "; in float32 " + short_number(m.float32_max_abs);
  if (m.certified_max_abs && std::isfinite(*m.certified_max_abs))
    error += "; certified |error| <= " + short_number(*m.certified_max_abs);
  lines.push_back(error);
  lines.push_back(fmt::format("cost {} ({}); ", short_number(m.cost), e.cost_name) +
                  cost_comment(m.expression, uniform));
  if (e.baseline)
    lines.push_back(fmt::format(
        "baseline {}: cost {}, {} {}, max |error| {}, in float32 {}", baseline_text(e),
        short_number(e.baseline->cost), e.loss_name, short_number(e.baseline->loss),
        short_number(e.baseline->metrics.max_abs), short_number(e.baseline->float32_max_abs)));
  lines.push_back("goal " + batch_goal_text(e.goal) + (e.goal_met ? ": met" : ": not met"));
  for (std::string& l : lines) l = comment_line(std::move(l));
  return lines;
}

// The first comment lines of every file: what made it, and what it leaves out.
std::string file_comment(const BatchResult& r) {
  std::size_t n = 0;
  for (const BatchEntryResult& e : r.entries) n += chosen_member(e) != nullptr ? 1 : 0;
  std::string s = "// " +
                  comment_line(fmt::format("shaderfit batch: {}, {} function{}", r.manifest, n,
                                           n == 1 ? "" : "s")) +
                  "\n";
  if (r.interrupted) s += "// interrupted: the entries that had not finished are missing\n";
  for (const BatchEntryResult& e : r.entries)
    if (chosen_member(e) == nullptr)
      s += "// not here: " + comment_line(e.name) + " (no formula found)\n";
  for (const BadManifestEntry& b : r.bad)
    s += "// not run: " + comment_line(b.name + ": " + b.message) + "\n";
  return s;
}

// Every chosen function in `language` (generate_source), without the file comment.
std::string functions_source(const BatchResult& r, Language language) {
  std::vector<SourceFunction> functions;
  for (const BatchEntryResult& e : r.entries) {
    const FrontMember* m = chosen_member(e);
    if (m == nullptr) continue;
    SourceFunction f{m->expression, {}};
    f.options.name = e.name;
    f.options.bake_parameters = true;
    f.options.uniform = uniform_of(run_of(e), *m);
    f.options.comment = function_comment(e, *m, f.options.uniform);
    functions.push_back(std::move(f));
  }
  return generate_source(functions, language);
}

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json baseline_json(const std::optional<BaselineScore>& b) {
  if (!b) return nullptr;
  return {{"formula", b->formula},
          {"cost", number(b->cost)},
          {"loss", number(b->loss)},
          {"max_abs", number(b->metrics.max_abs)},
          {"max_rel", number(b->metrics.max_rel)},
          {"float32_max_abs", number(b->float32_max_abs)}};
}

// A section id for an entry: its name is a C identifier, but a bad entry's may be anything.
std::string section_id(const std::string& name) {
  std::string id = "entry-";
  for (char c : name) id += std::isalnum(static_cast<unsigned char>(c)) || c == '_' ? c : '-';
  return id;
}

constexpr const char* kNotRunId = "not-run";

HtmlCell number_cell(double v) { return {short_number(v), {}, v}; }
HtmlCell no_number() { return {"—", {}, std::nan("")}; }

std::vector<HtmlCell> entry_row(const BatchEntryResult& e) {
  const FrontMember* m = chosen_member(e);
  const double nan = std::nan("");
  const double cost = m ? m->cost : nan, loss = m ? m->loss : nan;
  std::vector<HtmlCell> row = {{e.name, "#" + section_id(e.name), std::nullopt},
                               {e.description, {}, std::nullopt}};
  if (e.baseline) {
    row.push_back(number_cell(e.baseline->cost));
    row.push_back(number_cell(e.baseline->loss));
  } else {
    row.push_back(no_number());
    row.push_back(no_number());
  }
  row.push_back(m ? number_cell(cost) : no_number());
  row.push_back(m ? number_cell(loss) : no_number());
  if (e.baseline && m) {
    row.push_back(number_cell(e.baseline->cost - cost));
    row.push_back(number_cell(loss / e.baseline->loss));
  } else {
    row.push_back(no_number());
    row.push_back(no_number());
  }
  row.push_back(m ? number_cell(m->float32_max_abs) : no_number());
  row.push_back({std::string(e.goal_met ? "yes" : "no") + " (" + batch_goal_text(e.goal) + ")",
                 {},
                 std::nullopt});
  return row;
}

std::vector<HtmlCell> bad_row(const BadManifestEntry& b) {
  std::vector<HtmlCell> row = {{b.name, "#" + std::string(kNotRunId), std::nullopt},
                               {"not run: " + b.message, {}, std::nullopt}};
  for (int c = 0; c < 7; ++c) row.push_back(no_number());
  row.push_back({"not run", {}, std::nullopt});
  return row;
}

// The choice rule that picks the member the goal picks (as run_batch chose it).
const Problem* problem_of(const Manifest* manifest, const std::string& name) {
  if (manifest == nullptr) return nullptr;
  for (const ManifestEntry& m : manifest->entries)
    if (m.name == name) return m.loaded.get();
  return nullptr;
}

void add_entry_section(HtmlReport& r, const BatchEntryResult& e, const Problem* problem) {
  r.heading(e.name, 1, section_id(e.name));
  std::vector<std::pair<std::string, std::string>> facts = {
      {"approximates", e.description},
      {"inputs", fmt::format("{}", fmt::join(e.inputs, ", "))},
      {"target", e.target},
      {"loss, cost", e.loss_name + ", " + e.cost_name},
      {"goal", batch_goal_text(e.goal) + (e.goal_met ? ": met" : ": not met")},
      {"why this member", e.why}};
  if (e.baseline)
    facts.push_back({"baseline", fmt::format("{}: cost {}, {} {}, max |error| {}, in float32 {}",
                                             e.baseline->formula, short_number(e.baseline->cost),
                                             e.loss_name, short_number(e.baseline->loss),
                                             short_number(e.baseline->metrics.max_abs),
                                             short_number(e.baseline->float32_max_abs))});
  facts.push_back({"search", e.from_checkpoint
                                 ? "finished by an earlier run (read back)"
                                 : fmt::format("{:.1f} s", e.seconds) +
                                       (e.rank == BatchEntryResult::kAllRanks
                                            ? std::string(" on every rank, islands shared")
                                        : e.rank != 0 ? fmt::format(" on rank {}", e.rank)
                                                      : std::string())});
  r.settings(facts);

  const json run = run_of(e);
  if (!run.is_object() || !run.contains("front") || !run["front"].is_array() ||
      run["front"].empty()) {
    r.paragraph("No search report: the search found no formula.");
    return;
  }
  SearchReportOptions o;
  o.choice = batch_choice_rule(e);
  if (problem != nullptr) {
    o.data = &problem->data;
    o.reference = problem->reference.get();
    o.problem = problem;
    if (e.baseline)
      o.baselines.push_back({"baseline", e.baseline->formula,
                             parse_formula_on(e.baseline->formula, problem->data,
                                              "baseline of entry '" + e.name + "'")});
  }
  add_search_report(r, run, e.name, o);
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  f.close();
  if (!f) throw Error("cannot write '" + path + "'", SourceLocation{path});
}

}  // namespace

std::string batch_header(const BatchResult& result, Language language) {
  return file_comment(result) + "\n" + functions_source(result, language);
}

std::string batch_cpp_cuda_header(const BatchResult& result) {
  return file_comment(result) +
         "// C++17 and CUDA: under nvcc the CUDA functions (__device__), elsewhere the C++ ones.\n"
         "#pragma once\n\n#ifdef __CUDACC__\n\n" +
         functions_source(result, Language::Cuda) + "\n#else  // C++\n\n" +
         functions_source(result, Language::Cpp) + "\n#endif  // __CUDACC__\n";
}

std::string batch_json(const BatchResult& result) {
  json entries = json::array();
  for (const BatchEntryResult& e : result.entries) {
    entries.push_back({{"name", e.name},
                       {"hash", e.hash},
                       {"description", e.description},
                       {"inputs", e.inputs},
                       {"target", e.target},
                       {"loss", e.loss_name},
                       {"cost", e.cost_name},
                       {"goal", batch_goal_text(e.goal)},
                       {"goal_met", e.goal_met},
                       {"why", e.why},
                       {"chosen", chosen_member(e) ? json(e.chosen) : json(nullptr)},
                       {"baseline", baseline_json(e.baseline)},
                       {"seconds", number(e.seconds)},
                       {"from_checkpoint", e.from_checkpoint},
                       {"rank", e.rank},
                       {"run", run_of(e)}});
  }
  json bad = json::array();
  for (const BadManifestEntry& b : result.bad)
    bad.push_back({{"name", b.name}, {"line", b.line}, {"message", b.message}});
  const json out = {{"schema", "shaderfit.batch/1"},
                    {"manifest", result.manifest},
                    {"seconds", number(result.seconds)},
                    {"interrupted", result.interrupted},
                    {"entries", entries},
                    {"bad", bad}};
  return out.dump(2) + "\n";
}

void add_batch_report(HtmlReport& r, const BatchResult& result, const Manifest* manifest) {
  std::size_t met = 0, earlier = 0;
  for (const BatchEntryResult& e : result.entries) {
    met += e.goal_met ? 1 : 0;
    earlier += e.from_checkpoint ? 1 : 0;
  }
  r.paragraph(fmt::format(
      "{}: {} function{}{} in {:.1f} s, {} meeting {} goal{}{}{}.", result.manifest,
      result.entries.size(), result.entries.size() == 1 ? "" : "s",
      earlier == 0 ? std::string() : fmt::format(" ({} finished by an earlier run)", earlier),
      result.seconds, met, met == 1 ? "its" : "their", met == 1 ? "" : "s",
      result.bad.empty() ? "" : fmt::format("; {} not run", result.bad.size()),
      result.interrupted ? "; interrupted, the others did not finish" : ""));
  r.heading("Functions");
  HtmlTable t;
  t.header = {
      "entry",     "reference/data",     "baseline cost", "baseline error",      "our cost",
      "our error", "instructions saved", "error ratio",   "float32 max |error|", "goal met"};
  t.numeric = {false, false, true, true, true, true, true, true, true, false};
  t.sortable = true;
  for (const BatchEntryResult& e : result.entries) t.rows.push_back(entry_row(e));
  for (const BadManifestEntry& b : result.bad) t.rows.push_back(bad_row(b));
  r.table(t);
  r.paragraph(
      "Click a column's header to sort by it. Errors are each entry's own loss (its section names "
      "it); instructions saved: the baseline's cost minus ours; error ratio: our error over the "
      "baseline's (below 1: more accurate); float32 max |error|: our formula computed in float32 "
      "as a shader computes it.");
  // Each entry's section on its own (its plots are gnuplot runs), then in order.
  std::vector<HtmlReport> sections(result.entries.size(), HtmlReport(""));
  parallel_for(result.entries.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      add_entry_section(sections[i], result.entries[i],
                        problem_of(manifest, result.entries[i].name));
  });
  for (const HtmlReport& section : sections) r.append(section);
  if (!result.bad.empty()) {
    r.heading("Not run", 1, kNotRunId);
    std::vector<std::vector<std::string>> rows;
    for (const BadManifestEntry& b : result.bad)
      rows.push_back({b.name, std::to_string(b.line), b.message});
    r.table({"entry", "line", "why"}, rows, {false, true, false});
  }
}

std::vector<std::string> write_batch_outputs(const BatchResult& result, const Manifest* manifest,
                                             const std::string& directory) {
  make_directories(directory);
  std::vector<std::string> written;
  // Each file made then written; an error names the file it was for.
  auto output = [&](const char* name, auto make) {
    const std::string path = (std::filesystem::path(directory) / name).string();
    std::string text;
    try {
      text = make();
    } catch (const Error& e) {
      throw Error("cannot write '" + path + "': " + e.what(), SourceLocation{path});
    }
    write_file(path, text);
    written.push_back(path);
  };
  output("fastmath.glsl", [&] { return batch_header(result, Language::Glsl); });
  output("fastmath.hlsl", [&] { return batch_header(result, Language::Hlsl); });
  output("fastmath.h", [&] { return batch_cpp_cuda_header(result); });
  output("fastmath.metal", [&] { return batch_header(result, Language::Metal); });
  output("batch.json", [&] { return batch_json(result); });
  output("report.html", [&] {
    HtmlReport report("shaderfit batch: " + result.manifest);
    add_batch_report(report, result, manifest);
    return report.html();
  });
  return written;
}

}  // namespace shaderfit
