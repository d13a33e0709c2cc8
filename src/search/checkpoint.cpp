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
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/hash.hpp"
#include "search/exact_json.hpp"

// The build defines it for this file from the CMake project version (CMakeLists.txt).
#ifndef SHADERFIT_VERSION
#define SHADERFIT_VERSION "unknown"
#endif

namespace shaderfit::search_detail {

using core_detail::fnv1a64;

namespace {

using nlohmann::json;

constexpr std::string_view kMagic = "shaderfit checkpoint";

// A body that does not hold what the format says; reported as a damaged file.
using BadBody = BadExactJson;

json num(double v) { return exact_number(v); }
double get_num(const json& j) { return exact_number_from(j); }
template <class T>
T get_integer(const json& j, std::string_view field) {
  return exact_integer_from<T>(j, field);
}
json expression_json(const Expression& e) { return exact_expression_json(e); }
Expression expression_from(const json& j) { return exact_expression_from(j); }

}  // namespace

json saved_individual_json(const SavedIndividual& s) {
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

SavedIndividual saved_individual_from(const json& j) {
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

namespace {

void check_rng_text(const std::string& text) {
  Rng rng;
  if (!rng_from_text(text, &rng)) throw BadBody("a random generator state does not read back");
}

}  // namespace

json saved_island_json(const SavedIsland& is) {
  json pop = json::array();
  for (const SavedIndividual& s : is.population) pop.push_back(saved_individual_json(s));
  return {{"rng", is.rng}, {"population", pop}};
}

SavedIsland saved_island_from(const json& j) {
  SavedIsland island;
  island.rng = j.at("rng").get<std::string>();
  check_rng_text(island.rng);
  for (const json& s : j.at("population")) island.population.push_back(saved_individual_from(s));
  return island;
}

namespace {

json body_json(const Checkpoint& c) {
  json options = json::array();
  for (const auto& [k, v] : c.options) options.push_back({k, v});
  json front = json::array();
  for (const FrontMember& m : c.front) front.push_back(front_member_json(m, FrontJson::Exact));
  json islands = json::array();
  for (const SavedIsland& is : c.evolution.islands) islands.push_back(saved_island_json(is));
  json data = {{"hash", c.data_hash}, {"rows", c.rows}, {"inputs", c.input_names}};
  if (c.symmetry)
    data["symmetry"] = {{"input", c.symmetry->input_name},
                        {"kind", symmetry_kind_name(c.symmetry->kind)},
                        {"center", num(c.symmetry->center)},
                        {"sign", c.symmetry->sign},
                        {"method", symmetry_method_name(c.symmetry->evidence.method)},
                        {"rows_compared", c.symmetry->evidence.rows_compared},
                        {"max_residual", num(c.symmetry->evidence.max_residual)},
                        {"noise", num(c.symmetry->evidence.noise)}};
  return {{"phase", search_phase_name(c.phase)},
          {"data", data},
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
            {"ranks", c.ranks},
            {"islands", islands}}}};
}

Checkpoint checkpoint_from(const json& j) {
  Checkpoint c;
  const auto phase = search_phase_from_name(j.at("phase").get<std::string>());
  if (!phase) throw BadBody("an unknown phase");
  c.phase = *phase;
  const json& d = j.at("data");
  c.data_hash = get_integer<std::uint64_t>(d.at("hash"), "hash");
  c.rows = get_integer<std::size_t>(d.at("rows"), "rows");
  c.input_names = d.at("inputs").get<std::vector<std::string>>();
  if (d.contains("symmetry")) {
    const json& sy = d.at("symmetry");
    const auto input =
        std::find(c.input_names.begin(), c.input_names.end(), sy.at("input").get<std::string>());
    const auto kind = symmetry_kind_from_name(sy.at("kind").get<std::string>());
    if (input == c.input_names.end() || !kind)
      throw BadBody("a symmetry in no known input or kind");
    c.symmetry =
        DataSymmetry{static_cast<std::size_t>(input - c.input_names.begin()), *input, *kind,
                     get_num(sy.at("center")), get_integer<int>(sy.at("sign"), "sign")};
    if (c.symmetry->sign < -1 || c.symmetry->sign > 1)
      throw BadBody("a symmetry sign not -1, 0 or 1");
    if (sy.contains("method")) {  // the evidence; absent in older checkpoints
      const auto method = symmetry_method_from_name(sy.at("method").get<std::string>());
      if (!method) throw BadBody("a symmetry found by no known method");
      c.symmetry->evidence = {*method,
                              get_integer<std::size_t>(sy.at("rows_compared"), "rows_compared"),
                              get_num(sy.at("max_residual")), get_num(sy.at("noise"))};
    }
  }
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
    if (!m.is_object() || !m.contains("expression"))
      throw BadBody("a front member without its expression");
    c.front.push_back(front_member_from_json(m, c.input_names, {}, "front").member);
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
  if (ev.contains("ranks")) c.ranks = get_integer<int>(ev.at("ranks"), "ranks");
  if (c.ranks < 1) throw BadBody("a count of ranks below 1");
  for (const json& is : ev.at("islands")) {
    c.evolution.islands.push_back(saved_island_from(is));
    for (const SavedIndividual& s : c.evolution.islands.back().population) over_inputs(s.expr);
  }
  if (c.phase == SearchPhase::Evolution) {
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

}  // namespace

std::string_view checkpoint_writer_version() { return SHADERFIT_VERSION; }

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
  std::vector<std::pair<std::string, std::string>> out;
  for (const SearchOptionField& f : search_option_fields())
    if (f.role == OptionRole::Search) out.emplace_back(f.name, search_option_text(o, f));
  return out;
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
  const SourceLocation where{"SearchOptions::checkpoint_path"};
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

std::string read_checkpoint_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open the checkpoint '" + path + "'", {"SearchOptions::resume_path"});
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

Checkpoint read_checkpoint(const std::string& path) {
  return parse_checkpoint(read_checkpoint_text(path), path);
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
  // An option the checkpoint does not record (one added since it was written) is taken to have
  // had its default.
  const auto defaults = checkpoint_options(SearchOptions{});
  for (const auto& option : checkpoint_options(options)) {
    auto it = std::find_if(c.options.begin(), c.options.end(),
                           [&](const auto& kv) { return kv.first == option.first; });
    auto fallback = std::find_if(defaults.begin(), defaults.end(),
                                 [&](const auto& kv) { return kv.first == option.first; });
    const std::string then = it != c.options.end() ? it->second : fallback->second;
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
  base_.symmetry = ctx.symmetry;
  base_.options = checkpoint_options(o);
  base_.ranks = ctx.ranks.size();
  // Fail now, not after an hour of searching, when the file cannot be written.
  const std::string tmp = o.checkpoint_path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr)
    throw Error("cannot write the checkpoint '" + tmp + "': " + std::strerror(errno),
                {"SearchOptions::checkpoint_path"});
  std::fclose(f);
  std::remove(tmp.c_str());
  last_write_s_ = ctx.elapsed();
}

void Checkpointer::begin_evolution(double enumeration_time_s, std::uint64_t distinct_candidates,
                                   int enumeration_cost_completed, const Rng& rng) {
  base_.enumeration_time_s = enumeration_time_s;
  base_.distinct_candidates = distinct_candidates;
  base_.enumeration_cost_completed = enumeration_cost_completed;
  base_.rng = rng_text(rng);
}

Checkpoint Checkpointer::capture(SearchPhase phase) {
  Checkpoint c = base_;
  c.phase = phase;
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
  if (!deferred_error_.empty()) throw Error(deferred_error_, {"SearchOptions::checkpoint_path"});
  write_checkpoint(ctx_.options.checkpoint_path, c);
  last_write_s_ = ctx_.elapsed();
}

void Checkpointer::at_boundary(const EvolutionState& state) {
  std::lock_guard lock(write_mutex_);
  at_boundary_ = capture(SearchPhase::Evolution);
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
  Checkpoint c = capture(SearchPhase::Evolution);
  c.evolution = current;
  write(c);
}

void Checkpointer::enumeration_tick() {
  std::unique_lock lock(write_mutex_, std::try_to_lock);
  if (!lock.owns_lock() || !due() || !deferred_error_.empty()) return;
  try {
    write(capture(SearchPhase::Enumeration));
  } catch (const Error& e) {
    // Not thrown on an enumeration worker: the next write, on the search's thread, reports it.
    deferred_error_ = e.message();
  }
}

void Checkpointer::write_enumeration() {
  std::lock_guard lock(write_mutex_);
  write(capture(SearchPhase::Enumeration));
}

}  // namespace shaderfit::search_detail
