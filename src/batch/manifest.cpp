#include "shaderfit/batch/manifest.hpp"

#include <fmt/format.h>
// toml++ 3 as Debian ships it (libtomlplusplus-dev: the header is toml.h, the library compiled).
// Its templates stay in this file: no header of shaderfit names a toml++ type.
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <utility>

#include "core/hash.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/report/search_json.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {

namespace {

namespace fs = std::filesystem;

// The command line's names of two search options (apps/shaderfit/cli.cpp: --time, --evals),
// which a manifest takes besides the library names.
struct OptionAlias {
  std::string_view alias;
  std::string_view field;
};
constexpr OptionAlias kOptionAliases[] = {{"time", "time_limit_s"}, {"evals", "max_candidates"}};

// An entry's keys besides the search options, in the order messages list them.
constexpr std::string_view kEntryKeys[] = {
    "name",     "data",        "dataset", "data_seed", "reference",      "reference_file",
    "function", "domain",      "define",  "samples",   "drop_nonfinite", "drop_missing",
    "inputs",   "target",      "scene",   "term",      "weights",        "baseline",
    "start_from_baseline",     "goal",    "across_ranks"};

Error unknown_key(std::string_view key, const SourceLocation& at) {
  std::string known;
  for (std::string_view k : kEntryKeys) known += (known.empty() ? "" : ", ") + std::string(k);
  for (const OptionAlias& a : kOptionAliases) known += ", " + std::string(a.alias);
  return Error("unknown key '" + std::string(key) + "' (known: " + known +
                   "; and every search option by its name, docs/search.md)",
               at);
}

// The search option a key sets (its library name or an alias), or nullptr.
const SearchOptionField* option_of_key(std::string_view key) {
  for (const OptionAlias& a : kOptionAliases)
    if (key == a.alias) return find_search_option(a.field);
  return find_search_option(key);
}

std::string number_text(double v) { return fmt::format("{}", v); }

bool is_identifier(std::string_view s) {
  if (s.empty() || (std::isdigit(static_cast<unsigned char>(s[0])) != 0)) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
  });
}

// The whole file, or std::nullopt when it cannot be read.
std::optional<std::string> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return std::nullopt;
  return text.str();
}

// The manifest being read: its path (error locations) and folder (relative paths in it).
struct Reader {
  std::string path;
  fs::path folder;

  [[nodiscard]] SourceLocation at(const toml::source_region& r) const {
    return {path, static_cast<int>(r.begin.line), static_cast<int>(r.begin.column)};
  }
  [[nodiscard]] std::string resolve(const std::string& p) const {
    const fs::path given(p);
    return given.is_absolute() || folder.empty() ? p : (folder / given).string();
  }
};

struct Item {
  std::string_view key;
  const toml::key* name;
  const toml::node* value;
};

// A table's keys in the order the file writes them (toml++ keeps them sorted by name).
std::vector<Item> in_order(const toml::table& t) {
  std::vector<Item> items;
  for (auto&& [k, v] : t) items.push_back({k.str(), &k, &v});
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    const toml::source_position& p = a.name->source().begin;
    const toml::source_position& q = b.name->source().begin;
    return std::pair(p.line, p.column) < std::pair(q.line, q.column);
  });
  return items;
}

std::string type_name(const toml::node& v) {
  switch (v.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "true or false";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    default: return "a date or time";
  }
}

[[noreturn]] void bad_type(std::string_view key, const std::string& expected, const toml::node& v,
                           const Reader& r) {
  throw Error(std::string(key) + ": expected " + expected + ", got " + type_name(v),
              r.at(v.source()));
}

// A string, number or boolean as text (numbers shortest round-trip, as search_option_text).
std::optional<std::string> scalar_text(const toml::node& v) {
  if (const auto* s = v.as_string()) return s->get();
  if (const auto* i = v.as_integer()) return std::to_string(i->get());
  if (const auto* f = v.as_floating_point()) return number_text(f->get());
  if (const auto* b = v.as_boolean()) return std::string(b->get() ? "true" : "false");
  return std::nullopt;
}

std::string string_of(std::string_view key, const toml::node& v, const Reader& r) {
  if (const auto* s = v.as_string()) return s->get();
  bad_type(key, "a string", v, r);
}

// An array of strings, or one string (split at commas when `comma_list`), with each one's
// position.
std::vector<std::pair<std::string, SourceLocation>> strings_of(std::string_view key,
                                                               const toml::node& v, const Reader& r,
                                                               bool comma_list) {
  std::vector<std::pair<std::string, SourceLocation>> out;
  if (const auto* s = v.as_string()) {
    if (!comma_list) return {{s->get(), r.at(v.source())}};
    std::stringstream list(s->get());
    for (std::string item; std::getline(list, item, ',');) {
      const auto first = item.find_first_not_of(' ');
      if (first == std::string::npos) continue;
      out.emplace_back(item.substr(first, item.find_last_not_of(' ') - first + 1),
                       r.at(v.source()));
    }
    return out;
  }
  const auto* a = v.as_array();
  if (a == nullptr) bad_type(key, "an array of strings", v, r);
  for (const toml::node& e : *a) out.emplace_back(string_of(key, e, r), r.at(e.source()));
  return out;
}

// A search option's text (search_option_text's form) from a scalar or an array of scalars.
std::string option_text(std::string_view key, const SearchOptionField& field, const toml::node& v,
                        const Reader& r) {
  if (std::optional<std::string> t = scalar_text(v)) return *t;
  const auto* a = v.as_array();
  if (a == nullptr) bad_type(key, "a value or an array", v, r);
  const std::string separator = search_option_kind(field) == OptionKind::Formulas ? "; " : ",";
  std::string text;
  for (const toml::node& e : *a) {
    std::optional<std::string> t = scalar_text(e);
    if (!t) bad_type(key, "an array of values", e, r);
    text += (text.empty() ? "" : separator) + *t;
  }
  return text;
}

double goal_limit(std::string_view text, std::string_view what, const SourceLocation& at) {
  const std::string s(text);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || errno != 0 || !std::isfinite(v) || v < 0)
    throw Error("goal: the " + std::string(what) + " must be a number >= 0, not '" + s + "'", at);
  return v;
}

BatchGoal goal_of(const toml::node& v, const Reader& r) {
  const std::string expected =
      "\"knee\", \"beat-baseline\", { cost = N }, { error = E }, \"cost=N\" or \"error=E\"";
  const SourceLocation at = r.at(v.source());
  BatchGoal g;
  if (const auto* t = v.as_table()) {
    if (t->size() != 1) throw Error("goal: expected " + expected, at);
    const Item item = in_order(*t).front();
    const std::string_view key = item.key;
    const toml::node& value = *item.value;
    if (key != "cost" && key != "error")
      throw Error("goal: unknown key '" + std::string(key) + "' (known: cost, error)",
                  r.at(item.name->source()));
    if (!value.is_number()) bad_type("goal", "a number", value, r);
    g.kind = key == "cost" ? BatchGoal::Kind::MaxCost : BatchGoal::Kind::MaxError;
    g.limit = goal_limit(*scalar_text(value), key, r.at(value.source()));
    return g;
  }
  const auto* s = v.as_string();
  if (s == nullptr) bad_type("goal", expected, v, r);
  std::string text = s->get();
  std::erase(text, ' ');
  if (text == "knee") return g;
  if (text == "beat-baseline") {
    g.kind = BatchGoal::Kind::BeatBaseline;
    return g;
  }
  for (const auto& [prefix, kind] : {std::pair{"cost=", BatchGoal::Kind::MaxCost},
                                     std::pair{"error=", BatchGoal::Kind::MaxError}}) {
    if (text.starts_with(prefix)) {
      g.kind = kind;
      g.limit = goal_limit(std::string_view(text).substr(std::strlen(prefix)),
                           kind == BatchGoal::Kind::MaxCost ? "cost" : "error", at);
      return g;
    }
  }
  throw Error("goal: expected " + expected + ", got '" + s->get() + "'", at);
}

// Where a key that was set is: its value's position, and the key as written (an alias, say).
struct Where {
  SourceLocation at;
  std::string key;
};

// What an entry says, [defaults] first: the values and where each was given.
struct Settings {
  ProblemSource problem;
  std::string data, reference_file;  // the paths as written
  std::string scene, term;           // the scene's kind and term by name ("" : none)
  SearchOptions options;
  std::string baseline, weights;
  bool start_from_baseline = true;
  bool across_ranks = false;
  BatchGoal goal;
  std::map<std::string, Where, std::less<>> where;   // by key (a search option: its field's name)
  std::vector<SourceLocation> domain_at, define_at;  // each variable's, each definition's

  [[nodiscard]] const Where* find(std::string_view key) const {
    const auto it = where.find(key);
    return it == where.end() ? nullptr : &it->second;
  }
};

// Sets one key's value; throws Error (the message starts with the key) at the value.
void apply_key(Settings& s, std::string_view key, const toml::node& v, const Reader& r) {
  ProblemSource& p = s.problem;
  if (const SearchOptionField* f = option_of_key(key)) {
    try {
      set_search_option(s.options, *f, option_text(key, *f, v, r));
    } catch (const Error& e) {
      if (e.where().source != search_option_location(*f)) throw;
      throw Error(std::string(key) + ": " + e.message(), r.at(v.source()));
    }
  } else if (key == "data") {
    s.data = string_of(key, v, r);
    p.csv_path = s.data.empty() ? "" : r.resolve(s.data);
  } else if (key == "dataset") {
    p.dataset = string_of(key, v, r);
  } else if (key == "data_seed") {
    const auto* i = v.as_integer();
    if (i == nullptr || i->get() < 0) bad_type(key, "an integer >= 0", v, r);
    p.dataset_seed = static_cast<std::uint64_t>(i->get());
  } else if (key == "reference") {
    p.reference.formula = string_of(key, v, r);
  } else if (key == "reference_file") {
    s.reference_file = string_of(key, v, r);
  } else if (key == "function") {
    p.reference.function = string_of(key, v, r);
  } else if (key == "domain") {
    const auto* t = v.as_table();
    if (t == nullptr) bad_type(key, "a table such as { x = [0, 1] }", v, r);
    p.domain.clear();
    s.domain_at.clear();
    for (const Item& item : in_order(*t)) {
      std::string bounds;
      if (const auto* text = item.value->as_string()) {
        bounds = text->get();
      } else if (const auto* a = item.value->as_array(); a != nullptr && !a->empty()) {
        for (const toml::node& e : *a) {
          std::optional<std::string> b = scalar_text(e);
          if (!b || e.is_boolean()) bad_type(key, "numbers: [lo, hi] or [lo, hi, count]", e, r);
          bounds += (bounds.empty() ? "" : ":") + *b;
        }
      } else {
        bad_type(std::string(key) + "." + std::string(item.key),
                 "[lo, hi], [lo, hi, count] or \"lo:hi\"", *item.value, r);
      }
      p.domain.push_back(std::string(item.key) + "=" + bounds);
      s.domain_at.push_back(r.at(item.value->source()));
    }
  } else if (key == "define") {
    p.reference.definitions.clear();
    s.define_at.clear();
    for (auto& [text, at] : strings_of(key, v, r, false)) {
      p.reference.definitions.push_back(std::move(text));
      s.define_at.push_back(std::move(at));
    }
  } else if (key == "samples") {
    const auto* i = v.as_integer();
    if (i == nullptr || i->get() <= 0) bad_type(key, "an integer > 0", v, r);
    p.samples = static_cast<std::size_t>(i->get());
  } else if (key == "drop_nonfinite") {
    const auto* b = v.as_boolean();
    if (b == nullptr) bad_type(key, "true or false", v, r);
    p.drop_nonfinite = b->get();
  } else if (key == "drop_missing") {
    const auto* b = v.as_boolean();
    if (b == nullptr) bad_type(key, "true or false", v, r);
    p.drop_missing_rows = b->get();
  } else if (key == "inputs") {
    p.inputs.clear();
    for (auto& item : strings_of(key, v, r, true)) p.inputs.push_back(std::move(item.first));
  } else if (key == "target") {
    p.target = string_of(key, v, r);
  } else if (key == "scene" || key == "term") {
    (key == "scene" ? s.scene : s.term) = string_of(key, v, r);
  } else if (key == "weights") {
    s.weights = string_of(key, v, r);
  } else if (key == "baseline") {
    s.baseline = string_of(key, v, r);
  } else if (key == "start_from_baseline" || key == "across_ranks") {
    const auto* b = v.as_boolean();
    if (b == nullptr) bad_type(key, "true or false", v, r);
    (key == "across_ranks" ? s.across_ranks : s.start_from_baseline) = b->get();
  } else if (key == "goal") {
    s.goal = goal_of(v, r);
  } else {
    throw unknown_key(key, r.at(v.source()));
  }
}

// Applies a table's keys ([defaults] or an entry's but its name) in the file's order. Throws
// Error for an unknown key, one that is not for [defaults], two keys for one option (an alias and
// its name), and as apply_key.
void apply_table(Settings& s, const toml::table& t, const Reader& r, bool entry) {
  std::map<std::string, std::string_view, std::less<>> set_here;  // field -> key as written
  for (const Item& item : in_order(t)) {
    const SearchOptionField* f = option_of_key(item.key);
    if (!entry && (item.key == "name" || item.key == "baseline"))
      throw Error("'" + std::string(item.key) + "' is for an entry ([[function]]), not [defaults]",
                  r.at(item.name->source()));
    if (entry && item.key == "name") continue;
    const std::string canonical = f != nullptr ? std::string(f->name) : std::string(item.key);
    if (const auto it = set_here.find(canonical); it != set_here.end())
      throw Error(std::string(item.key) + ": '" + std::string(it->second) + "' sets " + canonical +
                      " already",
                  r.at(item.name->source()));
    if (f == nullptr &&
        std::find(std::begin(kEntryKeys), std::end(kEntryKeys), item.key) == std::end(kEntryKeys))
      throw unknown_key(item.key, r.at(item.name->source()));
    set_here.emplace(canonical, item.key);
    apply_key(s, item.key, *item.value, r);
    s.where[canonical] = Where{r.at(item.value->source()), std::string(item.key)};
  }
}

// The same Error at the manifest key that caused it: library errors are located at the field
// (ProblemSource::domain, SearchOptions::max_nodes), a formula's source, or a file the entry
// names; `fallback` is the entry's header.
Error in_manifest(const Error& e, const Settings& s, const SourceLocation& fallback) {
  const std::string& source = e.where().source;
  auto at_key = [&](std::string_view key, const std::string& message) {
    const Where* w = s.find(key);
    return Error(message, w != nullptr ? w->at : fallback);
  };
  constexpr std::string_view kOptions = "SearchOptions::";
  if (source.starts_with(kOptions)) {
    const std::string field = source.substr(kOptions.size());
    const Where* w = s.find(field);
    return Error((w != nullptr ? w->key : field) + ": " + e.message(),
                 w != nullptr ? w->at : fallback);
  }
  // Fields of ProblemSource and the manifest keys that set them.
  static const std::pair<std::string_view, std::string_view> kFields[] = {
      {"ProblemSource::csv_path", "data"},   {"ProblemSource::dataset", "dataset"},
      {"ProblemSource::samples", "samples"}, {"ProblemSource::inputs", "inputs"},
      {"ProblemSource::target", "target"},   {"ProblemSource::scene", "scene"},
      {"SceneSpec::kind", "scene"},          {"SceneSpec::term", "term"},
      {"ManifestEntry::weights", "weights"},
      {"ProblemSource::drop_missing_rows", "drop_missing"}};
  for (const auto& [field, key] : kFields)
    if (source == field) return at_key(key, e.message());
  if (source == "ProblemSource::domain") {
    const int i = e.where().line - 1;
    if (i >= 0 && static_cast<std::size_t>(i) < s.domain_at.size())
      return Error(e.message(), s.domain_at[static_cast<std::size_t>(i)]);
    return at_key("domain", e.message());
  }
  if (source == "ProblemSource::reference")
    return at_key(s.find("reference") != nullptr ? "reference" : "reference_file", e.message());
  // The formula languages' own positions ("reference:1:5", "define:2:7") stay in the message.
  if (source == s.problem.reference.formula_source) return at_key("reference", e.what());
  if (source == s.problem.reference.definitions_source) {
    const int i = e.where().line - 1;
    if (i >= 0 && static_cast<std::size_t>(i) < s.define_at.size())
      return Error(e.what(), s.define_at[static_cast<std::size_t>(i)]);
    return at_key("define", e.what());
  }
  // A file the entry names: its line and column where known (the message names the file, and
  // the CSV reader's option by its key).
  std::string in_file = e.where().line > 0 ? e.what() : e.message();
  constexpr std::string_view kDropOption = "CsvOptions::drop_missing_rows";
  if (const std::size_t at = in_file.find(kDropOption); at != std::string::npos)
    in_file.replace(at, kDropOption.size(), "drop_missing = true");
  if (!s.problem.csv_path.empty() && source == s.problem.csv_path) return at_key("data", in_file);
  if (!s.problem.reference.shader_path.empty() && source == s.problem.reference.shader_path)
    return at_key("reference_file", in_file);
  return Error(e.what(), fallback);
}

// The problem, and the weights column checked: a column of numbers that is not the target; a
// data file's inferred inputs leave it out.
Problem load_entry_problem(const Settings& s) {
  const ProblemSource& src = s.problem;
  Problem p = load_problem(src);
  if (s.weights.empty()) return p;
  const Where& w = *s.find("weights");
  const Column* c = p.data.find(s.weights);
  if (c == nullptr || !c->numeric()) {
    std::string names;
    for (const Column& col : p.data.columns)
      if (col.numeric()) names += (names.empty() ? "" : ", ") + col.name;
    throw Error("weights: " + std::string(c == nullptr ? "no column '" : "the text column '") +
                    s.weights + "' in " + p.description + " (numeric columns: " + names + ")",
                w.at);
  }
  if (p.target == s.weights)
    throw Error("weights: column '" + s.weights + "' is the target" +
                    (src.target.empty() ? " chosen for the data (name the target)" : ""),
                w.at);
  const auto input = std::find(p.inputs.begin(), p.inputs.end(), s.weights);
  if (input == p.inputs.end()) return p;
  if (!src.inputs.empty() || p.reference)
    throw Error("weights: column '" + s.weights + "' is an input", w.at);
  ProblemSource again = src;
  again.inputs = p.inputs;
  again.inputs.erase(again.inputs.begin() + (input - p.inputs.begin()));
  again.target = p.target;
  if (again.inputs.empty())
    throw Error("weights: column '" + s.weights + "' is the only input", w.at);
  Problem q = load_problem(again);
  q.notes.push_back("column " + s.weights + " weighs the rows; not an input");
  return q;
}

std::string entry_hash(const ManifestEntry& e, const Settings& s) {
  using core_detail::fnv1a64;
  ProblemSource as_written = e.problem;
  as_written.csv_path = s.data;
  as_written.reference.shader_path = s.reference_file;
  std::uint64_t h = fnv1a64("shaderfit batch entry");
  auto add = [&h](std::string_view part) {
    h = fnv1a64(std::to_string(part.size()) + ':', h);
    h = fnv1a64(part, h);
  };
  add(problem_source_json(as_written).dump());
  add(e.problem.csv_path.empty() ? "" : read_bytes(e.problem.csv_path).value_or(""));
  add(search_options_json(e.options).dump());
  add(e.baseline);
  add(e.start_from_baseline ? "start" : "no start");
  add(batch_goal_text(e.goal));
  add(e.weights);
  return fmt::format("{:016x}", h);
}

// One [[function]] table; throws Error (the message without the entry's name) in the manifest.
ManifestEntry read_entry(const toml::table& t, const Settings& defaults, const Reader& r,
                         ManifestEntry e) {
  Settings s = defaults;
  apply_table(s, t, r, true);
  s.problem.reference.formula_source = "reference";
  s.problem.reference.definitions_source = "define";
  const SourceLocation header{r.path, e.line, 0};
  if (s.goal.kind == BatchGoal::Kind::BeatBaseline && s.baseline.empty()) {
    const Where* w = s.find("goal");
    throw Error("goal beat-baseline needs a baseline (baseline = \"formula\")",
                w != nullptr ? w->at : header);
  }
  try {
    s.options.validate();
    if (!s.reference_file.empty()) {
      s.problem.reference.shader_path = r.resolve(s.reference_file);
      s.problem.reference.shader_source =
          reference::read_shader_file(s.problem.reference.shader_path);
    }
    if (!s.scene.empty())
      s.problem.scene = scene_spec_from_names(s.scene, s.term);
    else if (!s.term.empty())
      throw Error("a term is for a scene: give scene = \"sphere\" or \"plane\"",
                  SourceLocation{"SceneSpec::term"});
    Problem p = load_entry_problem(s);
    // The display loss's rows: its weights are the scene's (an error without one, or with weights).
    if (s.options.loss == Loss::Display)
      (void)search_problem(p, s.options.loss, s.weights, {"ManifestEntry::weights"});
    if (p.scene) s.problem.scene = p.scene->spec;  // as rendered: the term filled in
    if (!s.baseline.empty()) {
      ParseOptions po;
      po.variables = p.inputs;
      po.source = "baseline";
      (void)parse_formula(s.baseline, po);
    }
    s.problem.inputs = p.inputs;
    s.problem.target = p.target;
    e.loaded = std::make_shared<const Problem>(std::move(p));
  } catch (const Error& err) {
    if (err.where().source == "baseline") {
      const Where* w = s.find("baseline");
      throw Error(err.what(), w != nullptr ? w->at : header);
    }
    if (err.where().source == r.path) throw;
    throw in_manifest(err, s, header);
  }
  e.problem = std::move(s.problem);
  e.options = std::move(s.options);
  e.baseline = std::move(s.baseline);
  e.start_from_baseline = s.start_from_baseline;
  e.across_ranks = s.across_ranks;
  e.goal = s.goal;
  e.weights = std::move(s.weights);
  e.hash = entry_hash(e, s);
  return e;
}

}  // namespace

std::string batch_goal_text(const BatchGoal& goal) {
  switch (goal.kind) {
    case BatchGoal::Kind::Knee: return "knee";
    case BatchGoal::Kind::MaxCost: return "cost=" + number_text(goal.limit);
    case BatchGoal::Kind::MaxError: return "error=" + number_text(goal.limit);
    case BatchGoal::Kind::BeatBaseline: return "beat-baseline";
  }
  return "knee";
}

Manifest read_manifest(const std::string& path, bool strict) {
  const std::optional<std::string> text = read_bytes(path);
  if (!text) throw Error("cannot read the manifest", {path});
  toml::table doc;
  try {
    doc = toml::parse(std::string_view(*text), std::string_view(path));
  } catch (const toml::parse_error& e) {
    const toml::source_position& at = e.source().begin;
    throw Error(std::string(e.description()),
                {path, static_cast<int>(at.line), static_cast<int>(at.column)});
  }
  const Reader r{path, fs::path(path).parent_path()};

  Settings defaults;
  defaults.options.threads = 1;  // a batch shares the cores among its entries
  const toml::array* functions = nullptr;
  for (const Item& item : in_order(doc)) {
    if (item.key == "defaults") {
      const toml::table* t = item.value->as_table();
      if (t == nullptr) bad_type("defaults", "a table ([defaults])", *item.value, r);
      try {
        try {
          apply_table(defaults, *t, r, false);
          defaults.options.validate();
        } catch (const Error& e) {
          if (e.where().source == r.path) throw;
          throw in_manifest(e, defaults, r.at(item.value->source()));
        }
      } catch (const Error& e) {
        throw Error("defaults: " + e.message(), e.where());
      }
    } else if (item.key == "function") {
      functions = item.value->as_array();
      if (functions == nullptr || !functions->is_array_of_tables())
        bad_type("function", "[[function]] tables", *item.value, r);
    } else {
      throw Error("unknown key '" + std::string(item.key) + "' (known: defaults, function)",
                  r.at(item.name->source()));
    }
  }
  if (functions == nullptr || functions->empty())
    throw Error("no [[function]] entry: nothing to approximate", {path});

  Manifest m;
  m.path = path;
  std::map<std::string, int, std::less<>> first_line;  // each name's first entry
  int index = 0;
  for (const toml::node& node : *functions) {
    const toml::table& t = *node.as_table();
    const int line = static_cast<int>(t.source().begin.line);
    const toml::node* name_node = t.get("name");
    std::string name;
    if (name_node != nullptr && name_node->is_string()) name = name_node->as_string()->get();
    const std::string label = "function " + std::to_string(++index);
    try {
      if (name_node == nullptr)
        throw Error("no name (name = \"...\", a C identifier)", {path, line, 0});
      if (!name_node->is_string()) bad_type("name", "a string", *name_node, r);
      if (!is_identifier(name))
        throw Error("name: not a C identifier (letters, digits and _, not first a digit)",
                    r.at(name_node->source()));
      if (const auto it = first_line.find(name); it != first_line.end())
        throw Error("name: the entry at line " + std::to_string(it->second) + " has it too",
                    r.at(name_node->source()));
      first_line.emplace(name, line);
      ManifestEntry e;
      e.name = name;
      e.line = line;
      m.entries.push_back(read_entry(t, defaults, r, std::move(e)));
    } catch (const Error& err) {
      const Error located((name.empty() ? label : "entry '" + name + "'") + ": " + err.message(),
                          err.where());
      if (strict) throw located;
      m.bad.push_back({name.empty() ? label : name, line, located.what()});
    }
  }
  return m;
}

}  // namespace shaderfit
