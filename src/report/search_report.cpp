#include "shaderfit/report/search_report.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/data/fresnel_sweep.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/plot/chart.hpp"
#include "shaderfit/search/front_member.hpp"

namespace shaderfit {

namespace {

using nlohmann::json;

std::string scalar_text(const json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) return fmt::format("{:.6g}", v.get<double>());
  if (v.is_null()) return "—";
  return v.dump();
}

// A number read from a front member: NaN where the file had none.
std::string number_text(double v) { return std::isnan(v) ? "—" : fmt::format("{:.6g}", v); }

// How the page prints a member's formula: for people, parameters as their values where the file
// gave values.
PrintOptions people(const ReadFrontMember& read) {
  PrintOptions p = PrintOptions::for_people();
  p.substitute_parameters = read.parameters_have_values;
  return p;
}

bool is_image_path(const json& v) {
  if (!v.is_string()) return false;
  const std::string s = v.get<std::string>();
  return s.size() > 4 && s.compare(s.size() - 4, 4, ".png") == 0 && std::filesystem::exists(s);
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

Scored score(const std::string& label, const std::string& text, const Expression& e,
             const Dataset& d, const std::string& target) {
  Scored s{label, text, e, {}, 0};
  s.m = error_metrics(evaluate_on(s.e, d), d.numeric(target).values);
  s.cost = expression_cost(s.e, CostTarget::Instructions);
  return s;
}

}  // namespace

void add_json_section(HtmlReport& r, const json& j, const std::string& name, int level) {
  std::vector<std::pair<std::string, std::string>> scalars;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!it->is_object() && !(it->is_array() && !it->empty() && (*it)[0].is_object()) &&
        !is_image_path(*it))
      scalars.push_back({it.key(), scalar_text(*it)});
  }
  if (!name.empty()) r.heading(name, level);
  if (!scalars.empty()) r.settings(scalars);
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (is_image_path(*it)) r.image(it->get<std::string>(), it.key());
  }
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it->is_object()) add_json_section(r, *it, it.key(), std::min(level + 1, 4));
    if (it->is_array() && !it->empty() && (*it)[0].is_object()) {
      std::vector<std::string> cols;
      for (const auto& row : *it)
        for (auto c = row.begin(); c != row.end(); ++c)
          if (!c->is_structured() && std::find(cols.begin(), cols.end(), c.key()) == cols.end())
            cols.push_back(c.key());
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

void add_search_report(HtmlReport& r, const json& j, const std::string& source,
                       const SearchReportOptions& a) {
  if (!j.contains("front") || !j["front"].is_array() || j["front"].empty())
    throw Error("no front to report: 'front' is empty", {source});
  const FrontFile file = front_file_from_json(j, source);
  if (j.contains("data"))
    r.settings({{"data", scalar_text(j["data"].value("source", json()))},
                {"rows", scalar_text(j["data"].value("rows", json()))},
                {"target", scalar_text(j["data"].value("target", json()))}});
  if (j.contains("options")) add_json_section(r, j["options"], "Settings", 2);
  if (j.contains("summary")) add_json_section(r, j["summary"], "Run", 2);

  r.heading("Pareto front");
  std::vector<std::vector<std::string>> rows;
  for (const ReadFrontMember& read : file.front) {
    const FrontMember& m = read.member;
    rows.push_back({number_text(m.cost), number_text(m.metrics.mse), number_text(m.metrics.max_abs),
                    std::isnan(m.time_s) ? "—" : fmt::format("{:.1f} ms", 1e3 * m.time_s),
                    to_infix(m.expression, people(read))});
  }
  r.table({"cost", "MSE", "max abs", "found at", "formula"}, rows, {true, true, true, true, false});

  // The data, when given, scores the baselines and draws curves.
  const std::string target = j.contains("data") ? j["data"].value("target", std::string("R")) : "R";
  std::vector<Scored> baselines;
  Chart pareto;
  pareto.x_label =
      "cost [" +
      (j.contains("options") ? j["options"].value("cost", std::string("instructions")) : "") + "]";
  pareto.y_label = "MSE (log scale)";
  pareto.log_y = true;
  Series fs{"Pareto front", {}, {}, Series::Style::LinesPoints, true};
  for (const ReadFrontMember& read : file.front) {
    if (std::isnan(read.member.metrics.mse)) continue;
    fs.x.push_back(read.member.cost);
    fs.y.push_back(read.member.metrics.mse);
  }
  pareto.series.push_back(fs);
  if (a.data != nullptr) {
    for (const ReportFormula& b : a.baselines) {
      baselines.push_back(score(b.label, b.formula, b.expression, *a.data, target));
      pareto.markers.push_back({b.label, baselines.back().cost, baselines.back().m.mse});
    }
  }
  const std::string pareto_png = temp_png("pareto");
  render(pareto, pareto_png);
  r.image(pareto_png, "Pareto front: MSE against cost; the baselines are marked");
  std::filesystem::remove(pareto_png);

  std::string chosen = a.choose;
  if (chosen.empty()) {
    double best = INFINITY;
    const double limit = baselines.empty() ? INFINITY : baselines.front().cost;
    for (const ReadFrontMember& read : file.front) {
      const FrontMember& m = read.member;
      if (m.cost <= limit && m.metrics.mse < best) {
        best = m.metrics.mse;
        chosen = m.formula;
      }
    }
    if (chosen.empty()) chosen = file.front.back().member.formula;
  }
  const std::string choose_location = "SearchReportOptions::choose";
  ParseOptions po;
  po.variables = file.inputs;
  po.source = choose_location;
  Expression ce = parse_formula(chosen, po);
  const std::string chosen_text = to_infix(ce, PrintOptions::for_people());
  r.heading("Chosen formula");
  r.paragraph(chosen_text);

  if (a.data != nullptr) {
    const Dataset& d = *a.data;
    std::vector<std::vector<std::string>> cmp;
    Scored c =
        score("chosen", chosen_text, parse_formula_on(chosen, d, choose_location), d, target);
    auto row = [&](const Scored& s, const Scored* base) {
      return std::vector<std::string>{
          s.label,
          s.formula,
          fmt::format("{:g}", s.cost),
          fmt::format("{:.4e}", s.m.mse),
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
    for (const auto& v : ce.variables)
      sweepable = sweepable && sweep.find(v) && sweep.find(v)->numeric();
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
        for (const Scored& b : baselines)
          add(b.label, evaluate_on(parse_formula_on(b.formula, sweep), sweep), false);
        add("chosen: " + chosen_text, evaluate_on(parse_formula_on(chosen, sweep), sweep), false);
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
    co.comment = {chosen_text};
    r.code(std::string(language_name(l)), generate_function(ce, co));
  }
}

}  // namespace shaderfit
