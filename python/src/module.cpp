// shaderfit._shaderfit: the library as the Python package sees it (python/shaderfit/ is the
// user-facing layer; docs/python.md). Each function takes arrays and text and returns arrays,
// handles and the commands' JSON, so that the formats stay the library's own.
//
// Errors: shaderfit::Error becomes shaderfit.Error (a ValueError) with the library's message and
// location; bad argument types are TypeErrors raised by nanobind. Nothing here ends the process.
#include <nanobind/nanobind.h>
#include <nanobind/stl/function.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "arrays.hpp"
#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/cost/per_material.hpp"
#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/eval/evaluate_in.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/fit/fit_setup.hpp"
#include "shaderfit/image/flip.hpp"
#include "shaderfit/problem/problem.hpp"
#include "shaderfit/report/command_json.hpp"
#include "shaderfit/report/search_json.hpp"
#include "shaderfit/search/front/choice.hpp"
#include "shaderfit/search/options.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit::python {

namespace {

// ---- errors ---------------------------------------------------------------------------------

// shaderfit.Error(message, source, line, column), defined in python/shaderfit/_errors.py.
void raise_error(const Error& e) {
  static nb::object cls = nb::module_::import_("shaderfit._errors").attr("Error");
  const SourceLocation& w = e.where();
  nb::object exc = cls(e.message(), w.source, w.line, w.column);
  PyErr_SetObject(cls.ptr(), exc.ptr());
}

// ---- formulas -------------------------------------------------------------------------------

// A formula over named inputs, with its parameters' values: what a front member, evaluate(),
// cost() and codegen() work on.
struct Formula {
  Expression expression;

  std::string infix(int digits, bool exact) const {
    return exact ? to_infix(expression) : to_infix(expression, PrintOptions::for_people(digits));
  }
  std::string latex(int digits) const {
    return to_latex(expression, PrintOptions::for_people(digits));
  }

  // One column per variable, in the order of expression.variables; in `precision` (double,
  // float or half: eval/evaluate_in.hpp).
  OutArray evaluate(const std::vector<Column>& columns, const std::string& precision) const {
    const Precision p = parse_precision(precision, {"precision"});
    if (columns.size() != expression.variables.size())
      throw Error("expected " + std::to_string(expression.variables.size()) +
                      " columns (one per input), got " + std::to_string(columns.size()),
                  {"X"});
    const std::vector<std::vector<double>> data = to_columns(columns, expression.variables);
    const std::size_t rows = data.empty() ? 0 : data.front().size();
    std::vector<const double*> pointers;
    for (std::size_t i = 0; i < data.size(); ++i) {
      if (data[i].size() != rows) throw Error("columns of unequal length", {"X"});
      pointers.push_back(data[i].data());
    }
    std::vector<double> out(rows);
    if (data.empty()) {  // a constant formula: one value per row is unknowable without rows
      throw Error("the formula has no inputs; give it at least one", {"X"});
    }
    {
      nb::gil_scoped_release release;
      if (p == Precision::Double)
        shaderfit::evaluate(expression, pointers, out);
      else
        evaluate_in(p, expression, pointers, out);
    }
    return to_numpy(std::move(out));
  }

  // The shaderfit.cost/1 document of `shaderfit cost` (docs/cost-model.md), for `shown`.
  // With per-material inputs the counts are per pixel, the per-material ones beside them.
  std::string cost_json_text(const std::string& shown,
                             const std::vector<std::string>& uniform) const {
    const InstructionTarget target = parse_instruction_target(shown, {"target"});
    return cost_json(expression, cost_table(expression, target, uniform, {"uniform"}));
  }

  double search_cost(const std::string& cost) const {
    const auto target = cost_target_from_name(cost);
    if (!target) throw Error("unknown cost '" + cost + "' (known: instructions, nodes)", {"cost"});
    return expression_cost(expression, *target);
  }

  // A source file that compiles as printed (generate_source), parameters baked in.
  std::string code(const std::string& language, const std::string& name,
                   const std::vector<std::string>& uniform, const std::string& precision) const {
    const auto lang = language_from_name(language);
    if (!lang)
      throw Error("unknown language '" + language + "' (known: glsl, hlsl, cuda, cpp, metal)",
                  {"lang"});
    SourceFunction f{expression, {}};
    f.options.name = name;
    f.options.bake_parameters = true;
    check_uniform_inputs(uniform, expression.variables, {"uniform"});
    f.options.uniform = uniform;
    f.options.precision = parse_precision(precision, {"precision"});
    f.options.comment = {to_infix(expression, PrintOptions::for_people()),
                         cost_comment(expression, uniform, f.options.precision)};
    return generate_source(std::span<const SourceFunction>(&f, 1), *lang);
  }
};

Formula parse(const std::string& text, const std::vector<std::string>& inputs,
              const std::vector<std::string>& parameters, const std::vector<double>& values) {
  ParseOptions o;
  o.variables = inputs;
  o.parameters = parameters;
  o.parameter_values = values;
  return Formula{parse_formula(text, o)};
}

// ---- search ---------------------------------------------------------------------------------

// The library's options from the Python layer's text values (search_option_text's forms):
// unknown names, text that does not parse and values out of range throw Error located at the
// field, with the messages the command line gives.
SearchOptions make_options(const std::vector<std::pair<std::string, std::string>>& texts) {
  SearchOptions o;
  for (const auto& [name, text] : texts) {
    const SearchOptionField* f = find_search_option(name);
    if (f == nullptr) throw Error("unknown option '" + name + "'", {"SearchOptions"});
    set_search_option(o, *f, text);
  }
  o.validate();
  o.device = search_device(o);
  return o;
}

// ---- problems ---------------------------------------------------------------------------------

// What to approximate, stated as the command line states it (problem/problem.hpp): a CSV file, a
// built-in data set or a reference sampled on a domain. The Python layer passes its keywords as
// text; a reference file is read here.
struct LoadedProblem {
  Problem problem;
  ProblemSource source;  // as loaded: inputs and target chosen, a file's text in it

  std::vector<std::string> inputs() const { return problem.inputs; }
  std::string target() const { return problem.target; }
  std::string description() const { return problem.description; }
  std::vector<std::string> notes() const { return problem.notes; }
  std::string operators() const { return problem.operators; }
  std::string evolution_operators() const { return problem.evolution_operators; }
  std::string source_json() const { return problem_source_json(source).dump(); }
  // Each numeric column by name, as float64 arrays.
  nb::dict columns() const {
    nb::dict out;
    for (const shaderfit::Column& c : problem.data.columns)
      if (c.numeric()) out[c.name.c_str()] = to_numpy(c.values);
    return out;
  }
};

LoadedProblem load(const std::string& csv_path, const std::string& dataset,
                   std::uint64_t dataset_seed, const std::string& reference,
                   const std::string& reference_file, const std::string& function,
                   const std::vector<std::string>& domain, const std::vector<std::string>& define,
                   std::size_t samples, bool drop_nonfinite, bool drop_missing,
                   const std::vector<std::string>& inputs, const std::string& target,
                   const std::string& scene, const std::string& term) {
  ProblemSource s;
  s.csv_path = csv_path;
  s.dataset = dataset;
  s.dataset_seed = dataset_seed;
  s.reference.formula = reference;
  s.reference.function = function;
  s.reference.definitions = define;
  s.reference.formula_source = "reference";
  s.reference.definitions_source = "define";
  s.domain = domain;
  s.samples = samples;
  s.drop_nonfinite = drop_nonfinite;
  s.drop_missing_rows = drop_missing;
  s.inputs = inputs;
  s.target = target;
  if (!reference_file.empty()) {
    s.reference.shader_source = reference::read_shader_file(reference_file);
    s.reference.shader_path = reference_file;
    if (function.empty())
      throw Error("name the function of the reference file to approximate", {"function"});
  }
  if (!scene.empty()) {
    s.scene = scene_spec_from_names(scene, term);
  } else if (!term.empty()) {
    throw Error("a term is for a scene: give scene=...", {"ProblemSource::scene"});
  }
  LoadedProblem out{load_problem(s), s};
  if (out.problem.scene) out.source.scene = out.problem.scene->spec;
  out.source.inputs = out.problem.inputs;
  out.source.target = out.problem.target;
  return out;
}

// What the search thread hands to the Python thread.
struct Event {
  enum class Kind { Member, Progress } kind;
  FrontMember member;
  SearchProgress progress;
};

// A finished search: the summary, the options it ran with (auto operators resolved), and what
// the JSON says of the data.
struct SearchRun {
  SearchSummary summary;
  SearchOptions options;
  SearchDataInfo data;

  std::string json() const { return search_json(summary, options, data); }
  std::vector<Formula> formulas() const {
    std::vector<Formula> out;
    for (const FrontMember& m : summary.front) out.push_back(Formula{m.expression});
    return out;
  }
  bool interrupted() const { return summary.interrupted; }
  std::string termination() const { return std::string(termination_name(summary.termination)); }
  std::string summary_text() const { return summary.brief_report(); }
};

nb::dict member_event(const FrontMember& m) {
  nb::dict d;
  d["formula"] = m.formula;
  d["formula_display"] = to_infix(m.expression, PrintOptions::for_people());
  d["cost"] = m.cost;
  d["loss"] = m.loss;
  d["time_s"] = m.time_s;
  d["origin"] = std::string(search_phase_name(m.origin));
  return d;
}

nb::dict progress_event(const SearchProgress& p) {
  nb::dict d;
  d["elapsed_s"] = p.elapsed_s;
  d["candidates"] = p.candidates;
  d["candidates_per_s"] = p.candidates_per_s;
  d["front_size"] = p.front_size;
  d["phase"] = std::string(search_phase_name(p.phase));
  return d;
}

// Runs the search on its own thread while this one, holding the GIL only briefly, hands its
// events to the callbacks and checks for signals: Ctrl-C (KeyboardInterrupt) stops the search,
// which returns the front found so far (SearchRun::interrupted). An exception from a callback
// stops it too, and is raised once the search has returned.
// `from`: the problem when the data was stated as one (load_problem); columns, names and
// target are then ignored, and the problem's reference checks the front between the samples.
SearchRun run(const std::vector<Column>& columns, const std::vector<std::string>& names,
              const Column& target, std::optional<Column> weights,
              const std::vector<std::pair<std::string, std::string>>& option_texts,
              std::optional<nb::callable> on_member, std::optional<nb::callable> on_progress,
              const std::string& source, const std::string& target_name,
              const LoadedProblem* from) {
  const auto t0 = std::chrono::steady_clock::now();
  SearchRun result;
  SearchOptions options = make_options(option_texts);
  SearchProblem problem;
  if (from != nullptr) {
    problem = search_problem(from->problem, options.loss);
    problem.reference_samples = from->source.samples;
  } else {
    problem.input_names = names;
    if (columns.size() != names.size())
      throw Error("expected one name per column: " + std::to_string(columns.size()) + " columns, " +
                      std::to_string(names.size()) + " names",
                  {"inputs"});
    problem.inputs = to_columns(columns, names);
    problem.target = to_doubles(target, "y");
    if (options.loss == Loss::Display)
      throw Error(
          "the display loss needs a scene: the pixels the function shades weigh the "
          "rows (reference=..., scene=...; docs/scenes.md)",
          {"SearchOptions::loss"});
  }
  if (weights) problem.weights = to_doubles(*weights, "weights");
  problem.validate();
  options = resolve_auto_operators(options, problem);
  result.data =
      SearchDataInfo{from != nullptr ? from->problem.description : source,
                     from != nullptr ? from->problem.target : target_name,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                     problem.target.size(), problem.input_names};
  if (from != nullptr) result.data.problem = from->source;

  std::mutex mutex;
  std::condition_variable wake;
  std::deque<Event> events;
  bool done = false;
  std::atomic<bool> stop{false};
  std::exception_ptr failure;
  SearchOptions running = options;
  running.interrupt = &stop;
  if (on_member) {
    running.on_new_member = [&](const FrontMember& m) {
      std::lock_guard lock(mutex);
      events.push_back({Event::Kind::Member, m, {}});
      wake.notify_one();
    };
  }
  if (on_progress) {
    running.on_progress = [&](const SearchProgress& p) {
      std::lock_guard lock(mutex);
      events.push_back({Event::Kind::Progress, {}, p});
      wake.notify_one();
    };
  }

  std::optional<nb::python_error> raised;  // from a callback, raised after the search
  {
    nb::gil_scoped_release release;
    std::thread worker([&] {
      try {
        run_search(running, problem, &result.summary);
      } catch (...) {
        failure = std::current_exception();
      }
      std::lock_guard lock(mutex);
      done = true;
      wake.notify_one();
    });
    for (;;) {
      std::deque<Event> batch;
      bool finished = false;
      {
        std::unique_lock lock(mutex);
        wake.wait_for(lock, std::chrono::milliseconds(50), [&] { return done || !events.empty(); });
        batch.swap(events);
        finished = done;
      }
      nb::gil_scoped_acquire gil;
      if (!stop.load() && PyErr_CheckSignals() != 0) {
        // KeyboardInterrupt (or another signal handler's exception): stop and keep the front.
        if (PyErr_ExceptionMatches(PyExc_KeyboardInterrupt) != 0)
          PyErr_Clear();
        else
          raised.emplace();
        stop.store(true);
      }
      for (const Event& e : batch) {
        if (raised) break;
        try {
          if (e.kind == Event::Kind::Member)
            (*on_member)(member_event(e.member));
          else
            (*on_progress)(progress_event(e.progress));
        } catch (nb::python_error& err) {
          raised.emplace(std::move(err));
          stop.store(true);
        }
      }
      if (finished) break;
    }
    worker.join();
  }
  if (raised) throw std::move(*raised);
  if (failure) std::rethrow_exception(failure);
  result.options = options;  // without the callbacks, which point into this frame
  return result;
}

// The member `rule` picks ("knee", "cost=N", "error=E") from a front given as its members'
// costs, errors and origins (cheapest first): (index, why).
std::pair<std::size_t, std::string> choose(const std::vector<double>& costs,
                                           const std::vector<double>& errors,
                                           const std::vector<std::string>& origins,
                                           const std::string& rule_text,
                                           const std::string& error_name) {
  const ChoiceRule rule = parse_choice_rule(rule_text, {"ChoiceRule"});
  if (costs.size() != errors.size() || costs.size() != origins.size())
    throw Error("one error and one origin per cost", {"errors"});
  std::vector<FrontMember> front(costs.size());
  for (std::size_t i = 0; i < costs.size(); ++i) {
    front[i].cost = costs[i];
    front[i].loss = errors[i];
    front[i].origin = search_phase_from_name(origins[i]).value_or(SearchPhase::Enumeration);
  }
  const Choice c = choose_member(front, rule, error_name);
  return {c.index, c.why};
}

std::vector<nb::dict> option_fields() {
  std::vector<nb::dict> out;
  const SearchOptions defaults;
  for (const SearchOptionField& f : search_option_fields()) {
    nb::dict d;
    d["name"] = std::string(f.name);
    d["kind"] = std::string(option_kind_name(search_option_kind(f)));
    d["role"] = std::string(f.role == OptionRole::Search   ? "search"
                            : f.role == OptionRole::Budget ? "budget"
                                                           : "run");
    d["help"] = std::string(f.help);
    d["choices"] = std::string(f.choices);
    d["may_be_empty"] = f.may_be_empty;
    d["default"] = search_option_text(defaults, f);
    out.push_back(d);
  }
  return out;
}

// ---- fit, rational, data sets -----------------------------------------------------------------

// `shaderfit fit` on arrays, or on a domain the library samples: shaderfit.fit/1 (docs/fit.md).
// The reference is the target array, or a reference-language formula over the columns (or the
// domain's variables and the definitions), or the function `function` of a GLSL or HLSL source.
std::string fit_document(const std::string& formula, const std::vector<Column>& columns,
                         const std::vector<std::string>& names, std::optional<Column> target,
                         const std::string& target_name, std::optional<Column> weights,
                         std::optional<std::vector<std::string>> groups,
                         const std::string& group_name, const std::vector<std::string>& parameters,
                         const std::vector<std::string>& per_group, const std::string& loss,
                         const std::string& solver, const std::vector<std::string>& constraints,
                         const std::string& transform, const std::vector<std::string>& baselines,
                         int max_iterations, int threads, const std::string& reference,
                         const std::vector<std::string>& definitions,
                         const std::vector<std::string>& domain, std::size_t samples,
                         const std::string& reference_source, const std::string& reference_path,
                         const std::string& function) {
  FitSetup s;
  if (domain.empty()) {
    Dataset d;
    d.source = "arrays";
    if (columns.size() != names.size()) throw Error("expected one name per column", {"inputs"});
    for (std::size_t i = 0; i < columns.size(); ++i)
      d.add_numeric(names[i], to_doubles(columns[i], names[i]));
    if (target) {
      d.add_numeric(target_name, to_doubles(*target, "y"));
      s.target = target_name;
    }
    if (weights) {
      d.add_numeric("__weights", to_doubles(*weights, "weights"));
      s.weight = "__weights";
    }
    if (groups) d.add_text(group_name, *groups);
    s.data = std::move(d);
    s.data_name = "arrays";
  } else if (weights || groups || target) {
    throw Error("a sampled domain has its own rows: no X, y, weights or groups with it",
                {"domain"});
  }
  s.domain = domain;
  s.samples = samples;
  s.reference = reference;
  s.definitions = definitions;
  s.reference_source = reference_source;
  s.reference_path = reference_path;
  s.function = function;
  s.formula = formula;
  s.parameters = parameters;
  s.per_group = per_group;
  s.constraints = constraints;
  s.transform = transform;
  s.baselines = baselines;
  const auto l = loss_from_name(loss);
  if (!l) throw Error("unknown loss '" + loss + "' (known: mse, log, max_abs)", {"loss"});
  s.options.loss = *l;
  const std::optional<SolverKind> kind = solver_kind_from_name(solver);
  if (!kind) throw Error("unknown solver '" + solver + "' (known: auto, linear, lm)", {"solver"});
  s.options.solver = *kind;
  s.options.max_iterations = max_iterations;
  s.options.threads = threads;
  const PreparedFit p = prepare_fit(std::move(s));
  FixedFormSummary summary;
  {
    nb::gil_scoped_release release;
    solve_fixed_form(p.options, p.problem, &summary);
  }
  return fit_json(p, summary, compare_blocks(p, summary));
}

// `shaderfit rational`: shaderfit.rational/1 (docs/rational.md). The target is a built-in, a
// reference-language formula in `variable`, or the function `function` of a GLSL or HLSL source.
std::string rational_document(const std::string& target, const std::string& variable,
                              const std::string& domain, const std::vector<std::string>& conditions,
                              const std::vector<std::string>& forms,
                              const std::vector<std::string>& transforms,
                              const std::vector<std::string>& parameters, int count,
                              const std::string& fit, bool relative_minimax,
                              const std::string& rank_by, const std::string& reference_source,
                              const std::string& reference_path, const std::string& function) {
  rational::RationalSetup s;
  s.target = target;
  s.variable = variable;
  s.reference_source = reference_source;
  s.reference_path = reference_path;
  s.function = function;
  s.domain = domain;
  s.conditions = conditions;
  s.forms = forms;
  s.transforms = transforms;
  s.parameters = parameters;
  s.count = count;
  bool known = false;
  for (rational::Fit f : {rational::Fit::None, rational::Fit::LeastSquares, rational::Fit::Minimax})
    if (rational::fit_name(f) == fit) {
      s.fit = f;
      known = true;
    }
  if (!known) throw Error("unknown fit '" + fit + "' (known: none, lsq, minimax)", {"fit"});
  s.relative_minimax = relative_minimax;
  const auto rank = loss_from_name(rank_by);
  if (!rank || (*rank != Loss::Rmse && *rank != Loss::MaxAbs && *rank != Loss::MaxRel))
    throw Error("unknown ranking '" + rank_by + "' (known: rmse, max_abs, max_rel)", {"rank_by"});
  s.rank_by = *rank;
  rational::PreparedRational prepared = rational::prepare_rational(s);
  std::optional<rational::RationalReport> report;
  {
    nb::gil_scoped_release release;
    report = rational::solve_prepared(prepared);
  }
  return rational_json(*report);
}

// A built-in data set: each column by name, numbers as float64 arrays, text as lists.
nb::dict dataset(const std::string& name, std::uint64_t seed, std::size_t rows) {
  Rng rng(seed);
  const std::optional<Dataset> d = make_builtin_dataset(name, rng, rows);
  if (!d) {
    std::string known;
    for (const std::string& n : builtin_dataset_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error("unknown data set '" + name + "' (known: " + known + ")", {"name"});
  }
  nb::dict out;
  for (const shaderfit::Column& c : d->columns) {
    if (c.numeric())
      out[c.name.c_str()] = to_numpy(c.values);
    else
      out[c.name.c_str()] = nb::cast(c.labels);
  }
  return out;
}

// LDR-FLIP of two H x W x 3 sRGB images (float32, C order): the per-pixel error, flattened
// row-major, and its mean. python/tests/flip_agreement_test.py compares it with flip-evaluator.
using ImageArray = nb::ndarray<const float, nb::ndim<3>, nb::c_contig, nb::device::cpu>;

RgbImage to_rgb_image(const ImageArray& a, const char* where) {
  if (a.shape(2) != 3) throw Error("expected an H x W x 3 array", {where});
  return {static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)),
          std::vector<float>(a.data(), a.data() + a.size())};
}

std::pair<OutArray, double> flip(const ImageArray& reference, const ImageArray& test,
                                 double pixels_per_degree) {
  const RgbImage r = to_rgb_image(reference, "reference"), t = to_rgb_image(test, "test");
  FlipResult result;
  {
    nb::gil_scoped_release release;
    result = ldr_flip(r, t, FlipOptions{pixels_per_degree});
  }
  return {to_numpy(std::vector<double>(result.error.begin(), result.error.end())), result.mean};
}

}  // namespace

}  // namespace shaderfit::python

using namespace shaderfit;
using namespace shaderfit::python;

NB_MODULE(_shaderfit, m) {
  m.doc() = "shaderfit's C++ library; use the shaderfit package, not this module.";
  nb::register_exception_translator([](const std::exception_ptr& p, void*) {
    try {
      std::rethrow_exception(p);
    } catch (const Error& e) {
      raise_error(e);
    }
  });

  nb::class_<Formula>(m, "Formula")
      .def_prop_ro("variables", [](const Formula& f) { return f.expression.variables; })
      .def_prop_ro("parameters", [](const Formula& f) { return f.expression.parameters; })
      .def_prop_ro("parameter_values",
                   [](const Formula& f) { return f.expression.parameter_values; })
      .def("infix", &Formula::infix, nb::arg("digits") = 0, nb::arg("exact") = false)
      .def("latex", &Formula::latex, nb::arg("digits") = 0)
      .def("evaluate", &Formula::evaluate, nb::arg("columns"), nb::arg("precision") = "double")
      .def("cost_json", &Formula::cost_json_text, nb::arg("target") = "sass",
           nb::arg("uniform") = std::vector<std::string>{})
      .def("search_cost", &Formula::search_cost, nb::arg("cost") = "instructions")
      .def("code", &Formula::code, nb::arg("language"), nb::arg("name"),
           nb::arg("uniform") = std::vector<std::string>{}, nb::arg("precision") = "float")
      // Pickled as its exact infix with parameters by name, and their values: parse_formula
      // reads that back to a formula that evaluates equal on every input.
      .def("__getstate__",
           [](const Formula& f) {
             return std::make_tuple(to_infix(f.expression), f.expression.variables,
                                    f.expression.parameters, f.expression.parameter_values);
           })
      .def("__setstate__", [](Formula& f,
                              const std::tuple<std::string, std::vector<std::string>,
                                               std::vector<std::string>, std::vector<double>>& s) {
        new (&f) Formula(parse(std::get<0>(s), std::get<1>(s), std::get<2>(s), std::get<3>(s)));
      });
  m.def("parse", &parse, nb::arg("text"), nb::arg("inputs"), nb::arg("parameters"),
        nb::arg("values"));

  nb::class_<SearchRun>(m, "SearchRun")
      .def("json", &SearchRun::json)
      .def("formulas", &SearchRun::formulas)
      .def_prop_ro("interrupted", &SearchRun::interrupted)
      .def_prop_ro("termination", &SearchRun::termination)
      .def("summary_text", &SearchRun::summary_text);
  m.def("choose", &choose, nb::arg("costs"), nb::arg("errors"), nb::arg("origins"),
        nb::arg("rule"), nb::arg("error_name"));
  m.def("option_fields", &option_fields);
  m.def("check_options", [](const std::vector<std::pair<std::string, std::string>>& texts) {
    (void)make_options(texts);
  });
  nb::class_<LoadedProblem>(m, "Problem")
      .def_prop_ro("inputs", &LoadedProblem::inputs)
      .def_prop_ro("target", &LoadedProblem::target)
      .def_prop_ro("description", &LoadedProblem::description)
      .def_prop_ro("notes", &LoadedProblem::notes)
      .def_prop_ro("operators", &LoadedProblem::operators)
      .def_prop_ro("evolution_operators", &LoadedProblem::evolution_operators)
      .def("source_json", &LoadedProblem::source_json)
      .def("columns", &LoadedProblem::columns);
  m.def("load_problem", &load, nb::arg("csv_path"), nb::arg("dataset"), nb::arg("dataset_seed"),
        nb::arg("reference"), nb::arg("reference_file"), nb::arg("function"), nb::arg("domain"),
        nb::arg("define"), nb::arg("samples"), nb::arg("drop_nonfinite"), nb::arg("drop_missing"),
        nb::arg("inputs"), nb::arg("target"), nb::arg("scene"), nb::arg("term"));
  m.def("search", &run, nb::arg("columns"), nb::arg("names"), nb::arg("target"),
        nb::arg("weights").none(), nb::arg("options"), nb::arg("on_member").none(),
        nb::arg("on_progress").none(), nb::arg("source"), nb::arg("target_name"),
        nb::arg("problem").none());
  m.def("fit", &fit_document, nb::arg("formula"), nb::arg("columns"), nb::arg("names"),
        nb::arg("target").none(), nb::arg("target_name"), nb::arg("weights").none(),
        nb::arg("groups").none(), nb::arg("group_name"), nb::arg("parameters"),
        nb::arg("per_group"), nb::arg("loss"), nb::arg("solver"), nb::arg("constraints"),
        nb::arg("transform"), nb::arg("baselines"), nb::arg("max_iterations"), nb::arg("threads"),
        nb::arg("reference"), nb::arg("definitions"), nb::arg("domain"), nb::arg("samples"),
        nb::arg("reference_source"), nb::arg("reference_path"), nb::arg("function"));
  m.def("rational", &rational_document, nb::arg("target"), nb::arg("variable"), nb::arg("domain"),
        nb::arg("conditions"), nb::arg("forms"), nb::arg("transforms"), nb::arg("parameters"),
        nb::arg("count"), nb::arg("fit"), nb::arg("relative_minimax"), nb::arg("rank_by"),
        nb::arg("reference_source"), nb::arg("reference_path"), nb::arg("function"));
  m.def("dataset", &dataset, nb::arg("name"), nb::arg("seed"), nb::arg("rows"));
  m.def("dataset_names", &builtin_dataset_names);
  m.def("ldr_flip", &flip, nb::arg("reference"), nb::arg("test"), nb::arg("pixels_per_degree"));
}
