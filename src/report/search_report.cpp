#include "shaderfit/report/search_report.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/files.hpp"
#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/cost/per_material.hpp"
#include "shaderfit/data/fresnel_sweep.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/plot/chart.hpp"
#include "shaderfit/report/scene_report.hpp"
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

// A formula written by another command's JSON (exact constants) as people read it: each number
// in the text as PrintOptions::for_people writes it; names with digits (r0) stay as they are.
std::string formula_for_people(const std::string& text) {
  const PrintOptions people = PrintOptions::for_people();
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    const char ch = text[i];
    const bool in_name =
        !out.empty() && (std::isalnum(static_cast<unsigned char>(out.back())) || out.back() == '_');
    if (!in_name && (std::isdigit(static_cast<unsigned char>(ch)) ||
                     (ch == '.' && i + 1 < text.size() &&
                      std::isdigit(static_cast<unsigned char>(text[i + 1]))))) {
      std::size_t used = 0;
      double v = 0;
      try {
        v = std::stod(text.substr(i), &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used > 0) {
        out += format_number(v, people);
        i += used;
        continue;
      }
    }
    out += ch;
    ++i;
  }
  return out;
}

// A JSON value in a table or list: a "formula" as people read it, numbers to 6 digits.
std::string cell_text(const std::string& key, const json& v) {
  if (key == "formula" && v.is_string()) return formula_for_people(v.get<std::string>());
  return scalar_text(v);
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
  static std::atomic<int> counter{0};  // pages may be made on several threads (a batch's)
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

// `weights` as the search's rows weighed (a scene's display loss), or empty.
Scored score(const std::string& label, const std::string& text, const Expression& e,
             const Dataset& d, const std::string& target, std::span<const double> weights,
             std::span<const std::string> uniform, Precision precision, CostTarget cost) {
  Scored s{label, text, e, {}, 0};
  s.m = error_metrics(evaluate_on(s.e, d, precision), d.numeric(target).values, {}, weights);
  s.cost = expression_cost(s.e, cost, uniform);
  return s;
}

// Renders each figure into the page, and with a figure directory also keeps it there as PNG and
// SVG under its name.
struct Figures {
  HtmlReport& report;
  std::string directory;

  template <class Figure>
  void add(const Figure& chart, const std::string& name, const std::string& caption) {
    if (directory.empty()) {
      const std::string png = temp_png(name);
      render(chart, png);
      report.image(png, caption);
      std::filesystem::remove(png);
      return;
    }
    make_directories(directory);
    const std::string stem = (std::filesystem::path(directory) / name).string();
    render(chart, stem + ".png");
    render(chart, stem + ".svg");
    report.image(stem + ".png", caption);
  }
};

}  // namespace

void add_json_section(HtmlReport& r, const json& j, const std::string& name, int level) {
  std::vector<std::pair<std::string, std::string>> scalars;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!it->is_object() && !(it->is_array() && !it->empty() && (*it)[0].is_object()) &&
        !is_image_path(*it))
      scalars.push_back({it.key(), cell_text(it.key(), *it)});
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
          cells.push_back(cell_text(cols[c], v));
        }
        rows.push_back(cells);
      }
      r.heading(it.key(), std::min(level + 1, 4));
      r.table(cols, rows, numeric);
    }
  }
}

ReportChoice add_search_report(HtmlReport& r, const json& j, const std::string& source,
                               const SearchReportOptions& a) {
  if (!j.contains("front") || !j["front"].is_array() || j["front"].empty())
    throw Error("no front to report: 'front' is empty", {source});
  const FrontFile file = front_file_from_json(j, source);
  const std::vector<std::string>& uniform = a.uniform.empty() ? file.uniform : a.uniform;
  // The page leads with the answer: the chosen formula, its code, its error and cost against
  // the baselines and its pictures; then the front; the data, settings and run last, folded.
  // Each part is made apart, then appended in that order.
  HtmlReport answer(""), front(""), provenance("");
  if (j.contains("data"))
    provenance.settings({{"data", scalar_text(j["data"].value("source", json()))},
                         {"rows", scalar_text(j["data"].value("rows", json()))},
                         {"target", scalar_text(j["data"].value("target", json()))}});
  if (j.contains("options")) add_json_section(provenance, j["options"], "Settings", 2);
  if (j.contains("summary")) add_json_section(provenance, j["summary"], "Run", 2);

  const std::string loss =
      j.contains("options") ? j["options"].value("loss", std::string("loss")) : "loss";
  std::vector<FrontMember> members;
  for (const ReadFrontMember& read : file.front) members.push_back(read.member);
  const Precision run_precision =
      j.contains("options") && j["options"].contains("precision") &&
              j["options"]["precision"].is_string()
          ? precision_from_name(j["options"]["precision"].get<std::string>())
                .value_or(Precision::Double)
          : Precision::Double;
  const Precision precision = a.precision.value_or(run_precision);
  // The search's cost (JSON options.cost): baselines and the chosen formula are counted the same.
  const CostTarget cost_target =
      j.contains("options") && j["options"].contains("cost") && j["options"]["cost"].is_string()
          ? cost_target_from_name(j["options"]["cost"].get<std::string>()).value_or(CostTarget::Instructions)
          : CostTarget::Instructions;
  const InstructionTarget counted = instruction_target_of(cost_target).value_or(InstructionTarget::Sass);

  // The chosen formula: the rule's pick, or the caller's formula.
  ReportChoice chosen;
  std::optional<Choice> pick;
  if (a.formula.empty()) {
    pick = choose_member(members, a.choice, loss);
    chosen.formula = members[pick->index].formula;
    chosen.how = choice_rule_description(a.choice);
    chosen.why = pick->why;
  } else {
    chosen.formula = a.formula;
    chosen.how = "given";
    chosen.why = "the formula was given, not chosen from the front";
    chosen.by_rule = false;
  }

  front.heading("Pareto front");
  // Columns for what the run measured: float32 errors, certified bounds.
  bool float32 = false, half = false, certified = false, checked = false;
  for (const FrontMember& m : members) {
    float32 = float32 || (std::isfinite(m.float32_max_abs) && m.float32_max_abs > 0);
    half = half || m.half_max_abs > 0;
    certified = certified || m.certified_max_abs.has_value();
    checked = checked || m.checked_between_samples;
  }
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < members.size(); ++i) {
    const FrontMember& m = members[i];
    // The front as shown: a minor step only where it is the chosen member.
    if (m.minor_step && !(pick && pick->index == i)) continue;
    std::vector<std::string> row = {number_text(m.cost)};
    if (!uniform.empty())
      row.push_back(std::to_string(
          split_instruction_count(m.expression, uniform, counted).per_material));
    row.insert(row.end(), {number_text(m.metrics.mse), number_text(m.metrics.max_abs)});
    if (float32) row.push_back(number_text(m.float32_max_abs));
    if (half) row.push_back(number_text(m.half_max_abs));
    if (certified)
      row.push_back(!m.certified_max_abs ? "—"
                    : std::isinf(*m.certified_max_abs)
                        ? "none found"
                        : "≤ " + number_text(*m.certified_max_abs) +
                              (m.certified_converged ? "" : " (time ran out)"));
    row.push_back(std::isnan(m.time_s) ? "—" : fmt::format("{:.1f} ms", 1e3 * m.time_s));
    row.push_back(to_infix(m.expression, people(file.front[i])) +
                  (pick && pick->index == i ? "  ← chosen" : ""));
    rows.push_back(std::move(row));
  }
  std::vector<std::string> heads = {"cost", "MSE", "max abs"};
  if (!uniform.empty()) {
    heads[0] = "cost per pixel";
    heads.insert(heads.begin() + 1, "per material");
  }
  if (float32) heads.push_back("max abs in float32");
  if (half) heads.push_back("max abs in half");
  if (certified) heads.push_back("certified max abs");
  heads.insert(heads.end(), {"found at", "formula"});
  std::vector<bool> numeric(heads.size(), true);
  numeric.back() = false;
  if (certified) numeric[heads.size() - 3] = false;
  front.table(heads, rows, numeric);
  std::string notes;
  if (checked)
    notes +=
        "Max abs is the largest error found at the samples and between them (a denser "
        "check, then local maximisation around the worst points). ";
  if (float32)
    notes +=
        "In float32: the formula computed operation by operation in float32, as a shader "
        "computes it, against the reference. ";
  if (half)
    notes +=
        "In half: every input, constant and operation rounded to binary16, as half-precision "
        "shader code computes it (docs/precision.md). ";
  if (run_precision != Precision::Double)
    notes += "MSE and max abs are those of the formula computed in " +
             std::string(precision_name(run_precision)) + ", the precision the run ranked by. ";
  if (certified)
    notes +=
        "Certified: a rigorous bound of the error on the whole domain by interval "
        "arithmetic, for the formula's exact constants (docs/reference.md).";
  if (!notes.empty()) front.paragraph(notes);

  Figures answer_figures{answer, a.figure_directory}, front_figures{front, a.figure_directory};
  // The data, when given, scores the baselines and draws curves.
  const std::string target = j.contains("data") ? j["data"].value("target", std::string("R")) : "R";
  std::vector<Scored> baselines;
  std::span<const double> weights;
  // The display loss weighed the search's rows by the scene's display (search_problem).
  const bool display = loss == loss_name(Loss::Display);
  if (a.data != nullptr && a.problem != nullptr && display)
    weights = a.problem->display_weights;
  else if (a.data != nullptr && a.problem != nullptr && !a.problem->weights.empty())
    weights = a.data->numeric(a.problem->weights).values;
  Chart pareto;
  pareto.title = "Pareto front: MSE against cost";
  pareto.x_label =
      std::string(uniform.empty() ? "cost" : "cost per pixel") + " [" +
      (j.contains("options") ? j["options"].value("cost", std::string("instructions")) : "") + "]";
  pareto.y_label = "MSE (log scale)";
  pareto.log_y = true;
  Series fs{"Pareto front", {}, {}, Series::Style::LinesPoints, true};
  for (const FrontMember& m : members) {
    if (std::isnan(m.metrics.mse) || m.minor_step) continue;
    fs.x.push_back(m.cost);
    fs.y.push_back(m.metrics.mse);
  }
  pareto.series.push_back(fs);
  if (pick && !std::isnan(members[pick->index].metrics.mse))
    pareto.markers.push_back(
        {"chosen", members[pick->index].cost, members[pick->index].metrics.mse});
  std::string pareto_caption = "The Pareto front: MSE against cost, one point per member";
  if (a.data != nullptr) {
    for (const ReportFormula& b : a.baselines) {
      baselines.push_back(
          score(b.label, b.formula, b.expression, *a.data, target, weights, uniform, precision,
                cost_target));
      pareto.markers.push_back({b.label, baselines.back().cost, baselines.back().m.mse});
      pareto_caption += "; " + b.label + " = " + b.formula;
    }
  }
  if (pick) pareto_caption += "; chosen = the chosen formula below";
  front_figures.add(pareto, "front", pareto_caption);

  const std::string formula_location = "SearchReportOptions::formula";
  ParseOptions po;
  po.variables = file.inputs;
  po.source = formula_location;
  Expression ce = parse_formula(chosen.formula, po);
  const std::string chosen_text = to_infix(ce, PrintOptions::for_people());
  answer.heading("Chosen formula");
  answer.answer(chosen_text);
  if (pick) {
    const FrontMember& m = members[pick->index];
    answer.paragraph(fmt::format("Cost {:g} {}{}; MSE {}, max abs {}.", m.cost,
                                 cost_target == CostTarget::Nodes ? "nodes" : "instructions",
                                 std::string(uniform.empty() ? "" : " per pixel") +
                                     (cost_target == CostTarget::Rdna2 || cost_target == CostTarget::Rdna3
                                          ? " (" + std::string(cost_target_name(cost_target)) + ")"
                                          : ""),
                                 number_text(m.metrics.mse), number_text(m.metrics.max_abs)));
  }
  answer.paragraph("How: " + chosen.how + ". Why: " + chosen.why + ".");
  if (pick)
    answer.paragraph(
        "The rules: knee (the default), the knee of the front; cost=N, the most accurate member "
        "that costs at most N; error=E, the cheapest whose " +
        loss + " is at most E.");
  std::vector<std::pair<std::string, std::string>> code;
  for (Language l : {Language::Glsl, Language::Hlsl, Language::Cuda}) {
    CodegenOptions co;
    co.language = l;
    co.comment = {chosen_text, cost_comment(ce, uniform)};
    co.uniform = uniform;
    code.emplace_back(std::string(language_name(l)), generate_function(ce, co));
  }
  answer.code_tabs(code);

  if (a.data != nullptr) {
    const Dataset& d = *a.data;
    std::vector<std::vector<std::string>> cmp;
    Scored c = score("chosen", chosen_text, parse_formula_on(chosen.formula, d, formula_location),
                     d, target, weights, uniform, precision, cost_target);
    c.label = fmt::format("chosen (cost {:g})", c.cost);
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
    answer.heading("Against the baselines");
    answer.table({"", "formula", "cost", "MSE", "max abs", "MSE vs first baseline"}, cmp,
            {false, false, true, true, true, true});

    // One input: the reference and the chosen formula over it, and the error.
    if (ce.variables.size() == 1 && d.find(ce.variables[0]) != nullptr) {
      const std::vector<double>& x = d.numeric(ce.variables[0]).values;
      const std::vector<double>& y = d.numeric(target).values;
      const std::vector<double> f = evaluate_on(ce, d);
      std::vector<std::size_t> order(x.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::sort(order.begin(), order.end(),
                [&](std::size_t p, std::size_t q) { return x[p] < x[q]; });
      Chart curves, error;
      curves.title = "The reference and the chosen formula";
      curves.x_label = error.x_label = ce.variables[0];
      curves.y_label = target;
      error.title = "Error of the chosen formula";
      error.y_label = "formula - " + target;
      Series ref{"reference", {}, {}, Series::Style::Lines, true};
      Series fit{c.label, {}, {}, Series::Style::Lines, false};
      Series err{c.label, {}, {}, Series::Style::Lines, true};
      for (const std::size_t i : order) {
        ref.x.push_back(x[i]);
        ref.y.push_back(y[i]);
        fit.x.push_back(x[i]);
        fit.y.push_back(f[i]);
        err.x.push_back(x[i]);
        err.y.push_back(f[i] - y[i]);
      }
      curves.series = {ref, fit};
      error.series = {err};
      answer_figures.add(curves, "curves", "The reference and " + c.label + " = " + chosen_text);
      answer_figures.add(error, "error",
                  "The error of " + c.label + " at the samples (" + chosen_text + ")");
    }

    // Two domain variables: |error| over the whole domain, from the reference itself.
    if (a.reference != nullptr && a.reference->domain.size() == 2) {
      constexpr int kCells = 96;
      const reference::ReferenceFunction& f = *a.reference;
      const std::vector<int> inputs = f.output_indices(ce.variables);
      const int t = f.program.find_output(f.target);
      Heatmap map;
      map.title = "|error| of the chosen formula";
      map.x_label = f.domain[0].name;
      map.y_label = f.domain[1].name;
      map.value_label = "|formula - " + target + "|";
      map.nx = map.ny = kCells;
      map.x_range = {f.domain[0].lo, f.domain[0].hi};
      map.y_range = {f.domain[1].lo, f.domain[1].hi};
      map.log_values = true;
      std::vector<double> out(f.program.outputs.size()), in(inputs.size());
      for (int cell_row = 0; cell_row < kCells; ++cell_row)
        for (int col = 0; col < kCells; ++col) {
          const double point[2] = {
              f.domain[0].lo + (col + 0.5) * f.domain[0].width() / kCells,
              f.domain[1].lo + (cell_row + 0.5) * f.domain[1].width() / kCells};
          f.program.evaluate_all(point, out);
          for (std::size_t k = 0; k < inputs.size(); ++k)
            in[k] = out[static_cast<std::size_t>(inputs[k])];
          const double e = std::abs(evaluate_scalar(ce, in) - out[static_cast<std::size_t>(t)]);
          map.values.push_back(std::isfinite(e) ? e : 0.0);  // blank where undefined
        }
      answer_figures.add(map, "error-map",
                  "|error| of " + c.label + " over the domain, at the centres of 96 x 96 cells (" +
                      chosen_text + ")");
    }

    // Curves over the angle for two materials, when the inputs are those of a Fresnel sweep.
    // The key names each curve briefly; the caption gives the formulas.
    Dataset sweep = make_fresnel_sweep({parse_material("1.5"), parse_material("aluminium")}, 181);
    // Only for Fresnel data (target R, the reflectance): other data may share a name (x).
    bool sweepable = target == "R";
    for (const auto& v : ce.variables)
      sweepable = sweepable && sweep.find(v) && sweep.find(v)->numeric();
    if (sweepable) {
      struct SweepMaterial {
        const char* label;  // in the sweep's material column
        const char* name;   // for people
      };
      for (const SweepMaterial& mat :
           {SweepMaterial{"ior1.5", "IOR 1.5"}, SweepMaterial{"aluminium", "aluminium"}}) {
        Chart ch;
        ch.title = std::string("Reflectance of ") + mat.name;
        ch.x_label = "angle of incidence θ [degrees]";
        ch.y_label = "reflectance R";
        std::vector<std::size_t> rows_of;
        for (std::size_t i = 0; i < sweep.rows(); ++i)
          if (sweep.column("material").labels[i] == mat.label) rows_of.push_back(i);
        auto add = [&](const std::string& label, const std::vector<double>& v, bool emph) {
          Series s{label, {}, {}, Series::Style::Lines, emph};
          for (std::size_t i : rows_of) {
            s.x.push_back(sweep.numeric("theta_deg").values[i]);
            s.y.push_back(v[i]);
          }
          ch.series.push_back(s);
        };
        std::string caption = ch.title + ": reference = exact Fresnel";
        add("reference", sweep.numeric("R").values, true);
        for (const Scored& b : baselines) {
          add(b.label, evaluate_on(parse_formula_on(b.formula, sweep), sweep), false);
          caption += "; " + b.label + " = " + b.formula;
        }
        add(c.label, evaluate_on(parse_formula_on(chosen.formula, sweep), sweep), false);
        caption += "; " + c.label + " = " + chosen_text;
        answer_figures.add(ch, std::string("curves-") + mat.label, caption);
      }
    }
    if (a.problem != nullptr && a.problem->scene) {
      std::vector<SceneFormula> shown;
      for (const Scored& b : baselines) shown.push_back({b.label, b.e});
      shown.push_back({c.label, c.e});
      add_scene_section(answer, *a.problem, shown, precision == Precision::Half, a.figure_directory,
                        display);
    }
  }
  r.append(answer);
  r.append(front);
  r.folded("Data, settings and run", provenance);
  return chosen;
}

}  // namespace shaderfit
