#include "search/checkpoint.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <locale>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <utility>

// The build defines it for this file from the CMake project version (CMakeLists.txt).
#ifndef SHADERFIT_VERSION
#define SHADERFIT_VERSION "unknown"
#endif

namespace shaderfit::search_detail {

namespace {

using nlohmann::json;

constexpr std::string_view kMagic = "shaderfit checkpoint";

// A body that does not hold what the format says; reported as a damaged file.
struct BadBody : std::runtime_error {
  using std::runtime_error::runtime_error;
};

json num(double v) {
  if (std::isfinite(v)) return v;  // nlohmann writes the shortest text that reads back exactly
  return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
}

double get_num(const json& j) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    const auto& s = j.get_ref<const std::string&>();
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
  }
  throw BadBody("a number was expected");
}

// An integer that fits T exactly. nlohmann's get<T> converts a fraction or an out-of-range value
// without a word (and a float beyond T's range is undefined behaviour), so a field that must be a
// count or an index is checked here.
template <class T>
T get_integer(const json& j, std::string_view field) {
  if (j.is_number_unsigned()) {
    const auto v = j.get<std::uint64_t>();
    if (std::in_range<T>(v)) return static_cast<T>(v);
  } else if (j.is_number_integer()) {
    const auto v = j.get<std::int64_t>();
    if (std::in_range<T>(v)) return static_cast<T>(v);
  }
  throw BadBody("an integer in range was expected for '" + std::string(field) + "'");
}

json expression_json(const Expression& e) {
  json nodes = json::array();
  for (const Node& n : e.nodes) nodes.push_back({static_cast<int>(n.op), n.index, num(n.value)});
  json values = json::array();
  for (double v : e.parameter_values) values.push_back(num(v));
  return {{"variables", e.variables},
          {"parameters", e.parameters},
          {"values", values},
          {"nodes", nodes}};
}

Expression expression_from(const json& j) {
  Expression e;
  e.variables = j.at("variables").get<std::vector<std::string>>();
  e.parameters = j.at("parameters").get<std::vector<std::string>>();
  for (const json& v : j.at("values")) e.parameter_values.push_back(get_num(v));
  if (e.parameter_values.size() != e.parameters.size())
    throw BadBody("a formula has parameters without values");
  for (const json& n : j.at("nodes")) {
    const int op = get_integer<int>(n.at(0), "a node's operator");
    const int index = get_integer<std::int16_t>(n.at(1), "a node's index");
    if (op < 0 || op >= kOpCount) throw BadBody("an unknown operator");
    Node node = Node::op_node(static_cast<Op>(op));
    node.index = static_cast<std::int16_t>(index);
    node.value = get_num(n.at(2));
    const auto bound =
        static_cast<int>(node.op == Op::Var ? e.variables.size() : e.parameters.size());
    if ((node.op == Op::Var || node.op == Op::Param) && (index < 0 || index >= bound))
      throw BadBody("a variable or parameter out of range");
    e.nodes.push_back(node);
  }
  if (e.nodes.empty()) throw BadBody("an empty formula");
  e.update_lengths();  // throws on a malformed tree
  return e;
}

json member_json(const FrontMember& m) {
  return {{"expression", expression_json(m.expression)},
          {"formula", m.formula},
          {"cost", num(m.cost)},
          {"nodes", m.nodes},
          {"loss", num(m.loss)},
          {"mse", num(m.metrics.mse)},
          {"rmse", num(m.metrics.rmse)},
          {"max_abs", num(m.metrics.max_abs)},
          {"rel", num(m.metrics.rel)},
          {"log", num(m.metrics.log)},
          {"time_s", num(m.time_s)},
          {"origin", m.origin}};
}

FrontMember member_from(const json& j) {
  FrontMember m;
  m.expression = expression_from(j.at("expression"));
  m.formula = j.at("formula").get<std::string>();
  m.cost = get_num(j.at("cost"));
  m.nodes = get_integer<std::size_t>(j.at("nodes"), "nodes");
  m.loss = get_num(j.at("loss"));
  m.metrics.mse = get_num(j.at("mse"));
  m.metrics.rmse = get_num(j.at("rmse"));
  m.metrics.max_abs = get_num(j.at("max_abs"));
  m.metrics.rel = get_num(j.at("rel"));
  m.metrics.log = get_num(j.at("log"));
  m.time_s = get_num(j.at("time_s"));
  m.origin = j.at("origin").get<std::string>();
  return m;
}

json individual_json(const SavedIndividual& s) {
  return {{"expression", expression_json(s.expr)},
          {"loss", num(s.loss)},
          {"cost", num(s.cost)},
          {"raw_loss", num(s.raw_loss)},
          {"raw_cost", num(s.raw_cost)},
          {"hash", s.hash},
          {"scaled", s.scaled},
          {"a", num(s.a)},
          {"b", num(s.b)}};
}

SavedIndividual individual_from(const json& j) {
  SavedIndividual s;
  s.expr = expression_from(j.at("expression"));
  s.loss = get_num(j.at("loss"));
  s.cost = get_num(j.at("cost"));
  s.raw_loss = get_num(j.at("raw_loss"));
  s.raw_cost = get_num(j.at("raw_cost"));
  s.hash = get_integer<std::uint64_t>(j.at("hash"), "hash");
  s.scaled = j.at("scaled").get<bool>();
  s.a = get_num(j.at("a"));
  s.b = get_num(j.at("b"));
  return s;
}

void check_rng_text(const std::string& text) {
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  Rng rng;
  if (!(in >> rng)) throw BadBody("a random generator state does not read back");
}

json body_json(const Checkpoint& c) {
  json options = json::array();
  for (const auto& [k, v] : c.options) options.push_back({k, v});
  json front = json::array();
  for (const FrontMember& m : c.front) front.push_back(member_json(m));
  json islands = json::array();
  for (const SavedIsland& is : c.evolution.islands) {
    json pop = json::array();
    for (const SavedIndividual& s : is.population) pop.push_back(individual_json(s));
    islands.push_back({{"rng", is.rng}, {"population", pop}});
  }
  return {{"phase", c.phase},
          {"data", {{"hash", c.data_hash}, {"rows", c.rows}, {"inputs", c.input_names}}},
          {"options", options},
          {"clock",
           {{"elapsed_s", num(c.elapsed_s)},
            {"candidates", c.candidates},
            {"node_evaluations", c.node_evaluations}}},
          {"front", front},
          {"enumeration",
           {{"time_s", num(c.enumeration_time_s)},
            {"distinct_candidates", c.distinct_candidates},
            {"cost_completed", c.enumeration_cost_completed}}},
          {"rng", c.rng},
          {"evolution",
           {{"generations", c.evolution.generations},
            {"polished", c.evolution.polished},
            {"islands", islands}}}};
}

Checkpoint checkpoint_from(const json& j) {
  Checkpoint c;
  c.phase = j.at("phase").get<std::string>();
  if (c.phase != "enumeration" && c.phase != "evolution") throw BadBody("an unknown phase");
  const json& d = j.at("data");
  c.data_hash = get_integer<std::uint64_t>(d.at("hash"), "hash");
  c.rows = get_integer<std::size_t>(d.at("rows"), "rows");
  c.input_names = d.at("inputs").get<std::vector<std::string>>();
  for (const json& kv : j.at("options"))
    c.options.emplace_back(kv.at(0).get<std::string>(), kv.at(1).get<std::string>());
  const json& clock = j.at("clock");
  c.elapsed_s = get_num(clock.at("elapsed_s"));
  c.candidates = get_integer<std::uint64_t>(clock.at("candidates"), "candidates");
  c.node_evaluations = get_integer<std::uint64_t>(clock.at("node_evaluations"), "node_evaluations");
  // The resumed search evaluates every formula on the data's columns by variable index.
  auto over_inputs = [&](const Expression& e) {
    if (e.variables != c.input_names) throw BadBody("a formula over other inputs than the data's");
  };
  for (const json& m : j.at("front")) {
    c.front.push_back(member_from(m));
    over_inputs(c.front.back().expression);
  }
  const json& en = j.at("enumeration");
  c.enumeration_time_s = get_num(en.at("time_s"));
  c.distinct_candidates =
      get_integer<std::uint64_t>(en.at("distinct_candidates"), "distinct_candidates");
  c.enumeration_cost_completed = get_integer<int>(en.at("cost_completed"), "cost_completed");
  c.rng = j.at("rng").get<std::string>();
  const json& ev = j.at("evolution");
  c.evolution.generations = get_integer<std::uint64_t>(ev.at("generations"), "generations");
  c.evolution.polished = ev.at("polished").get<bool>();
  for (const json& is : ev.at("islands")) {
    SavedIsland island;
    island.rng = is.at("rng").get<std::string>();
    check_rng_text(island.rng);
    for (const json& s : is.at("population")) {
      island.population.push_back(individual_from(s));
      over_inputs(island.population.back().expr);
    }
    c.evolution.islands.push_back(std::move(island));
  }
  if (c.phase == "evolution") {
    check_rng_text(c.rng);
    if (c.evolution.islands.empty()) throw BadBody("an evolution without islands");
  }
  return c;
}

std::string header_lines(std::string_view version) {
  return fmt::format("{}\nformat {}\nshaderfit {}\n", kMagic, kCheckpointFormat, version);
}

// Splits off the first line of `rest` (without its newline); false when there is no newline.
bool take_line(std::string_view& rest, std::string_view* line) {
  const std::size_t nl = rest.find('\n');
  if (nl == std::string_view::npos) return false;
  *line = rest.substr(0, nl);
  rest.remove_prefix(nl + 1);
  return true;
}

std::string option_text(double v) { return fmt::format("{}", v); }

}  // namespace

std::string_view checkpoint_writer_version() { return SHADERFIT_VERSION; }

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h) {
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::uint64_t problem_hash(const SearchProblem& p) {
  auto column = [](std::uint64_t h, const std::vector<double>& v) {
    h = fnv1a64(std::to_string(v.size()), h);
    return fnv1a64({reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double)}, h);
  };
  std::uint64_t h = fnv1a64("shaderfit data");
  for (const std::string& n : p.input_names) h = fnv1a64(n + '\n', h);
  for (const auto& c : p.inputs) h = column(h, c);
  h = column(h, p.target);
  return column(h, p.weights);
}

std::vector<std::pair<std::string, std::string>> checkpoint_options(const SearchOptions& o) {
  std::string literals;
  for (double v : o.literals) literals += (literals.empty() ? "" : ",") + option_text(v);
  return {{"seed", std::to_string(o.seed)},
          {"loss", std::string(loss_name(o.loss))},
          {"cost", std::string(cost_target_name(o.cost))},
          {"operators", operator_list_name(o.operators)},
          {"evolution_operators", operator_list_name(o.evolution_operators)},
          {"max_power", std::to_string(o.max_power)},
          {"literals", literals},
          {"enumerate", o.enumerate ? "true" : "false"},
          {"screen_rows", std::to_string(o.screen_rows)},
          {"max_classes", std::to_string(o.max_classes)},
          {"max_enumeration_share", option_text(o.max_enumeration_share)},
          {"max_enumeration_cost", std::to_string(o.max_enumeration_cost)},
          {"evolve", o.evolve ? "true" : "false"},
          {"max_nodes", std::to_string(o.max_nodes)},
          {"population", std::to_string(o.population)},
          {"islands", std::to_string(o.islands)},
          {"migration_interval", std::to_string(o.migration_interval)},
          {"max_parameters", std::to_string(o.max_parameters)},
          {"fit_rows", std::to_string(o.fit_rows)},
          {"linear_scaling", o.linear_scaling ? "true" : "false"}};
}

std::string checkpoint_text(const Checkpoint& c) {
  const std::string head = header_lines(c.shaderfit_version);
  const std::string body = body_json(c).dump() + "\n";
  return head + fmt::format("fnv1a64 {:016x}\n", fnv1a64(body, fnv1a64(head))) + body;
}

Checkpoint parse_checkpoint(std::string_view text, const std::string& path) {
  const SourceLocation where{path};
  std::string_view rest = text;
  std::string_view magic, format, version, sum;
  if (!take_line(rest, &magic) || magic != kMagic)
    throw Error("not a shaderfit checkpoint (its first line is not '" + std::string(kMagic) + "')",
                where);
  if (!take_line(rest, &format) || !format.starts_with("format "))
    throw Error("damaged checkpoint: the format line is missing", where);
  if (format != fmt::format("format {}", kCheckpointFormat))
    throw Error("checkpoint " + std::string(format) + " cannot be read: this shaderfit (" +
                    SHADERFIT_VERSION + ") reads format " + std::to_string(kCheckpointFormat),
                where);
  if (!take_line(rest, &version) || !version.starts_with("shaderfit ") || !take_line(rest, &sum) ||
      !sum.starts_with("fnv1a64 "))
    throw Error("damaged checkpoint: its header is cut short", where);
  const std::size_t head_size = magic.size() + format.size() + version.size() + 3;
  const std::string expected =
      fmt::format("fnv1a64 {:016x}", fnv1a64(rest, fnv1a64(text.substr(0, head_size))));
  if (sum != expected)
    throw Error(
        "damaged checkpoint: its checksum does not match (the file was cut short or "
        "changed after it was written)",
        where);
  const std::string_view written_by = version.substr(10);
  if (written_by != SHADERFIT_VERSION)
    throw Error("checkpoint written by shaderfit " + std::string(written_by) +
                    "; this is shaderfit " + SHADERFIT_VERSION +
                    " (resume it with the version that wrote it)",
                where);
  try {
    Checkpoint c = checkpoint_from(json::parse(rest));
    c.shaderfit_version = std::string(written_by);
    return c;
  } catch (const std::exception& e) {
    // The checksum matched, so the writer itself was wrong: still a file we cannot use.
    throw Error(std::string("damaged checkpoint: ") + e.what(), where);
  }
}

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  const std::string text = checkpoint_text(c);
  const std::string tmp = path + ".tmp";
  const SourceLocation where{"--checkpoint"};
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr)
    throw Error("cannot write the checkpoint '" + tmp + "': " + std::strerror(errno), where);
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size() &&
                  std::fflush(f) == 0 && ::fsync(fileno(f)) == 0;
  const int err = errno;
  if (std::fclose(f) != 0 || !ok) {
    std::remove(tmp.c_str());
    throw Error("cannot write the checkpoint '" + tmp + "': " + std::strerror(err), where);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);  // atomic on POSIX file systems
  if (ec) throw Error("cannot rename '" + tmp + "' to '" + path + "': " + ec.message(), where);
}

Checkpoint read_checkpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open the checkpoint '" + path + "'", {"--resume"});
  std::ostringstream text;
  text << in.rdbuf();
  return parse_checkpoint(text.str(), path);
}

void check_checkpoint_matches(const Checkpoint& c, const SearchOptions& options,
                              const SearchProblem& problem, const std::string& path) {
  const SourceLocation where{path};
  auto names = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& n : v) s += (s.empty() ? "" : ",") + n;
    return s;
  };
  if (c.input_names != problem.input_names || c.rows != problem.target.size() ||
      c.data_hash != problem_hash(problem))
    throw Error(
        fmt::format("the checkpoint was made on other data ({} rows, inputs {}; this "
                    "search: {} rows, inputs {}{}); resume with the same data",
                    c.rows, names(c.input_names), problem.target.size(), names(problem.input_names),
                    c.input_names == problem.input_names && c.rows == problem.target.size()
                        ? ", other values"
                        : ""),
        where);
  for (const auto& option : checkpoint_options(options)) {
    auto it = std::find_if(c.options.begin(), c.options.end(),
                           [&](const auto& kv) { return kv.first == option.first; });
    const std::string then = it == c.options.end() ? "(not recorded)" : it->second;
    if (then != option.second)
      throw Error(fmt::format("the checkpoint was made with {0} = {1}; this search has {0} = {2} "
                              "(resume with the same options)",
                              option.first, then, option.second),
                  where);
  }
}

Checkpointer::Checkpointer(SearchContext& ctx) : ctx_(ctx) {
  const SearchOptions& o = ctx.options;
  base_.shaderfit_version = SHADERFIT_VERSION;
  base_.data_hash = problem_hash(ctx.problem);
  base_.rows = ctx.rows;
  base_.input_names = ctx.problem.input_names;
  base_.options = checkpoint_options(o);
  // Fail now, not after an hour of searching, when the file cannot be written.
  const std::string tmp = o.checkpoint_path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr)
    throw Error("cannot write the checkpoint '" + tmp + "': " + std::strerror(errno),
                {"--checkpoint"});
  std::fclose(f);
  std::remove(tmp.c_str());
  last_write_s_ = ctx.elapsed();
}

void Checkpointer::begin_evolution(double enumeration_time_s, std::uint64_t distinct_candidates,
                                   int enumeration_cost_completed, const Rng& rng) {
  base_.enumeration_time_s = enumeration_time_s;
  base_.distinct_candidates = distinct_candidates;
  base_.enumeration_cost_completed = enumeration_cost_completed;
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out << rng;
  base_.rng = out.str();
}

Checkpoint Checkpointer::capture(std::string phase) {
  Checkpoint c = base_;
  c.phase = std::move(phase);
  c.elapsed_s = ctx_.elapsed();
  c.candidates = ctx_.candidates.load();
  c.node_evaluations = ctx_.node_evaluations.load();
  c.front = ctx_.front.members();
  return c;
}

bool Checkpointer::due() const {
  return ctx_.elapsed() - last_write_s_ >= ctx_.options.checkpoint_interval_s;
}

void Checkpointer::write(const Checkpoint& c) {
  if (!deferred_error_.empty()) throw Error(deferred_error_, {"--checkpoint"});
  write_checkpoint(ctx_.options.checkpoint_path, c);
  last_write_s_ = ctx_.elapsed();
}

void Checkpointer::at_boundary(const EvolutionState& state) {
  std::lock_guard lock(write_mutex_);
  at_boundary_ = capture("evolution");
  at_boundary_.evolution = state;
  have_boundary_ = true;
  if (due()) write(at_boundary_);
}

void Checkpointer::at_end(bool generation_cut, const EvolutionState& current) {
  std::lock_guard lock(write_mutex_);
  if (generation_cut && have_boundary_) {
    write(at_boundary_);
    return;
  }
  Checkpoint c = capture("evolution");
  c.evolution = current;
  write(c);
}

void Checkpointer::enumeration_tick() {
  std::unique_lock lock(write_mutex_, std::try_to_lock);
  if (!lock.owns_lock() || !due() || !deferred_error_.empty()) return;
  try {
    write(capture("enumeration"));
  } catch (const Error& e) {
    // Not thrown on an enumeration worker: the next write, on the search's thread, reports it.
    deferred_error_ = e.message();
  }
}

void Checkpointer::write_enumeration() {
  std::lock_guard lock(write_mutex_);
  write(capture("enumeration"));
}

}  // namespace shaderfit::search_detail
