// shaderfit report: one self-contained HTML page for a run, from the JSON the run wrote.
// A search result (a "front" list) gets its front table, the Pareto plot with the baselines
// marked, reference curves against the chosen formula, the comparison with the baselines, and the
// chosen formula as GLSL, HLSL and CUDA. Any other run's JSON (fit, lut, rational) is laid out
// generically: its settings, its lists of records as tables, and the PNG images it names.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "data_source.hpp"
#include "shaderfit/cli.hpp"
#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/data/fresnel_sweep.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/plot/chart.hpp"
#include "shaderfit/report/html.hpp"

namespace shaderfit::cli {

namespace {

using nlohmann::json;

struct ReportArgs {
  std::string run_path, output, title, choose;
  DataSource data;
  std::vector<std::string> baselines;
};

std::string scalar_text(const json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) return fmt::format("{:.6g}", v.get<double>());
  if (v.is_null()) return "—";
  return v.dump();
}

bool is_image_path(const json& v) {
  if (!v.is_string()) return false;
  const std::string s = v.get<std::string>();
  return s.size() > 4 && s.compare(s.size() - 4, 4, ".png") == 0 && std::filesystem::exists(s);
}

// Generic layout: scalars as settings, arrays of objects as tables, images embedded, nested
// objects as sub-sections.
void generic_section(HtmlReport& r, const json& j, const std::string& name, int level) {
  std::vector<std::pair<std::string, std::string>> scalars;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!it->is_object() && !(it->is_array() && !it->empty() && (*it)[0].is_object()) && !is_image_path(*it))
      scalars.push_back({it.key(), scalar_text(*it)});
  }
  if (!name.empty()) r.heading(name, level);
  if (!scalars.empty()) r.settings(scalars);
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (is_image_path(*it)) r.image(it->get<std::string>(), it.key());
  }
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it->is_object()) generic_section(r, *it, it.key(), std::min(level + 1, 4));
    if (it->is_array() && !it->empty() && (*it)[0].is_object()) {
      std::vector<std::string> cols;
      for (const auto& row : *it)
        for (auto c = row.begin(); c != row.end(); ++c)
          if (!c->is_structured() && std::find(cols.begin(), cols.end(), c.key()) == cols.end()) cols.push_back(c.key());
      std::vector<std::vector<std::string>> rows;
      std::vector<bool> numeric(cols.size(), true);
      for (const auto& row : *it) {
        std::vector<std::string> cells;
        for (std::size_t c = 0; c < cols.size(); ++c) {
          const json v = row.contains(cols[c]) ? row[cols[c]] : json();
          if (v.is_string()) numeric[c] = false;
          cells.push_back(scalar_text(v));
        }
        rows.push_back(cells);
      }
      r.heading(it.key(), std::min(level + 1, 4));
      r.table(cols, rows, numeric);
    }
  }
}

std::string temp_png(const std::string& stem) {
  static int counter = 0;
  return (std::filesystem::temp_directory_path() /
          fmt::format("shaderfit-report-{}-{}-{}.png", getpid(), stem, counter++))
      .string();
}

struct Scored {
  std::string label, formula;
  Expression e;
  ErrorMetrics m;
  double cost = 0;
};

Scored score(const std::string& label, const std::string& text, const Dataset& d, const std::string& target,
             const std::string& source) {
  Scored s{label, text, parse_formula_on(text, d, source), {}, 0};
  s.m = error_metrics(evaluate_on(s.e, d), d.numeric(target).values);
  s.cost = expression_cost(s.e, CostTarget::Instructions);
  return s;
}

void search_report(HtmlReport& r, const json& j, ReportArgs& a) {
  const json& front = j["front"];
  if (!front.is_array() || front.empty()) throw Error("no front to report: 'front' is empty", {a.run_path});
  if (j.contains("data")) r.settings({{"data", scalar_text(j["data"].value("source", json()))},
                                      {"rows", scalar_text(j["data"].value("rows", json()))},
                                      {"target", scalar_text(j["data"].value("target", json()))}});
  if (j.contains("options")) generic_section(r, j["options"], "Settings", 2);
  if (j.contains("summary")) generic_section(r, j["summary"], "Run", 2);

  r.heading("Pareto front");
  std::vector<std::vector<std::string>> rows;
  for (const auto& m : front) {
    rows.push_back({scalar_text(m.value("cost", json())), scalar_text(m.value("mse", json())),
                    scalar_text(m.value("max_abs", json())),
                    m.contains("time_s") ? fmt::format("{:.1f} ms", 1e3 * m["time_s"].get<double>()) : "—",
                    m.value("formula", std::string())});
  }
  r.table({"cost", "MSE", "max abs", "found at", "formula"}, rows, {true, true, true, true, false});

  // The data, when the user names it, scores the baselines and draws curves.
  const bool have_data = !a.data.path.empty() || !a.data.dataset.empty();
  const std::string target = j.contains("data") ? j["data"].value("target", std::string("R")) : "R";
  std::vector<Scored> baselines;
  Chart pareto;
  pareto.x_label = "cost [" + (j.contains("options") ? j["options"].value("cost", std::string("instructions")) : "") + "]";
  pareto.y_label = "MSE (log scale)";
  pareto.log_y = true;
  Series fs{"Pareto front", {}, {}, Series::Style::LinesPoints, true};
  for (const auto& m : front) {
    if (!m.contains("mse") || !m["mse"].is_number()) continue;
    fs.x.push_back(m["cost"].get<double>());
    fs.y.push_back(m["mse"].get<double>());
  }
  pareto.series.push_back(fs);
  Dataset d;
  if (have_data) {
    d = load_data(a.data);
    for (std::size_t i = 0; i < a.baselines.size(); ++i) {
      const auto eq = a.baselines[i].find('=');
      const std::string label = eq == std::string::npos ? a.baselines[i] : a.baselines[i].substr(0, eq);
      const std::string text = eq == std::string::npos ? a.baselines[i] : a.baselines[i].substr(eq + 1);
      baselines.push_back(score(label, text, d, target, "--baseline " + std::to_string(i + 1)));
      pareto.markers.push_back({label, baselines.back().cost, baselines.back().m.mse});
    }
  }
  const std::string pareto_png = temp_png("pareto");
  render(pareto, pareto_png);
  r.image(pareto_png, "Pareto front: MSE against cost; the baselines are marked");
  std::filesystem::remove(pareto_png);

  // The chosen formula: --choose, else the most accurate member no costlier than the first
  // baseline, else the most accurate member.
  std::string chosen = a.choose;
  if (chosen.empty()) {
    double best = INFINITY;
    const double limit = baselines.empty() ? INFINITY : baselines.front().cost;
    for (const auto& m : front)
      if (m["cost"].get<double>() <= limit && m["mse"].is_number() && m["mse"].get<double>() < best) {
        best = m["mse"].get<double>();
        chosen = m["formula"].get<std::string>();
      }
    if (chosen.empty()) chosen = front.back()["formula"].get<std::string>();
  }
  r.heading("Chosen formula");
  r.paragraph(chosen);
  ParseOptions po;
  if (j.contains("inputs")) po.variables = j["inputs"].get<std::vector<std::string>>();
  po.source = "--choose";
  Expression ce = parse_formula(chosen, po);

  if (have_data) {
    std::vector<std::vector<std::string>> cmp;
    Scored c = score("chosen", chosen, d, target, "--choose");
    auto row = [&](const Scored& s, const Scored* base) {
      return std::vector<std::string>{s.label, s.formula, fmt::format("{:g}", s.cost), fmt::format("{:.4e}", s.m.mse),
                                      fmt::format("{:.4e}", s.m.max_abs),
                                      base ? fmt::format("{:+.1f}%", 100 * relative_change(s.m.mse, base->m.mse)) : "—"};
    };
    for (const Scored& b : baselines) cmp.push_back(row(b, nullptr));
    cmp.push_back(row(c, baselines.empty() ? nullptr : &baselines.front()));
    r.heading("Against the baselines");
    r.table({"", "formula", "cost", "MSE", "max abs", "MSE vs first baseline"}, cmp,
            {false, false, true, true, true, true});

    // Curves over the angle for two materials, when the inputs are those of a Fresnel sweep.
    Dataset sweep = make_fresnel_sweep({parse_material("1.5"), parse_material("aluminium")}, 181);
    bool sweepable = true;
    for (const auto& v : ce.variables) sweepable = sweepable && sweep.find(v) && sweep.find(v)->numeric();
    if (sweepable) {
      for (const char* mat : {"ior1.5", "aluminium"}) {
        Chart ch;
        ch.title = std::string("Reflectance of ") + mat;
        ch.x_label = "angle of incidence θ [degrees]";
        ch.y_label = "reflectance R";
        std::vector<std::size_t> rows_of;
        for (std::size_t i = 0; i < sweep.rows(); ++i)
          if (sweep.column("material").labels[i] == mat) rows_of.push_back(i);
        auto add = [&](const std::string& label, const std::vector<double>& v, bool emph) {
          Series s{label, {}, {}, Series::Style::Lines, emph};
          for (std::size_t i : rows_of) {
            s.x.push_back(sweep.numeric("theta_deg").values[i]);
            s.y.push_back(v[i]);
          }
          ch.series.push_back(s);
        };
        add("exact Fresnel", sweep.numeric("R").values, true);
        for (const Scored& b : baselines) add(b.label, evaluate_on(parse_formula_on(b.formula, sweep), sweep), false);
        add("chosen: " + chosen, evaluate_on(parse_formula_on(chosen, sweep), sweep), false);
        const std::string png = temp_png("curve");
        render(ch, png);
        r.image(png, ch.title + ": the reference, the baselines and the chosen formula");
        std::filesystem::remove(png);
      }
    }
  }
  r.heading("Code");
  for (Language l : {Language::Glsl, Language::Hlsl, Language::Cuda}) {
    CodegenOptions co;
    co.language = l;
    co.comment = {chosen};
    r.code(std::string(language_name(l)), generate_function(ce, co));
  }
}

void run_report(ReportArgs& a, Context& ctx) {
  std::ifstream f(a.run_path);
  if (!f) throw Error("cannot open '" + a.run_path + "'", SourceLocation{a.run_path});
  json j;
  try {
    f >> j;
  } catch (const json::exception& e) {
    throw Error(std::string("not JSON: ") + e.what(), SourceLocation{a.run_path});
  }
  if (!j.is_object()) throw Error("expected a JSON object written by a shaderfit run", SourceLocation{a.run_path});
  const bool search = j.contains("front");
  HtmlReport r(a.title.empty() ? (search ? "shaderfit search" : "shaderfit run") + std::string(": ") +
                                     std::filesystem::path(a.run_path).filename().string()
                               : a.title);
  if (search) {
    search_report(r, j, a);
  } else {
    generic_section(r, j, "", 2);
  }
  r.write(a.output);
  ctx.out << "wrote " << a.output << "\n";
}

}  // namespace

void register_report_command(CLI::App& app, Context& ctx) {
  auto a = std::make_shared<ReportArgs>();
  CLI::App* cmd = app.add_subcommand("report", "One self-contained HTML page for a run (search, fit, lut, rational)");
  cmd->add_option("run", a->run_path, "the JSON a run wrote (--json)")->required();
  cmd->add_option("-o,--output", a->output, "HTML file to write")->required();
  cmd->add_option("--title", a->title, "page title");
  cmd->add_option("--choose", a->choose, "the front member to show as code (default: best within the first baseline's cost)");
  cmd->add_option("--baseline", a->baselines, "formulas to compare with, 'Schlick=r0 + (1 - r0)*x^5' (needs data)")
      ->allow_extra_args(false);
  add_data_options(cmd, a->data, false);
  cmd->footer("Example:\n  shaderfit search --dataset fresnel-seed --inputs r0,x --target R --json run.json\n"
              "  shaderfit report run.json --dataset fresnel-seed --baseline 'Schlick=r0 + (1 - r0)*x^5' -o run.html");
  cmd->callback([a, &ctx] { run_report(*a, ctx); });
}

}  // namespace shaderfit::cli
