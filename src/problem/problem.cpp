#include "shaderfit/problem/problem.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "data/number.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/data/csv.hpp"
#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/data/fresnel_sweep.hpp"
#include "shaderfit/data/sampling.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/reference/domain.hpp"

namespace shaderfit {

namespace {

const SourceLocation kCsvField{"ProblemSource::csv_path"};
const SourceLocation kDatasetField{"ProblemSource::dataset"};
const SourceLocation kReferenceField{"ProblemSource::reference"};
const SourceLocation kShaderField{"ReferenceText::shader_path"};
const SourceLocation kDomainField{"ProblemSource::domain"};
const SourceLocation kSamplesField{"ProblemSource::samples"};
const SourceLocation kInputsField{"ProblemSource::inputs"};
const SourceLocation kTargetField{"ProblemSource::target"};
const SourceLocation kSceneField{"ProblemSource::scene"};
const SourceLocation kMaterialsField{"ProblemSource::materials"};
const SourceLocation kAnglesField{"ProblemSource::angles"};

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

bool contains(const std::vector<std::string>& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

using data_detail::format_count;

std::string number_text(double v) { return format_number(v, PrintOptions::for_people()); }

bool has_reference(const reference::ReferenceText& r) {
  return !r.formula.empty() || !r.shader_source.empty() || !r.shader_path.empty();
}

// Throws unless exactly one source is given; checks the fields that belong to another source.
void check_source(const ProblemSource& s) {
  struct Given {
    const SourceLocation* field;
    std::string what;
  };
  std::vector<Given> given;
  if (!s.csv_path.empty()) given.push_back({&kCsvField, "a CSV file (" + s.csv_path + ")"});
  if (!s.dataset.empty()) {
    given.push_back({&kDatasetField, "a built-in data set (" + s.dataset + ")"});
  }
  if (has_reference(s.reference)) {
    const bool shader = s.reference.formula.empty();
    given.push_back({shader ? &kShaderField : &kReferenceField,
                     shader ? "a shader function" : "a reference"});
  }
  if (!s.materials.empty()) given.push_back({&kMaterialsField, "a material sweep"});
  if (given.empty()) {
    throw Error("no data: give a CSV file, a built-in data set, or a reference and its domain",
                kCsvField);
  }
  if (given.size() > 1) {
    throw Error("give one source of data, not both " + given[0].what + " and " + given[1].what,
                *given[1].field);
  }
  if (s.drop_missing_rows && given[0].field != &kCsvField)
    throw Error("dropping rows with gaps is for a CSV file, not for " + given[0].what,
                SourceLocation{"ProblemSource::drop_missing_rows"});
  const bool reference = given[0].field == &kReferenceField || given[0].field == &kShaderField;
  if (s.scene && !reference)
    throw Error("a scene feeds a reference: " + given[0].what + " has its samples already",
                kSceneField);
  if (s.scene && !s.domain.empty())
    throw Error("a scene supplies the reference's inputs: give no domain with it", kDomainField);
  if (s.scene && s.samples != 0)
    throw Error("a scene's samples are its pixels: give no number of samples with it",
                kSamplesField);
  if (reference) {
    if (!s.reference.formula.empty() &&
        (!s.reference.shader_source.empty() || !s.reference.shader_path.empty())) {
      throw Error("give a reference formula or a shader function, not both", kReferenceField);
    }
    return;
  }
  if (!s.domain.empty()) {
    throw Error("a domain is for a reference: " + given[0].what + " has its samples already",
                kDomainField);
  }
  if (s.samples != 0) {
    throw Error(
        "a number of samples is for a reference: " + given[0].what + " has its samples already",
        kSamplesField);
  }
  if (!s.reference.definitions.empty()) {
    throw Error("definitions are for a reference, not for " + given[0].what,
                SourceLocation{s.reference.definitions_source});
  }
  if (!s.reference.function.empty() || !s.reference.variables.empty()) {
    throw Error("a function or variables are for a reference, not for " + given[0].what,
                kReferenceField);
  }
}

// The inputs and target a caller named, checked against the columns of `data` (`what` names it:
// "xy.csv", "the reference's samples").
void check_named_columns(const Dataset& data, const std::string& what, const ProblemSource& s) {
  std::vector<std::string> numeric, text;
  for (const Column& c : data.columns) (c.numeric() ? numeric : text).push_back(c.name);
  auto check = [&](const std::string& name, const SourceLocation& field) {
    const Column* c = data.find(name);
    if (c == nullptr) {
      throw Error(
          "no column '" + name + "' in " + what + " (numeric columns: " + join(numeric) + ")",
          field);
    }
    if (!c->numeric()) {
      std::string where = c->first_non_number.source.empty()
                              ? ""
                              : ", first non-number at " + c->first_non_number.to_string();
      throw Error("column '" + name + "' of " + what + " is text, not numbers" + where +
                      " (numeric columns: " + join(numeric) + ")",
                  field);
    }
  };
  for (std::size_t i = 0; i < s.inputs.size(); ++i) {
    check(s.inputs[i], kInputsField);
    if (std::find(s.inputs.begin(), s.inputs.begin() + static_cast<std::ptrdiff_t>(i),
                  s.inputs[i]) != s.inputs.begin() + static_cast<std::ptrdiff_t>(i)) {
      throw Error("input '" + s.inputs[i] + "' is named twice", kInputsField);
    }
  }
  if (!s.target.empty()) {
    check(s.target, kTargetField);
    if (contains(s.inputs, s.target)) {
      throw Error("the target '" + s.target + "' is also an input", kTargetField);
    }
  }
}

// A CSV's inputs and target: the caller's, or inferred (the column named target or y, else the
// last numeric column; the other numeric columns), with a note on what was inferred.
void choose_csv_columns(const Dataset& data, const ProblemSource& s, Problem& p) {
  check_named_columns(data, data.source, s);
  std::vector<std::string> numeric, text;
  for (const Column& c : data.columns) (c.numeric() ? numeric : text).push_back(c.name);
  const SourceLocation header{data.source, data.header_line};
  auto too_few = [&]() {
    std::string what = numeric.empty()            ? "no numeric column"
                       : data.columns.size() == 1 ? "one column ('" + numeric[0] + "')"
                                                  : "one numeric column ('" + numeric[0] + "')";
    if (!text.empty()) what += (numeric.empty() ? " (text: " : " and text (") + join(text) + ")";
    return Error(data.source + " has " + what + ": a target and at least one input are needed",
                 header);
  };

  p.inputs = s.inputs;
  p.target = s.target;
  std::string target_reason;
  if (p.target.empty()) {
    std::vector<std::string> left;
    for (const std::string& n : numeric) {
      if (!contains(p.inputs, n)) left.push_back(n);
    }
    if (left.empty() && numeric.size() > 1) {
      throw Error("the inputs are every numeric column of " + data.source + " (" + join(numeric) +
                      "): none is left to be the target",
                  kInputsField);
    }
    if (left.size() < (p.inputs.empty() ? 2u : 1u)) throw too_few();
    if (contains(left, "target")) {
      p.target = "target";
      target_reason = "the column named target";
    } else if (contains(left, "y")) {
      p.target = "y";
      target_reason = "the column named y";
    } else {
      p.target = left.back();
      target_reason = p.inputs.empty() ? "the last numeric column"
                                       : "the last numeric column that is not an input";
    }
  }
  const bool infer_inputs = p.inputs.empty();
  if (infer_inputs) {
    for (const std::string& n : numeric) {
      if (n != p.target) p.inputs.push_back(n);
    }
    if (p.inputs.empty()) throw too_few();
  }

  if (infer_inputs && !target_reason.empty()) {
    p.notes.push_back("inputs " + join(p.inputs) + ", target " + p.target + " (" + target_reason +
                      " is the target, the other numeric columns the inputs)");
  } else if (infer_inputs) {
    p.notes.push_back("inputs " + join(p.inputs) + " (the numeric columns other than the target)");
  } else if (!target_reason.empty()) {
    p.notes.push_back("target " + p.target + " (" + target_reason + ")");
  }
  if (infer_inputs && !text.empty()) {
    p.notes.push_back(std::string(text.size() == 1 ? "text column " : "text columns ") +
                      join(text) + " not used");
  }
}

// Inputs and target with defaults of their own (a data set's, a reference's: `owner`): the
// caller's where given, the defaults (less the caller's target) where not.
void choose_own_columns(const Dataset& data, const std::string& what, const ProblemSource& s,
                        Problem& p, const std::vector<std::string>& own_inputs,
                        const std::string& own_target, const std::string& owner) {
  check_named_columns(data, what, s);
  p.target = s.target.empty() ? own_target : s.target;
  if (s.inputs.empty()) {
    for (const std::string& n : own_inputs) {
      if (n != p.target) p.inputs.push_back(n);
    }
    if (p.inputs.empty()) {
      throw Error("the target '" + p.target + "' leaves no input: name the inputs too",
                  kTargetField);
    }
  } else {
    p.inputs = s.inputs;
    if (contains(p.inputs, p.target)) {
      throw Error("input '" + p.target + "' is " + owner + " target: name another target",
                  kInputsField);
    }
  }
  std::vector<std::string> inferred;
  if (s.inputs.empty()) inferred.push_back("inputs " + join(p.inputs));
  if (s.target.empty()) inferred.push_back("target " + p.target);
  if (!inferred.empty()) p.notes.push_back(join(inferred) + " (" + owner + " own)");
}

// The domain's axes in the order given; errors at ProblemSource::domain, line = the entry.
std::vector<reference::DomainAxis> parse_domain(const std::vector<std::string>& domain) {
  std::vector<reference::DomainAxis> axes;
  for (std::size_t i = 0; i < domain.size(); ++i) {
    const int line = static_cast<int>(i) + 1;
    try {
      axes.push_back(reference::parse_domain_axis(domain[i], kDomainField.source));
    } catch (const Error& e) {
      throw Error(e.message(), {kDomainField.source, line, e.where().column});
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (axes[j].name == axes[i].name) {
        throw Error("two domains for '" + axes[i].name + "' (entries " + std::to_string(j + 1) +
                        " and " + std::to_string(i + 1) + ")",
                    {kDomainField.source, line});
      }
    }
  }
  return axes;
}

// The reference compiled with its inputs in domain order, after checking that the domain
// covers exactly the reference's variables.
reference::Program compile_over_domain(reference::ReferenceText text,
                                       const std::vector<reference::DomainAxis>& axes) {
  std::vector<std::string> order;
  for (const reference::DomainAxis& a : axes) order.push_back(a.name);
  reference::Program first;
  try {
    first = reference::compile_reference(text);
  } catch (const Error& e) {
    // A shader function's overloads are told apart by their parameters: the domain's names pick
    // one.
    if (text.shader_source.empty() || !text.variables.empty()) throw;
    reference::ReferenceText ordered = text;
    ordered.variables = order;
    try {
      return reference::compile_reference(ordered);
    } catch (const Error&) {
      throw e;
    }
  }
  if (first.inputs.empty()) {
    throw Error("the reference uses no variable: there is nothing to approximate", kReferenceField);
  }
  for (const std::string& v : first.inputs) {
    if (std::none_of(axes.begin(), axes.end(),
                     [&](const reference::DomainAxis& a) { return a.name == v; })) {
      throw Error("no domain for variable '" + v + "' (give one: " + v + "=lo:hi)", kDomainField);
    }
  }
  for (std::size_t i = 0; i < axes.size(); ++i) {
    if (!contains(first.inputs, axes[i].name)) {
      throw Error("a domain for '" + axes[i].name + "', which the reference does not use (its " +
                      (first.inputs.size() == 1 ? "variable: " : "variables: ") +
                      join(first.inputs) + ")",
                  {kDomainField.source, static_cast<int>(i) + 1});
    }
  }
  if (order == first.inputs) return first;
  text.variables = std::move(order);
  return reference::compile_reference(text);
}

// "x = 1.5, y = 0.25".
std::string point_text(const Dataset& data, const std::vector<reference::DomainAxis>& axes,
                       std::size_t row) {
  std::string out;
  for (const reference::DomainAxis& a : axes) {
    out +=
        (out.empty() ? "" : ", ") + a.name + " = " + number_text(data.numeric(a.name).values[row]);
  }
  return out;
}

// "x in [1.25, 2], y in [0, 1]": the range of the domain's variables over `rows`.
std::string span_text(const Dataset& data, const std::vector<reference::DomainAxis>& axes,
                      const std::vector<std::size_t>& rows) {
  std::string out;
  for (const reference::DomainAxis& a : axes) {
    const std::vector<double>& v = data.numeric(a.name).values;
    double lo = v[rows[0]], hi = v[rows[0]];
    for (std::size_t r : rows) {
      lo = std::min(lo, v[r]);
      hi = std::max(hi, v[r]);
    }
    out += (out.empty() ? "" : ", ") + a.name + " in [" + number_text(lo) + ", " + number_text(hi) +
           "]";
  }
  return out;
}

// Rows where the target or an input is NaN or infinite: an error, or dropped with a note.
void check_finite(Problem& p, const std::vector<reference::DomainAxis>& axes, bool drop) {
  std::vector<const Column*> used = {&p.data.numeric(p.target)};
  for (const std::string& name : p.inputs) used.push_back(&p.data.numeric(name));
  const std::size_t rows = p.data.rows();
  std::vector<std::size_t> bad;
  std::string first_column;
  for (std::size_t r = 0; r < rows; ++r) {
    for (const Column* c : used) {
      if (!std::isfinite(c->values[r])) {
        if (bad.empty()) first_column = c->name;
        bad.push_back(r);
        break;
      }
    }
  }
  if (bad.empty()) return;
  const std::string what =
      first_column == reference::kReferenceOutput ? "the reference" : "'" + first_column + "'";
  const std::string where = "first at " + point_text(p.data, axes, bad[0]) + "; they span " +
                            span_text(p.data, axes, bad);
  if (!drop || bad.size() == rows) {
    throw Error(what + " is NaN or infinite at " + format_count(bad.size()) + " of " +
                    format_count(rows) + " samples, " + where +
                    (bad.size() == rows
                         ? ""
                         : " (narrow the domain, or drop them: ProblemSource::drop_nonfinite)"),
                kReferenceField);
  }
  std::vector<bool> keep(rows, true);
  for (std::size_t r : bad) keep[r] = false;
  for (Column& c : p.data.columns) {
    std::vector<double> kept;
    kept.reserve(rows - bad.size());
    for (std::size_t r = 0; r < rows; ++r) {
      if (keep[r]) kept.push_back(c.values[r]);
    }
    c.values = std::move(kept);
  }
  p.notes.push_back("dropped " + format_count(bad.size()) + " of " + format_count(rows) +
                    " samples where " + what + " is NaN or infinite, " + where);
}

Problem load_csv(const ProblemSource& s) {
  Problem p;
  p.data = read_csv(s.csv_path, {.drop_missing_rows = s.drop_missing_rows});
  p.description = s.csv_path;
  if (p.data.dropped_rows > 0)
    p.notes.push_back("dropped " + format_count(p.data.dropped_rows) + " of " +
                      format_count(p.data.dropped_rows + p.data.rows()) +
                      " rows with an empty or non-number cell in a column of numbers, first at "
                      "line " + std::to_string(p.data.first_dropped_line));
  choose_csv_columns(p.data, s, p);
  return p;
}

Problem load_dataset(const ProblemSource& s) {
  Rng rng(s.dataset_seed);
  Problem p;
  p.data = builtin_dataset(s.dataset, rng, FresnelSeedOptions{}.rows, kDatasetField);
  p.description = s.dataset + " (seed " + std::to_string(s.dataset_seed) + ")";
  if (std::optional<BuiltinDatasetInfo> info = builtin_dataset_info(s.dataset)) {
    choose_own_columns(p.data, s.dataset, s, p, info->inputs, info->target, "the data set's");
    p.operators = info->operators;
    p.evolution_operators = info->evolution_operators;
  } else {
    choose_csv_columns(p.data, s, p);
  }
  return p;
}

Problem load_sweep(const ProblemSource& s) {
  std::vector<Material> materials;
  std::string names;
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    if (s.materials[i] == "seed") {
      for (const Material& m : seed_materials()) materials.push_back(m);
    } else {
      materials.push_back(
          parse_material(s.materials[i], {kMaterialsField.source, static_cast<int>(i) + 1}));
    }
  }
  if (s.angles < 2)
    throw Error("a sweep needs at least 2 angles, got " + std::to_string(s.angles), kAnglesField);
  for (const Material& m : materials) names += (names.empty() ? "" : ", ") + m.name;
  Problem p;
  p.data = make_fresnel_sweep(materials, s.angles);
  p.description =
      "the Fresnel sweep of " + names + " (" + std::to_string(s.angles) + " angles each)";
  choose_own_columns(p.data, "the material sweep", s, p, {"r0", "x"}, "R", "the sweep's");
  return p;
}

Problem load_reference(const ProblemSource& s) {
  reference::ReferenceText text = s.reference;
  if (text.formula.empty() && text.shader_source.empty()) {
    text.shader_source = reference::read_shader_file(text.shader_path);
  }
  std::vector<reference::DomainAxis> axes = parse_domain(s.domain);
  reference::Program program = compile_over_domain(text, axes);

  const bool counted = std::all_of(axes.begin(), axes.end(),
                                   [](const reference::DomainAxis& a) { return a.count > 0; });
  if (s.samples != 0 && counted) {
    throw Error(
        "every variable has its number of points (a grid): a number of samples does "
        "not apply",
        kSamplesField);
  }
  if (s.samples > kMaxDesignPoints || (s.samples == 1 && axes.size() == 1)) {
    throw Error(s.samples == 1 ? "one variable needs at least 2 samples (both ends), not 1"
                               : "at most " + format_count(kMaxDesignPoints) + " samples, not " +
                                     format_count(s.samples),
                kSamplesField);
  }
  const SampleColumns samples = sample_domain(axes, s.samples, 1, kDomainField);
  std::vector<std::span<const double>> inputs(samples.begin(), samples.end());
  std::vector<std::vector<double>> outputs = program.evaluate_columns(inputs);

  Problem p;
  p.data.source = program.description;
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    p.data.add_numeric(program.output_names[i], std::move(outputs[i]));
  }
  std::vector<std::string> variables;
  for (const reference::DomainAxis& a : axes) variables.push_back(a.name);
  choose_own_columns(p.data, "the reference's samples", s, p, variables,
                     std::string(reference::kReferenceOutput), "the reference's");
  const std::size_t sampled = p.data.rows();
  check_finite(p, axes, s.drop_nonfinite);

  std::string on;
  for (const reference::DomainAxis& a : axes) {
    on += (on.empty() ? "" : ", ") + a.name + " in [" + number_text(a.lo) + ", " +
          number_text(a.hi) + "]";
  }
  p.description = program.description + " on " + on + ", " + format_count(sampled) + " samples";
  if (p.data.rows() != sampled) {
    p.description += " (" + format_count(sampled - p.data.rows()) + " dropped)";
  }

  auto function = std::make_shared<reference::ReferenceFunction>();
  function->program = std::move(program);
  function->domain = std::move(axes);
  function->target = p.target;
  function->validate();
  p.reference = std::move(function);
  return p;
}

// The reference at every shading sample of the scene; its variables must be scene quantities,
// and the inputs the variables it uses.
Problem load_scene(const ProblemSource& s) {
  reference::ReferenceText text = s.reference;
  SceneSpec spec = *s.scene;
  std::string bound;
  if (!text.formula.empty()) {
    if (const std::optional<SceneReference> b = scene_reference(text.formula)) {
      bound = text.formula;
      text.formula = b->formula;
      if (!spec.term) spec.term = b->term;
    }
  } else if (text.shader_source.empty()) {
    text.shader_source = reference::read_shader_file(text.shader_path);
  }
  if (!spec.term)
    throw Error(
        "which factor of the specular term does the reference stand for? Give the term: F, V, D "
        "or FV",
        SourceLocation{"SceneSpec::term"});
  const SceneSamples samples = render_scene(spec);
  reference::Program program = reference::compile_reference(text);
  if (program.inputs.empty())
    throw Error("the reference uses no variable: there is nothing to approximate", kReferenceField);
  std::vector<std::span<const double>> inputs;
  for (const std::string& v : program.inputs)
    inputs.push_back(samples.column(v, kReferenceField.source));
  std::vector<std::vector<double>> outputs = program.evaluate_columns(inputs);

  Problem p;
  p.data.source = program.description;
  for (std::size_t i = 0; i < program.inputs.size(); ++i)
    p.data.add_numeric(program.inputs[i], std::vector<double>(inputs[i].begin(), inputs[i].end()));
  for (std::size_t i = 0; i < outputs.size(); ++i)
    if (!p.data.find(program.output_names[i]))
      p.data.add_numeric(program.output_names[i], std::move(outputs[i]));
  for (const std::string& n : s.inputs)
    if (!contains(program.inputs, n)) {
      if (p.data.find(n)) continue;  // a definition's output
      const bool quantity = std::find(scene_quantity_names().begin(), scene_quantity_names().end(),
                                      n) != scene_quantity_names().end();
      throw Error(quantity ? "input '" + n + "' is a scene quantity the reference does not use " +
                                 "(it uses " + join(program.inputs) + ")"
                           : "input '" + n + "' is not a quantity of the " +
                                 std::string(scene_kind_name(spec.kind)) + " scene",
                  kInputsField);
    }
  choose_own_columns(p.data, "the scene's samples", s, p, program.inputs,
                     std::string(reference::kReferenceOutput), "the reference's");
  const std::vector<double>& target = p.data.numeric(p.target).values;
  for (std::size_t r = 0; r < target.size(); ++r)
    if (!std::isfinite(target[r]))
      throw Error("the reference is NaN or infinite at sample " + std::to_string(r + 1) +
                      " of the scene, where " + program.inputs[0] + " = " +
                      number_text(inputs[0][r]),
                  kReferenceField);
  p.display_weights = display_weights(samples, target);
  const SceneSpec& used = samples.spec;
  p.description = program.description + " as " + std::string(shading_term_name(*used.term)) +
                  " in the " + std::string(scene_kind_name(used.kind)) + " scene, " +
                  format_count(samples.samples()) + " shading samples of " +
                  std::to_string(samples.width) + " x " + std::to_string(samples.height) +
                  " pixels";
  if (!bound.empty()) p.notes.push_back("the reference " + bound + " is " + text.formula);
  p.scene = std::make_shared<const SceneSamples>(samples);
  return p;
}

}  // namespace

Problem load_problem(const ProblemSource& source) {
  check_source(source);
  if (!source.csv_path.empty()) return load_csv(source);
  if (!source.dataset.empty()) return load_dataset(source);
  if (!source.materials.empty()) return load_sweep(source);
  if (source.scene) return load_scene(source);
  return load_reference(source);
}

}  // namespace shaderfit
