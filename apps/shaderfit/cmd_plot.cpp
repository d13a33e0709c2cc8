// shaderfit plot: reflectance-style curves of a reference against formulas, their errors, the
// Pareto front of error against cost, and 2-D error maps. Images go through gnuplot
// (shaderfit/plot/chart.hpp); the format follows the output's extension (.png or .svg).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>

#include "cli.hpp"
#include "data_source.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/fit/fit.hpp"
#include "shaderfit/lut/fv_lut.hpp"
#include "shaderfit/plot/chart.hpp"
#include "shaderfit/plot/sphere.hpp"
#include "shaderfit/report/scene_report.hpp"
#include "shaderfit/search/front_member.hpp"

namespace shaderfit::cli {

namespace {

// "label=formula" or a bare formula (labelled by itself).
struct LabelledFormula {
  std::string label, text;
};

LabelledFormula split_label(const std::string& arg) {
  const auto eq = arg.find('=');
  if (eq == std::string::npos) return {arg, arg};
  return {arg.substr(0, eq), arg.substr(eq + 1)};
}

std::optional<Range> parse_range(const std::string& text, const std::string& option) {
  if (text.empty()) return std::nullopt;
  const auto comma = text.find(',');
  double a = 0, b = 0;
  try {
    if (comma == std::string::npos) throw std::invalid_argument("");
    std::size_t used = 0;
    a = std::stod(text.substr(0, comma), &used);
    b = std::stod(text.substr(comma + 1));
  } catch (const std::exception&) {
    throw Error("expected MIN,MAX, got '" + text + "'", SourceLocation{option});
  }
  if (!(a < b)) throw Error("range has min >= max (" + text + ")", SourceLocation{option});
  return Range{a, b};
}

struct CommonArgs {
  DataSource data;
  std::vector<std::string> materials;
  int angles = 181;
  std::string output;
  std::string title;
};

void add_common(CLI::App* cmd, CommonArgs& c) {
  add_data_options(cmd, c.data, DataFiles | References | InputsTarget);
  cmd->add_option(
         "--material", c.materials,
         "sweep these materials over 0..90 degrees instead of --data: 1.5, 0.3+3i, aluminium, "
         "gold, or 'seed' for the seed 001 set")
      ->delimiter(';')
      ->allow_extra_args(false);
  cmd->add_option("--angles", c.angles, "angles per material in a sweep (default 181)");
  cmd->add_option("-o,--output", c.output, "image to write (.png or .svg)")->required();
  cmd->add_option("--title", c.title, "title over the plot");
}

// The data, as every command states it (problem/problem.hpp); --material is its material sweep.
Problem load(const CommonArgs& c) {
  DataSource data = c.data;
  data.problem.materials = c.materials;
  data.problem.angles = c.angles;
  return load_problem(data);
}

// --- curves ---------------------------------------------------------------------------------

struct CurveArgs {
  CommonArgs common;
  std::vector<std::string> fit;  // parameters fitted per group before drawing
  std::string x = "theta_deg", group;
  std::vector<std::string> formulas;
  bool errors = false;
  bool points = false;
  std::string x_range, y_range;
  bool log_y = false;
};

std::string axis_label(const std::string& column) {
  if (column == "theta_deg") return "angle of incidence θ [degrees]";
  if (column == "cos_theta") return "cos θ";
  if (column == "x") return "x = 1 - cos θ";
  if (column == "R") return "reflectance R";
  return column;
}

void run_curves(CurveArgs& a, Context& ctx) {
  const Problem p = load(a.common);
  const Dataset& d = p.data;
  if (a.group.empty() && d.find("material")) a.group = "material";
  const std::vector<double>& xs = d.numeric(a.x).values;
  const std::vector<double>& target = d.numeric(p.target).values;
  std::map<std::string, std::vector<std::size_t>> groups;
  if (a.group.empty()) {
    groups[""].resize(d.rows());
    std::iota(groups[""].begin(), groups[""].end(), std::size_t{0});
  } else {
    const Column& g = d.column(a.group);
    for (std::size_t r = 0; r < d.rows(); ++r)
      groups[g.numeric() ? format_number(g.values[r]) : g.labels[r]].push_back(r);
  }

  // Each formula's values; with --fit, its parameters are fitted on each group's rows first and
  // the label says the fitted values per group.
  std::vector<std::pair<LabelledFormula, std::vector<double>>> values;
  std::map<std::pair<std::size_t, std::string>, std::string> fitted_note;
  for (std::size_t i = 0; i < a.formulas.size(); ++i) {
    LabelledFormula f = split_label(a.formulas[i]);
    ParseOptions po;
    po.variables = d.names();
    po.parameters = a.fit;
    po.parameter_values.assign(a.fit.size(), 0.0);
    po.source = "formula " + std::to_string(i + 1);
    Expression e = parse_formula(f.text, po);
    e.drop_unused_variables();
    const bool has_params = std::any_of(e.nodes.begin(), e.nodes.end(),
                                        [](const Node& n) { return n.op == Op::Param; });
    std::vector<double> v(d.rows(), NAN);
    std::vector<const double*> cols;
    for (const std::string& name : e.variables) cols.push_back(d.numeric(name).values.data());
    for (const auto& [name, rows] : groups) {
      Expression ge = e;
      if (has_params) {
        // Least squares on this group's rows only.
        std::vector<std::vector<double>> sub(cols.size());
        std::vector<double> y;
        for (std::size_t r : rows) {
          for (std::size_t c = 0; c < cols.size(); ++c) sub[c].push_back(cols[c][r]);
          y.push_back(target[r]);
        }
        FitProblem fp;
        fp.expression = &ge;
        for (const auto& c : sub) fp.columns.push_back(c.data());
        fp.target = y;
        FitSummary fs;
        fit_parameters(FitOptions{}, fp, &fs);
        ge.parameter_values = fs.parameters;
        std::string note;
        for (std::size_t k = 0; k < a.fit.size(); ++k)
          note += fmt::format("{}{} = {:.3g}", k ? ", " : "", a.fit[k], ge.parameter_values[k]);
        fitted_note[{i, name}] = note;
      }
      const std::vector<double> all = evaluate_on(ge, d);
      for (std::size_t r : rows) v[r] = all[r];
    }
    values.push_back({f, v});
  }
  if (a.errors && values.empty())
    throw Error("--errors needs at least one formula", SourceLocation{"--errors"});

  Chart chart;
  chart.title = a.common.title;
  chart.x_label = axis_label(a.x);
  chart.y_label = a.errors ? "formula - " + p.target : axis_label(p.target);
  chart.x_range = parse_range(a.x_range, "--x-range");
  chart.y_range = parse_range(a.y_range, "--y-range");
  chart.log_y = a.log_y;
  const bool many = groups.size() > 1;
  for (auto& [name, rows] : groups) {
    std::sort(rows.begin(), rows.end(),
              [&](std::size_t i, std::size_t j) { return xs[i] < xs[j]; });
    auto series = [&](const std::string& label, const std::vector<double>& v, bool minus_target) {
      Series s;
      s.style = a.points ? Series::Style::Points : Series::Style::Lines;
      s.label = many ? (label.empty() ? name : name + ": " + label) : label;
      for (std::size_t r : rows) {
        s.x.push_back(xs[r]);
        s.y.push_back(minus_target ? v[r] - target[r] : v[r]);
      }
      return s;
    };
    if (!a.errors) {
      Series ref = series(values.empty() && many ? "" : p.target + " (reference)", target, false);
      ref.emphasis = !many || values.empty();
      chart.series.push_back(ref);
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
      const auto& [f, v] = values[i];
      const auto note = fitted_note.find({i, name});
      const std::string label =
          note == fitted_note.end() ? f.label : f.label + " (" + note->second + ")";
      chart.series.push_back(series(label, v, a.errors));
    }
  }
  render(chart, a.common.output);
  ctx.out << "wrote " << a.common.output << " (" << chart.series.size() << " curves)\n";
}

// --- front ----------------------------------------------------------------------------------

struct FrontArgs {
  CommonArgs common;
  std::string front_path, metric = "mse", cost = "instructions";
  std::vector<std::string> marks;
};

void run_front(FrontArgs& a, Context& ctx) {
  const FrontFile file = read_front_file(a.front_path);
  if (file.front.empty())
    throw Error("no front to plot: the file has no non-empty 'front' list",
                SourceLocation{a.front_path});
  // The vertical axis: "loss" or one of the metrics.
  const std::optional<Loss> metric = loss_from_name(a.metric);
  if (a.metric != "loss" && (!metric || a.metric != loss_name(*metric)))
    throw Error("front member without 'cost' or '" + a.metric + "'", SourceLocation{a.front_path});
  Series s;
  s.label = "Pareto front";
  s.style = Series::Style::LinesPoints;
  s.emphasis = true;
  std::vector<std::pair<double, double>> pts;
  for (const ReadFrontMember& read : file.front) {
    const FrontMember& m = read.member;
    const double e = metric ? loss_value(*metric, m.metrics) : m.loss;
    if (std::isnan(m.cost) || std::isnan(e))
      throw Error("front member without 'cost' or '" + a.metric + "'",
                  SourceLocation{a.front_path});
    pts.push_back({m.cost, e});
  }
  std::sort(pts.begin(), pts.end());
  for (auto [c, e] : pts) {
    s.x.push_back(c);
    s.y.push_back(e);
  }
  Chart chart;
  chart.title = a.common.title;
  chart.x_label = "cost [" + a.cost + "]";
  chart.y_label = a.metric + " (log scale)";
  chart.log_y = true;
  chart.step_series = false;
  chart.series.push_back(s);
  if (!a.marks.empty()) {
    const Problem problem = load(a.common);
    const Dataset& d = problem.data;
    const auto target = cost_target_from_name(a.cost);
    if (!target) throw Error("unknown cost target '" + a.cost + "'", SourceLocation{"--cost"});
    const std::vector<double>& y = d.numeric(problem.target).values;
    for (std::size_t i = 0; i < a.marks.size(); ++i) {
      LabelledFormula lf = split_label(a.marks[i]);
      Expression e = parse_formula_on(lf.text, d, "--mark " + std::to_string(i + 1));
      const std::vector<double> p = evaluate_on(e, d);
      double sum = 0;
      for (std::size_t r = 0; r < y.size(); ++r) sum += (p[r] - y[r]) * (p[r] - y[r]);
      chart.markers.push_back(
          {lf.label, expression_cost(e, *target), sum / static_cast<double>(y.size())});
    }
  }
  render(chart, a.common.output);
  ctx.out << "wrote " << a.common.output << " (" << pts.size() << " front members, "
          << chart.markers.size() << " marked)\n";
}

// --- map ------------------------------------------------------------------------------------

struct MapArgs {
  CommonArgs common;
  std::string x, y, formula, stat = "max";
  int bins = 48;
  bool log = true;
};

void run_map(MapArgs& a, Context& ctx) {
  if (a.bins < 1)
    throw Error("--bins must be at least 1, got " + std::to_string(a.bins),
                SourceLocation{"--bins"});
  if (a.stat != "max" && a.stat != "mean")
    throw Error("--stat must be max or mean", SourceLocation{"--stat"});
  const Problem problem = load(a.common);
  const Dataset& d = problem.data;
  const auto& xs = d.numeric(a.x).values;
  const auto& ys = d.numeric(a.y).values;
  const auto& t = d.numeric(problem.target).values;
  LabelledFormula lf = split_label(a.formula);
  const std::vector<double> p = evaluate_on(parse_formula_on(lf.text, d, "formula"), d);
  auto [x0, x1] = std::minmax_element(xs.begin(), xs.end());
  auto [y0, y1] = std::minmax_element(ys.begin(), ys.end());
  Heatmap m;
  m.nx = m.ny = a.bins;
  m.x_range = {*x0, *x1 > *x0 ? *x1 : *x0 + 1};
  m.y_range = {*y0, *y1 > *y0 ? *y1 : *y0 + 1};
  std::vector<double> sum(static_cast<std::size_t>(a.bins * a.bins), 0.0), count(sum.size(), 0.0);
  for (std::size_t r = 0; r < d.rows(); ++r) {
    auto bin = [&](double v, const Range& rg) {
      return std::clamp(static_cast<int>((v - rg.min) / (rg.max - rg.min) * a.bins), 0, a.bins - 1);
    };
    const std::size_t k =
        static_cast<std::size_t>(bin(ys[r], m.y_range) * a.bins + bin(xs[r], m.x_range));
    const double e = std::fabs(p[r] - t[r]);
    sum[k] = a.stat == "max" ? std::max(sum[k], e) : sum[k] + e;
    count[k] += 1;
  }
  for (std::size_t k = 0; k < sum.size(); ++k)
    m.values.push_back(count[k] == 0 ? NAN : (a.stat == "max" ? sum[k] : sum[k] / count[k]));
  m.title = a.common.title.empty() ? lf.label : a.common.title;
  m.x_label = axis_label(a.x);
  m.y_label = axis_label(a.y);
  m.value_label = a.stat + " |formula - " + problem.target + "|";
  m.log_values = a.log;
  render(m, a.common.output);
  ctx.out << "wrote " << a.common.output << " (" << a.bins << " x " << a.bins << " cells)\n";
}

// --- sphere ---------------------------------------------------------------------------------

struct SphereArgs {
  SphereScene scene;
  std::vector<double> light;
  std::string fv, output, title;
  double diff_scale = 8.0;  // --exposure is data.exposure, for both pictures
  // --formula: any formula of the scene's quantities against --reference in a scene.
  std::string formula, precision = "double";
  DataSource data;
};

// A formula of any scene quantities against the reference, in the scene's picture with FLIP.
void run_scene_formula(SphereArgs& a, Context& ctx) {
  if (a.data.problem.reference.formula.empty() && a.data.reference_file.empty())
    throw Error("--formula needs the function it approximates: give --reference",
                SourceLocation{"--reference"});
  if (!a.fv.empty()) throw Error("give --formula or --fv, not both", SourceLocation{"--fv"});
  if (a.data.scene.empty()) a.data.scene = "sphere";
  const Precision precision = precision_option(a.precision);
  const Problem p = load_problem(a.data);
  std::vector<std::string> names;
  for (std::string_view q : scene_quantity_names()) names.emplace_back(q);
  ParseOptions po;
  po.variables = names;
  po.source = "--formula";
  Expression e = parse_formula(a.formula, po);
  e.drop_unused_variables();
  const SceneImages im = formula_scene_images(p, e, precision);
  if (std::filesystem::path(a.output).extension() != ".png")
    throw Error("the scene's pictures are written as PNG: name a .png file", SourceLocation{"-o"});
  write_scene_png(a.output, im);
  ctx.out << fmt::format(
      "wrote {} ({}; reference, approximation, FLIP map): mean FLIP {:.4f}, {:.2f}% of pixels "
      "above {:g}, display RMSE {:.4g}\n",
      a.output, p.description, im.flip.mean, 100 * im.visible_share, kFlipVisible, im.display_rmse);
}

void run_sphere(SphereArgs& a, Context& ctx) {
  if (!a.formula.empty()) {
    run_scene_formula(a, ctx);
    return;
  }
  if (!a.light.empty()) {
    if (a.light.size() != 3)
      throw Error("--light takes three numbers X,Y,Z", SourceLocation{"--light"});
    a.scene.light = {a.light[0], a.light[1], a.light[2]};
  }
  std::string label;
  std::function<double(double)> fv;
  a.scene.validate();
  if (a.fv.empty()) {
    const auto [A, B] = lut::fit_fv_constrained(a.scene.roughness, a.scene.f0);
    const double f0 = a.scene.f0;
    fv = [=](double lh) {
      const double x = 1 - lh;
      return f0 * std::exp2(A * x * x + B * x);
    };
    label = fmt::format(
        "F0 exp2(A x^2 + B x), x = 1 - l.h, A = {:.4g}, B = {:.4g} (constrained fit, C = 0)", A, B);
  } else {
    ParseOptions po;
    po.variables = {"l_dot_h", "f0", "roughness"};
    po.source = "--fv";
    Expression e = parse_formula(a.fv, po);
    const double f0 = a.scene.f0, r = a.scene.roughness;
    fv = [e, f0, r](double lh) {
      const double v[] = {lh, f0, r};
      return evaluate_scalar(e, v);
    };
    label = a.fv;
  }
  const SphereImages im = render_sphere(a.scene, fv);
  // Three panels: reference, approximation, |difference| x diff_scale, each tone-mapped
  // (Reinhard) and gamma-encoded for display.
  const int n = im.size;
  HeatmapGrid g;
  g.columns = 3;
  g.width = 1200;
  g.height = 470;
  g.title = a.title.empty() ? fmt::format(
                                  "GGX sphere, roughness {:g}, F0 {:g}: reference F·V "
                                  "against the approximation",
                                  a.scene.roughness, a.scene.f0)
                            : a.title;
  auto tone = [&](double v) {
    v *= a.data.exposure;
    return std::pow(v / (1 + v), 1 / 2.2);
  };
  const std::string titles[3] = {"reference", "approximation",
                                 fmt::format("|difference| x {:g}", a.diff_scale)};
  for (int panel = 0; panel < 3; ++panel) {
    Heatmap m;
    m.title = titles[panel];
    m.nx = m.ny = n;
    m.x_range = {0, static_cast<double>(n)};
    m.y_range = {0, static_cast<double>(n)};
    m.palette = Heatmap::Palette::Grey;
    m.axes = false;
    m.values.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), NAN);
    for (std::size_t i = 0; i < m.values.size(); ++i) {
      const double ref = im.reference[i], app = im.approximation[i];
      if (std::isnan(ref)) continue;
      m.values[i] = tone(panel == 0 ? ref : panel == 1 ? app : a.diff_scale * std::fabs(ref - app));
    }
    g.panels.push_back(std::move(m));
  }
  render(g, a.output);
  double max_diff = 0, max_ref = 0;
  for (std::size_t i = 0; i < im.reference.size(); ++i) {
    if (std::isnan(im.reference[i])) continue;
    max_diff = std::max(max_diff, std::fabs(im.reference[i] - im.approximation[i]));
    max_ref = std::max(max_ref, im.reference[i]);
  }
  ctx.out << "wrote " << a.output << "\n  approximation: " << label
          << fmt::format("\n  max |reference - approximation| = {:.4g} (peak reference {:.4g})\n",
                         max_diff, max_ref);
}

}  // namespace

void register_plot_command(CLI::App& app, Context& ctx) {
  CLI::App* plot = app.add_subcommand(
      "plot", "Curves, error curves, Pareto fronts and error maps as PNG or SVG");
  plot->require_subcommand(1);

  auto c = std::make_shared<CurveArgs>();
  CLI::App* curves =
      plot->add_subcommand("curves", "A reference against formulas over one input, per group");
  add_common(curves, c->common);
  curves->add_option("--x", c->x, "column on the horizontal axis (default theta_deg)");
  curves->add_option("--group", c->group,
                     "one curve per value of this column (default: material, if present)");
  curves->add_flag("--errors", c->errors, "plot formula - reference instead of the values");
  curves->add_flag("--log-y", c->log_y, "logarithmic vertical axis");
  curves->add_flag("--points", c->points,
                   "draw points, not lines (scattered samples such as the seed data set)");
  curves->add_option("--x-range", c->x_range, "MIN,MAX of the horizontal axis");
  curves->add_option("--y-range", c->y_range, "MIN,MAX of the vertical axis");
  curves
      ->add_option("--fit", c->fit,
                   "parameters of the formulas to fit per group (least squares) before drawing")
      ->delimiter(',')
      ->allow_extra_args(false);
  curves->add_option("formulas", c->formulas,
                     "formulas, optionally labelled: 'Schlick=r0 + (1 - r0)*x^5'");
  curves->callback([c, &ctx] { run_curves(*c, ctx); });

  auto f = std::make_shared<FrontArgs>();
  CLI::App* front =
      plot->add_subcommand("front", "The Pareto front of a search (error against cost)");
  add_common(front, f->common);
  front
      ->add_option("front", f->front_path,
                   "JSON file with a 'front' list (shaderfit search --json)")
      ->required();
  front->add_option("--metric", f->metric, "error metric on the vertical axis (default mse)");
  front->add_option("--cost", f->cost, "cost target of the marks (default instructions)");
  front
      ->add_option("--mark", f->marks,
                   "well-known formulas to mark, 'Schlick=r0 + (1 - r0)*x^5' (needs data)")
      ->allow_extra_args(false);
  front->callback([f, &ctx] { run_front(*f, ctx); });

  auto m = std::make_shared<MapArgs>();
  CLI::App* map = plot->add_subcommand("map", "A 2-D map of a formula's error over two inputs");
  add_common(map, m->common);
  map->add_option("--x", m->x, "column on the horizontal axis")->required();
  map->add_option("--y", m->y, "column on the vertical axis")->required();
  map->add_option("--bins", m->bins, "cells per axis (default 48)");
  map->add_option("--stat", m->stat, "max or mean |error| per cell (default max)");
  map->add_flag("!--linear", m->log, "linear colour scale instead of log10");
  map->add_option("formula", m->formula, "the formula, optionally labelled")->required();
  map->callback([m, &ctx] { run_map(*m, ctx); });

  auto sp = std::make_shared<SphereArgs>();
  CLI::App* sphere = plot->add_subcommand("sphere",
                                          "Seed 002's images: a GGX sphere with the reference F*V, "
                                          "with an approximation, and their difference");
  sphere->add_option("--roughness", sp->scene.roughness,
                     "perceptual roughness (alpha = roughness^2; default 0.5)");
  sphere->add_option("--f0", sp->scene.f0,
                     "Fresnel reflectance at normal incidence (default 0.04)");
  sphere->add_option("--light", sp->light, "direction towards the light X,Y,Z (view is +z)")
      ->delimiter(',');
  sphere->add_option("--size", sp->scene.size, "pixels per side of each panel (default 256)");
  sphere->add_option("--diff-scale", sp->diff_scale,
                     "levels applied to the difference panel (default 8)");
  sphere->add_option(
      "--fv", sp->fv,
      "the approximation as a formula in l_dot_h, f0, roughness (default: seed 002's constrained "
      "exp2 fit for this cell)");
  sphere->add_option("--formula", sp->formula,
                     "any formula of the scene's quantities (n_dot_l, n_dot_v, n_dot_h, v_dot_h, "
                     "l_dot_h, roughness, alpha, f0, ior), drawn in --scene against --reference "
                     "with its FLIP map (a .png)");
  add_data_options(sphere, sp->data, References | Scenes);
  add_precision_option(sphere, sp->precision, "--formula is computed in", "double");
  sphere->add_option("-o,--output", sp->output, "image to write (.png or .svg)")->required();
  sphere->add_option("--title", sp->title, "title over the images");
  sphere->callback([sp, &ctx] { run_sphere(*sp, ctx); });
}

}  // namespace shaderfit::cli
