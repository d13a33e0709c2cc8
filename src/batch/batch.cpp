#include "shaderfit/batch/batch.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "core/files.hpp"
#include "search/exact_json.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/precision.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/report/search_json.hpp"
#include "shaderfit/search/front/choice.hpp"
#include "shaderfit/verify/worst_case.hpp"

namespace shaderfit {

namespace {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The baseline as the front's members are measured: its cost, its errors on the rows (weighted
// as the search weighs them) and, with a reference, between the samples too; float32 as a
// shader computes it.
BaselineScore score_baseline(const ManifestEntry& entry, const SearchOptions& o,
                             const SearchProblem& sp) {
  const Problem& p = *entry.loaded;
  BaselineScore b;
  b.formula = entry.baseline;
  const Expression e = parse_formula_on(entry.baseline, p.data, "ManifestEntry::baseline");
  b.cost = expression_cost(e, o.cost, o.uniform);
  const std::vector<double> y = evaluate_on(e, p.data, o.precision);
  b.metrics = error_metrics(y, sp.target, {}, sp.weights);
  const std::vector<double> y32 = evaluate_on(e, p.data, Precision::Float);
  for (std::size_t i = 0; i < y32.size(); ++i)
    b.float32_max_abs = std::max(b.float32_max_abs, std::isfinite(y32[i])
                                                        ? std::abs(y32[i] - sp.target[i])
                                                        : std::numeric_limits<double>::infinity());
  if (p.reference) {
    WorstCaseOptions wo;
    wo.samples = entry.problem.samples;
    wo.threads = std::max(1, o.threads);
    const WorstCase c = WorstCaseSearch(*p.reference, e.variables, wo).check(e);
    b.metrics.max_abs = std::max(b.metrics.max_abs, c.max_abs);
    b.metrics.max_rel = std::max(b.metrics.max_rel, c.max_rel);
    b.float32_max_abs = std::max(b.float32_max_abs, c.float32_max_abs);
  }
  b.loss = loss_value(o.loss, b.metrics);
  return b;
}

// The goal's member of the front, whether the goal is met, and why.
void choose_for_goal(BatchEntryResult& r, const std::string& loss) {
  if (r.front.empty()) {
    r.why = "the search found no formula";
    return;
  }
  const Choice c = choose_member(r.front, batch_choice_rule(r), loss);
  r.chosen = c.index;
  r.why = c.why;
  const FrontMember& m = r.front[c.index];
  switch (r.goal.kind) {
    case BatchGoal::Kind::Knee: r.goal_met = true; break;
    case BatchGoal::Kind::MaxCost: r.goal_met = m.cost <= r.goal.limit; break;
    case BatchGoal::Kind::MaxError: r.goal_met = m.loss <= r.goal.limit; break;
    case BatchGoal::Kind::BeatBaseline:
      r.goal_met = m.cost <= r.baseline->cost && m.loss <= r.baseline->loss;
      r.why = fmt::format("{}; the baseline costs {:g} with {} {:.4g}", c.why, r.baseline->cost,
                          loss, r.baseline->loss);
      break;
  }
}

// The order entries start in: the longest first, by time budget, then candidate budget, then
// rows; ties in manifest order.
std::vector<std::size_t> longest_first(const std::vector<const ManifestEntry*>& entries) {
  std::vector<std::size_t> order(entries.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto key = [&](std::size_t i) {
    const ManifestEntry& e = *entries[i];
    const double evals =
        e.options.max_candidates ? static_cast<double>(*e.options.max_candidates) : 1e300;
    return std::tuple(-e.options.time_limit_s, -evals,
                      -static_cast<double>(e.loaded ? e.loaded->data.rows() : 0));
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  return order;
}

std::string checkpoint_path(const std::string& directory, const std::string& name) {
  return (std::filesystem::path(directory) / (name + ".json")).string();
}

// The finished entry read back from its checkpoint, when the file holds the entry's hash.
std::optional<BatchEntryResult> read_finished(const std::string& directory,
                                              const ManifestEntry& entry) {
  const std::string path = checkpoint_path(directory, entry.name);
  std::ifstream f(path, std::ios::binary);
  if (!f) return std::nullopt;
  std::ostringstream text;
  text << f.rdbuf();
  try {
    BatchEntryResult r = batch_entry_from_json(text.str(), path);
    if (r.hash != entry.hash) return std::nullopt;
    r.from_checkpoint = true;
    return r;
  } catch (const Error&) {
    return std::nullopt;  // a damaged file: the entry runs again
  }
}

// Written to a temporary file and renamed, so that an interrupted write never leaves a file
// that reads as finished.
void write_finished(const std::string& directory, const BatchEntryResult& r) {
  make_directories(directory);
  const std::string path = checkpoint_path(directory, r.name);
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!(f << batch_entry_json(r))) throw Error("cannot write '" + tmp + "'", {tmp});
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw Error("cannot write '" + path + "': " + ec.message(), {path});
}

// Numbers to the last bit, NaN and infinities included (a relative error where the target is
// 0): the checkpoint reads back what the run computed.
json baseline_json(const std::optional<BaselineScore>& b) {
  using search_detail::exact_number;
  if (!b) return nullptr;
  const ErrorMetrics& m = b->metrics;
  return {{"formula", b->formula},
          {"cost", exact_number(b->cost)},
          {"loss", exact_number(b->loss)},
          {"float32_max_abs", exact_number(b->float32_max_abs)},
          {"metrics",
           {{"rows", m.rows},
            {"mse", exact_number(m.mse)},
            {"rmse", exact_number(m.rmse)},
            {"max_abs", exact_number(m.max_abs)},
            {"max_rel", exact_number(m.max_rel)},
            {"rel", exact_number(m.rel)},
            {"log", exact_number(m.log)},
            {"nonfinite", m.nonfinite}}}};
}

BaselineScore baseline_from_json(const json& j) {
  using search_detail::exact_number_from;
  BaselineScore b;
  b.formula = j.at("formula").get<std::string>();
  b.cost = exact_number_from(j.at("cost"));
  b.loss = exact_number_from(j.at("loss"));
  b.float32_max_abs = exact_number_from(j.at("float32_max_abs"));
  const json& m = j.at("metrics");
  b.metrics.rows = m.at("rows").get<std::size_t>();
  b.metrics.mse = exact_number_from(m.at("mse"));
  b.metrics.rmse = exact_number_from(m.at("rmse"));
  b.metrics.max_abs = exact_number_from(m.at("max_abs"));
  b.metrics.max_rel = exact_number_from(m.at("max_rel"));
  b.metrics.rel = exact_number_from(m.at("rel"));
  b.metrics.log = exact_number_from(m.at("log"));
  b.metrics.nonfinite = m.at("nonfinite").get<std::size_t>();
  return b;
}

}  // namespace

ChoiceRule batch_choice_rule(const BatchEntryResult& r) {
  switch (r.goal.kind) {
    case BatchGoal::Kind::Knee: break;
    case BatchGoal::Kind::MaxCost: return {ChoiceRule::Kind::MaxCost, r.goal.limit};
    case BatchGoal::Kind::MaxError: return {ChoiceRule::Kind::MaxError, r.goal.limit};
    case BatchGoal::Kind::BeatBaseline:
      if (r.baseline) return {ChoiceRule::Kind::MaxCost, r.baseline->cost};
      break;
  }
  return {};
}

std::string batch_entry_line(const BatchEntryResult& r) {
  if (r.front.empty()) return fmt::format("{}  no formula found", r.name);
  const FrontMember& m = r.front[r.chosen];
  std::string line = fmt::format("{}  cost {:g}", r.name, m.cost);
  if (r.baseline) line += fmt::format(" (baseline {:g})", r.baseline->cost);
  line += fmt::format("  {} {:.3g}", r.loss_name, m.loss);
  if (r.baseline) line += fmt::format(" (baseline {:.3g})", r.baseline->loss);
  line += r.goal.kind == BatchGoal::Kind::Knee ? "" : r.goal_met ? "  goal met" : "  goal missed";
  line += r.from_checkpoint ? "  (finished earlier)" : fmt::format("  {:.1f} s", r.seconds);
  if (!r.from_checkpoint && r.rank == BatchEntryResult::kAllRanks) line += " on every rank";
  return line;
}

BatchEntryResult run_batch_entry(const ManifestEntry& entry, const std::atomic<bool>* interrupt,
                                 Communicator* communicator) {
  if (!entry.loaded)
    throw Error("entry '" + entry.name + "' has no loaded problem", {"ManifestEntry::loaded"});
  const Problem& p = *entry.loaded;
  const auto t0 = Clock::now();
  SearchOptions o = entry.options;
  // A built-in data set's own operators, unless the manifest names others.
  if (is_auto_operators(o.operators) && !p.operators.empty())
    set_search_option(o, "operators", p.operators);
  if (is_auto_operators(o.evolution_operators) && !p.evolution_operators.empty())
    set_search_option(o, "evolution_operators", p.evolution_operators);
  // The formula in use today seeds the search, its constants refitted.
  if (!entry.baseline.empty() && entry.start_from_baseline &&
      std::find(o.start.begin(), o.start.end(), entry.baseline) == o.start.end())
    o.start.push_back(entry.baseline);
  o.interrupt = interrupt;
  o.communicator = communicator;
  SearchProblem sp = search_problem(p, o.loss, entry.weights, {"ManifestEntry::weights"});
  sp.reference_samples = entry.problem.samples;
  o = resolve_auto_operators(o, sp);
  SearchSummary summary;
  run_search(o, sp, &summary);
  if (communicator != nullptr && communicator->rank() != 0) return {};  // rank 0 has the result

  BatchEntryResult r;
  r.name = entry.name;
  r.hash = entry.hash;
  r.description = p.description;
  r.inputs = p.inputs;
  r.target = p.target;
  r.loss_name = std::string(loss_name(o.loss));
  r.cost_name = std::string(cost_target_name(o.cost));
  r.goal = entry.goal;
  r.front = summary.front;
  SearchDataInfo info{p.description, p.target, 0.0, p.data.rows(), p.inputs};
  info.problem = entry.problem;
  r.run_json = search_json(summary, o, info);
  if (!entry.baseline.empty()) r.baseline = score_baseline(entry, o, sp);
  choose_for_goal(r, r.loss_name);
  r.seconds = seconds_since(t0);
  return r;
}

std::string batch_entry_json(const BatchEntryResult& r) {
  json front = json::array();
  for (const FrontMember& m : r.front) front.push_back(front_member_json(m, FrontJson::Exact));
  json j{{"schema", "shaderfit.batch-entry/1"},
         {"name", r.name},
         {"hash", r.hash},
         {"description", r.description},
         {"inputs", r.inputs},
         {"target", r.target},
         {"loss", r.loss_name},
         {"cost", r.cost_name},
         {"goal", batch_goal_text(r.goal)},
         {"goal_kind", static_cast<int>(r.goal.kind)},
         {"goal_limit", search_detail::exact_number(r.goal.limit)},
         {"front", front},
         {"chosen", r.chosen},
         {"goal_met", r.goal_met},
         {"why", r.why},
         {"baseline", baseline_json(r.baseline)},
         {"run", json::parse(r.run_json)},
         {"seconds", search_detail::exact_number(r.seconds)},
         {"rank", r.rank}};
  return j.dump(1);
}

BatchEntryResult batch_entry_from_json(const std::string& text, const std::string& source) {
  try {
    const json j = json::parse(text);
    if (j.value("schema", "") != "shaderfit.batch-entry/1")
      throw Error("not a batch entry (schema shaderfit.batch-entry/1)", {source});
    BatchEntryResult r;
    r.name = j.at("name").get<std::string>();
    r.hash = j.at("hash").get<std::string>();
    r.description = j.at("description").get<std::string>();
    r.inputs = j.at("inputs").get<std::vector<std::string>>();
    r.target = j.at("target").get<std::string>();
    r.loss_name = j.at("loss").get<std::string>();
    r.cost_name = j.at("cost").get<std::string>();
    r.goal.kind = static_cast<BatchGoal::Kind>(j.at("goal_kind").get<int>());
    r.goal.limit = search_detail::exact_number_from(j.at("goal_limit"));
    for (const json& m : j.at("front"))
      r.front.push_back(front_member_from_json(m, r.inputs, {}, source).member);
    r.chosen = j.at("chosen").get<std::size_t>();
    if (!r.front.empty() && r.chosen >= r.front.size())
      throw Error("chosen member out of range", {source});
    r.goal_met = j.at("goal_met").get<bool>();
    r.why = j.at("why").get<std::string>();
    if (!j.at("baseline").is_null()) r.baseline = baseline_from_json(j.at("baseline"));
    r.run_json = j.at("run").dump(2);
    r.seconds = search_detail::exact_number_from(j.at("seconds"));
    r.rank = j.value("rank", 0);
    return r;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // JSON that does not parse or lacks a field
    throw Error(std::string("cannot read the batch entry: ") + e.what(), {source});
  }
}

namespace {

// Messages between ranks (Communicator::send), one line of text, then a body for some:
//   worker -> 0: "ready", "alive I", "done I\n<batch_entry_json>", "failed I\n<message>",
//                "interrupted I"
//   0 -> worker: "run I HASH" (I indexes the manifest's entries; HASH is checked), "stop", or
//                "stop lost" when a rank died (the worker then ends without MPI_Finalize)
std::pair<std::string, std::string> split_message(const std::string& m) {
  const auto nl = m.find('\n');
  if (nl == std::string::npos) return {m, ""};
  return {m.substr(0, nl), m.substr(nl + 1)};
}

// What the across-ranks phase leaves for the rest of the batch (on rank 0).
struct AcrossRanks {
  std::vector<std::optional<BatchEntryResult>> done;  // by manifest index; reported already
  std::vector<std::pair<std::size_t, std::string>> failed;
  Clock::time_point start = Clock::now();
};

// Every rank: the entries marked across_ranks, in manifest order, each searched by all ranks
// together. Rank 0 decides what runs (not finished earlier, not interrupted) and tells the
// others; an entry whose digest differs between ranks runs nowhere.
AcrossRanks search_across_ranks(const Manifest& manifest, const BatchOptions& options,
                                Communicator& comm) {
  AcrossRanks out;
  out.done.resize(manifest.entries.size());
  const bool leader = comm.rank() == 0;
  auto stopped = [&] { return options.interrupt != nullptr && options.interrupt->load(); };
  std::size_t finished = 0;
  for (std::size_t i = 0; i < manifest.entries.size(); ++i) {
    const ManifestEntry& e = manifest.entries[i];
    if (!e.across_ranks) continue;
    std::string decision = "skip";
    if (leader) {
      if (!options.checkpoint_directory.empty())
        out.done[i] = read_finished(options.checkpoint_directory, e);
      if (out.done[i]) {
        ++finished;
        if (options.on_entry) options.on_entry(*out.done[i]);
      } else if (!stopped()) {
        decision = "run";
      }
    }
    if (comm.broadcast(decision, 0) != "run") continue;
    const std::vector<std::string> digests = comm.all_gather(e.hash);
    if (std::any_of(digests.begin(), digests.end(), [&](const auto& d) { return d != e.hash; })) {
      if (leader)
        out.failed.emplace_back(i, "the ranks read different manifests (its digest differs)");
      continue;
    }
    if (leader && options.on_progress)
      options.on_progress({finished, manifest.entries.size(), seconds_since(out.start), {e.name}});
    std::optional<BatchEntryResult> r;
    std::string error;
    try {
      r = run_batch_entry(e, options.interrupt, &comm);
    } catch (const std::exception& ex) {  // thrown alike on every rank: checked before any message
      error = ex.what();
    }
    if (!leader) continue;
    if (r && !stopped()) {
      r->rank = BatchEntryResult::kAllRanks;
      if (!options.checkpoint_directory.empty()) write_finished(options.checkpoint_directory, *r);
      ++finished;
      if (options.on_entry) options.on_entry(*r);
      out.done[i] = std::move(r);
    } else if (!error.empty()) {
      out.failed.emplace_back(i, error);
    }
  }
  return out;
}

// Runs a batch: the entries not finished by an earlier run, on local worker threads and, with a
// communicator, on the other ranks as they ask for work. Everything is on rank 0's side: the
// queue, the results, the checkpoints and the callbacks (on the calling thread).
class Coordinator {
 public:
  // `earlier`: what the across-ranks phase finished (already reported) or failed, and when the
  // batch started.
  Coordinator(const Manifest& m, const BatchOptions& o, Communicator* comm,
              AcrossRanks earlier = {})
      : manifest_(m),
        options_(o),
        comm_(comm),
        done_(std::move(earlier.done)),
        failed_(std::move(earlier.failed)),
        t0_(earlier.start) {
    done_.resize(m.entries.size());
  }

  BatchResult run() {
    const auto t0 = t0_;
    BatchResult result;
    result.manifest = manifest_.path;
    result.bad = manifest_.bad;
    progress_.total = manifest_.entries.size();
    std::vector<const ManifestEntry*> todo;
    std::vector<std::size_t> todo_index;
    for (std::size_t i = 0; i < manifest_.entries.size(); ++i) {
      const ManifestEntry& e = manifest_.entries[i];
      if (done_[i]) {  // searched across the ranks, or read back then
        ++progress_.done;
        continue;
      }
      if (std::any_of(failed_.begin(), failed_.end(), [i](const auto& f) { return f.first == i; }))
        continue;
      if (!options_.checkpoint_directory.empty())
        done_[i] = read_finished(options_.checkpoint_directory, e);
      if (done_[i]) {
        ++progress_.done;
        if (options_.on_entry) options_.on_entry(*done_[i]);
      } else {
        todo.push_back(&e);
        todo_index.push_back(i);
      }
    }
    for (std::size_t k : longest_first(todo)) queue_.push_back(todo_index[k]);

    int workers = options_.parallel_entries > 0
                      ? options_.parallel_entries
                      : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    workers = std::max(1, std::min<int>(workers, static_cast<int>(queue_.size())));
    std::vector<std::thread> threads;
    if (!queue_.empty())
      for (int w = 0; w < workers; ++w) threads.emplace_back([this] { local_worker(); });
    {
      std::unique_lock lock(mutex_);
      for (;;) {
        if (comm_ != nullptr) {
          lock.unlock();
          serve_ranks();
          lock.lock();
        } else {
          changed_.wait_for(lock, std::chrono::milliseconds(200));
        }
        while (!finished_.empty()) {
          const std::size_t i = finished_.front();
          finished_.pop_front();
          ++progress_.done;
          lock.unlock();
          if (options_.on_entry) options_.on_entry(*done_[i]);
          lock.lock();
        }
        if (options_.on_progress) {
          progress_.elapsed_s = seconds_since(t0);
          progress_.running = running_;
          for (const auto& [rank, assignment] : assigned_)
            progress_.running.push_back(manifest_.entries[assignment.index].name);
          BatchProgress copy = progress_;
          lock.unlock();
          options_.on_progress(copy);
          lock.lock();
        }
        const bool local_idle = running_.empty() && (queue_.empty() || stopped());
        const bool remote_idle = assigned_.empty() || stopped();
        if (local_idle && remote_idle && finished_.empty()) break;
      }
    }
    for (std::thread& t : threads) t.join();
    if (comm_ != nullptr)
      for (int r = 1; r < comm_->size(); ++r)
        if (!dead_.contains(r)) comm_->send(r, dead_.empty() ? "stop" : "stop lost");
    for (std::size_t i = 0; i < done_.size(); ++i)
      if (done_[i]) result.entries.push_back(std::move(*done_[i]));
    for (const auto& [i, message] : failed_)
      result.bad.push_back({manifest_.entries[i].name, manifest_.entries[i].line,
                            "entry '" + manifest_.entries[i].name + "': " + message});
    result.interrupted = stopped();
    result.seconds = seconds_since(t0);
    result.notes = notes_;
    return result;
  }

 private:
  struct Assignment {
    std::size_t index = 0;
    Clock::time_point heard;
  };

  bool stopped() const { return options_.interrupt != nullptr && options_.interrupt->load(); }

  // A finished entry (under the lock): kept, checkpointed, and reported by the calling thread.
  void finish(std::size_t i, BatchEntryResult r) {
    done_[i] = std::move(r);
    finished_.push_back(i);
    changed_.notify_all();
  }

  void local_worker() {
    for (;;) {
      std::size_t i = 0;
      {
        // With entries out on other ranks, stay: one that dies comes back to the queue.
        std::unique_lock lock(mutex_);
        while (queue_.empty() && !assigned_.empty() && !stopped())
          changed_.wait_for(lock, std::chrono::milliseconds(200));
        if (queue_.empty() || stopped()) return;
        i = queue_.front();
        queue_.pop_front();
        running_.push_back(manifest_.entries[i].name);
      }
      const ManifestEntry& e = manifest_.entries[i];
      std::optional<BatchEntryResult> r;
      std::string error;
      try {
        r = run_batch_entry(e, options_.interrupt);
        if (stopped()) r.reset();  // not finished: it runs again from the start next time
        if (r && !options_.checkpoint_directory.empty())
          write_finished(options_.checkpoint_directory, *r);
      } catch (const std::exception& ex) {
        error = ex.what();
      }
      std::lock_guard lock(mutex_);
      std::erase(running_, e.name);
      if (r)
        finish(i, std::move(*r));
      else if (!error.empty())
        failed_.emplace_back(i, error);
      changed_.notify_all();
    }
  }

  // One round of the other ranks' messages (about 0.1 s): their requests, beats and results;
  // then work for the ranks that asked, and the entries of ranks gone silent handed out again.
  void serve_ranks() {
    for (auto m = comm_->receive(0.1); m; m = comm_->receive(0)) {
      const auto [from, text] = *m;
      const auto [head, body] = split_message(text);
      std::istringstream words(head);
      std::string verb;
      std::size_t i = 0;
      words >> verb >> i;
      std::lock_guard lock(mutex_);
      if (dead_.contains(from)) continue;
      if (verb == "ready") {
        waiting_.push_back(from);
      } else if (verb == "alive") {
        if (auto a = assigned_.find(from); a != assigned_.end()) a->second.heard = Clock::now();
      } else if (verb == "done" || verb == "failed" || verb == "interrupted") {
        assigned_.erase(from);
        if (i >= manifest_.entries.size() || done_[i]) continue;
        if (verb == "failed") {
          failed_.emplace_back(i, body);
        } else if (verb == "done") {
          try {
            BatchEntryResult r = batch_entry_from_json(body, "rank " + std::to_string(from));
            r.rank = from;
            if (!options_.checkpoint_directory.empty())
              write_finished(options_.checkpoint_directory, r);
            finish(i, std::move(r));
          } catch (const std::exception& ex) {
            failed_.emplace_back(i, ex.what());
          }
        }
      }
    }
    std::lock_guard lock(mutex_);
    const auto now = Clock::now();
    for (auto a = assigned_.begin(); a != assigned_.end();) {
      if (std::chrono::duration<double>(now - a->second.heard).count() <= options_.rank_timeout_s) {
        ++a;
        continue;
      }
      // Silent too long: taken for dead, its entry first in line for another rank.
      const std::string& name = manifest_.entries[a->second.index].name;
      notes_.push_back(
          fmt::format("rank {} went silent while it searched {}: taken for dead, {} "
                      "handed out again",
                      a->first, name, name));
      dead_.insert(a->first);
      comm_->forget(a->first);
      queue_.push_front(a->second.index);
      a = assigned_.erase(a);
    }
    while (!waiting_.empty() && !queue_.empty() && !stopped()) {
      const int rank = waiting_.front();
      waiting_.pop_front();
      const std::size_t i = queue_.front();
      queue_.pop_front();
      assigned_[rank] = {i, Clock::now()};
      comm_->send(rank, fmt::format("run {} {}", i, manifest_.entries[i].hash));
    }
    changed_.notify_all();
  }

  const Manifest& manifest_;
  const BatchOptions& options_;
  Communicator* comm_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::size_t> queue_;
  std::vector<std::optional<BatchEntryResult>> done_;
  std::deque<std::size_t> finished_;  // into done_, not yet reported
  std::vector<std::pair<std::size_t, std::string>> failed_;
  std::vector<std::string> running_;  // local entries being searched
  std::map<int, Assignment> assigned_;
  std::deque<int> waiting_;
  std::set<int> dead_;
  std::vector<std::string> notes_;
  BatchProgress progress_;
  Clock::time_point t0_;
};

// A rank other than 0: asks for an entry, searches it on a thread while it beats every second
// and listens for "stop", sends the result, and asks again, until told to stop.
void serve_as_worker(const Manifest& manifest, const BatchOptions& options, Communicator& comm) {
  const double beat_s = std::min(1.0, options.rank_timeout_s / 4);
  auto interrupted = [&] { return options.interrupt != nullptr && options.interrupt->load(); };
  comm.send(0, "ready");
  for (;;) {
    const auto m = comm.receive(0.2);
    if (interrupted()) return;
    if (!m || m->first != 0) continue;
    const auto [head, body] = split_message(m->second);
    std::istringstream words(head);
    std::string verb, hash;
    std::size_t i = 0;
    words >> verb >> i >> hash;
    if (verb == "stop") {
      if (head == "stop lost") comm.forget(-1);  // no collective call may wait for the dead
      return;
    }
    if (verb != "run") continue;
    if (i >= manifest.entries.size() || manifest.entries[i].hash != hash) {
      comm.send(0, fmt::format("failed {}\nrank {} reads another manifest (entry {} differs)", i,
                               comm.rank(), i));
      comm.send(0, "ready");
      continue;
    }
    std::atomic<bool> stop{false};
    std::atomic<bool> finished{false};
    std::optional<BatchEntryResult> result;
    std::string error;
    std::thread search([&] {
      try {
        result = run_batch_entry(manifest.entries[i], &stop);
      } catch (const std::exception& ex) {
        error = ex.what();
      }
      finished.store(true);
    });
    auto last_beat = Clock::now();
    bool told_to_stop = false;
    while (!finished.load()) {
      if (const auto s = comm.receive(0.05); s && s->first == 0 && s->second.starts_with("stop")) {
        if (s->second == "stop lost") comm.forget(-1);
        told_to_stop = true;
        stop.store(true);
      }
      if (interrupted()) stop.store(true);
      if (seconds_since(last_beat) >= beat_s) {
        comm.send(0, fmt::format("alive {}", i));
        last_beat = Clock::now();
      }
    }
    search.join();
    if (stop.load()) {
      comm.send(0, fmt::format("interrupted {}", i));
      if (told_to_stop || interrupted()) return;
    } else if (result) {
      result->rank = comm.rank();
      comm.send(0, fmt::format("done {}\n{}", i, batch_entry_json(*result)));
    } else {
      comm.send(0, fmt::format("failed {}\n{}", i, error));
    }
    comm.send(0, "ready");
  }
}

}  // namespace

BatchResult run_batch(const Manifest& manifest, const BatchOptions& options) {
  return Coordinator(manifest, options, nullptr).run();
}

BatchResult run_batch_distributed(const Manifest& manifest, const BatchOptions& options,
                                  Communicator& communicator) {
  AcrossRanks earlier = search_across_ranks(manifest, options, communicator);
  if (communicator.rank() != 0) {
    serve_as_worker(manifest, options, communicator);
    return {};
  }
  return Coordinator(manifest, options, &communicator, std::move(earlier)).run();
}

}  // namespace shaderfit
