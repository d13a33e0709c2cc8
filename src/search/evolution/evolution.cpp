#include "search/evolution/evolution.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "search/evolution/constant_fit.hpp"
#include "search/exact_json.hpp"
#include "search/evolution/nsga2.hpp"
#include "search/evolution/rewrites.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/simplify.hpp"
#include "shaderfit/fit/fit.hpp"
#include "shaderfit/fit/linear.hpp"
#include "shaderfit/search/front_member.hpp"

namespace shaderfit::search_detail {

namespace {

// An individual is scored on every row when its fit-row loss is within this factor of the
// front's loss at its cost (the fit rows are a sample, so their loss is an estimate), and, where
// the evolution races, so is its loss on the race rows.
constexpr double kFrontMargin = 1.1;
constexpr int kFitIterations = 4;     // Levenberg-Marquardt on the fit rows, warm-started: the
                                      // fitted values are inherited, so few steps suffice
constexpr int kRefitIterations = 10;  // and on every row (racing: the race rows), from there,
                                      // for front candidates
// Racing, on data with more rows than the fit rows and kRaceRows together: a child whose fit-row
// loss could enter the front is refitted on kRaceRows other rows and scored there, and only where
// that loss could enter too is it scored on every row (refitting and scoring every such child on
// every row took two thirds of the time on Burley's 15,096 rows). The race rows are the
// kRaceTail rows of the lowest and of the highest targets, and from the rows between them a
// sample stratified by the target, weighted by the rows each stands for: a few rows at the
// extremes (the forward peak of a phase function, grazing angles) can carry most of the squared
// error, and a plain sample, or the 256 fit rows, misjudged it by up to 5x.
constexpr std::size_t kRaceRows = 2048;
constexpr std::size_t kRaceTail = 256;
static_assert(2 * kRaceTail < kRaceRows);
// For a minimax loss, a front candidate whose least-squares loss on every row is within
// kMinimaxMargin of the front's at its cost is then refitted minimax on the fit rows (Lawson from
// the least-squares constants, kRefitPasses passes of kRefitSteps LM steps) and kept in that form
// when it is better on every row: the fit rows' least-squares constants choose shapes cheaply,
// the front shows minimax ones. (30 passes of 4 steps on every row cost erf_as_7126 of the
// yardstick more than half its generations.)
constexpr double kMinimaxMargin = 2.0;
constexpr int kRefitPasses = 10;
constexpr int kRefitSteps = 2;
constexpr std::size_t kMigrants = 4;
constexpr std::uint64_t kRestartEvery = 50;
// Near the end of the time budget, the front's fitted constants are refined on every row with a
// full Levenberg-Marquardt run (the evolution fits a few steps on the fit rows only), then, for
// a minimax loss, Lawson passes of kRefitIterations steps.
constexpr double kPolishAt = 0.9;
constexpr int kPolishIterations = 100;
constexpr int kPolishPasses = 100;
// Across ranks, islands are dealt again when the busiest rank took this much more than the mean
// since the last synchronisation.
constexpr double kRebalanceAbove = 1.1;
constexpr double kRebalanceGain = 0.95;  // and when that takes the busiest rank's share down by 5%

nlohmann::json metrics_json(const ErrorMetrics& m) {
  return {m.rows,
          exact_number(m.mse),
          exact_number(m.rmse),
          exact_number(m.max_abs),
          exact_number(m.max_rel),
          exact_number(m.rel),
          exact_number(m.log),
          m.nonfinite};
}

ErrorMetrics metrics_from(const nlohmann::json& j) {
  ErrorMetrics m;
  m.rows = exact_integer_from<std::size_t>(j.at(0), "rows");
  m.mse = exact_number_from(j.at(1));
  m.rmse = exact_number_from(j.at(2));
  m.max_abs = exact_number_from(j.at(3));
  m.max_rel = exact_number_from(j.at(4));
  m.rel = exact_number_from(j.at(5));
  m.log = exact_number_from(j.at(6));
  m.nonfinite = exact_integer_from<std::size_t>(j.at(7), "nonfinite");
  return m;
}

// The race rows (kRaceRows of `rows`, indices into target; see kRaceRows) and in *scale the
// weight of each: the number of rows it stands for.
std::vector<std::size_t> race_rows(std::span<const double> target, std::vector<std::size_t> rows,
                                   Rng& rng, std::vector<double>* scale) {
  std::stable_sort(rows.begin(), rows.end(),
                   [&](std::size_t a, std::size_t b) { return target[a] < target[b]; });
  const auto tail = static_cast<std::ptrdiff_t>(kRaceTail);
  std::vector<std::size_t> race(rows.begin(), rows.begin() + tail);
  race.insert(race.end(), rows.end() - tail, rows.end());
  scale->assign(race.size(), 1.0);
  std::vector<std::size_t> middle(rows.begin() + tail, rows.end() - tail);
  const std::size_t drawn = kRaceRows - 2 * kRaceTail;
  const double stands_for = static_cast<double>(middle.size()) / static_cast<double>(drawn);
  for (std::size_t r : stratified_rows(target, std::move(middle), drawn, rng)) {
    race.push_back(r);
    scale->push_back(stands_for);
  }
  return race;
}

double best_at(const std::vector<std::pair<double, double>>& front, double cost) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [c, l] : front)
    if (c <= cost) best = std::min(best, l);
  return best;
}

}  // namespace

Evolution::Evolution(SearchContext& ctx, Rng& rng) : ctx_(ctx) {
  const SearchOptions& o = ctx.options;
  limits_.variables = ctx.problem.input_names;
  limits_.operators = o.operators;
  for (Op op : o.evolution_operators)
    if (std::find(limits_.operators.begin(), limits_.operators.end(), op) ==
        limits_.operators.end())
      limits_.operators.push_back(op);
  limits_.max_power = o.max_power;
  limits_.literals = o.literals;
  limits_.max_nodes = o.max_nodes;
  limits_.max_parameters = o.max_parameters;
  // The uniform terminals are building blocks from the start (the front's parts join them).
  std::vector<const Expression*> terminals;
  for (const Expression& t : ctx.terminals) terminals.push_back(&t);
  limits_.blocks = subtree_blocks(terminals);

  // The fit rows: a uniform sample without replacement (all rows when there are few).
  const std::size_t rows = ctx.rows;
  std::vector<std::size_t> pick(rows);
  for (std::size_t i = 0; i < rows; ++i) pick[i] = i;
  const std::size_t m = std::min(rows, o.fit_rows);
  for (std::size_t i = 0; i < m; ++i) std::swap(pick[i], pick[i + uniform_index(rng, rows - i)]);
  {
    std::vector<std::size_t> fit(pick.begin(), pick.begin() + static_cast<std::ptrdiff_t>(m));
    std::sort(fit.begin(), fit.end());
    fit_ = RowSample(ctx.problem, fit);
  }
  rewrites_ = reference_formula(ctx.problem).formula.has_value();
  if (rewrites_) {
    rewrite_rows_.input_names = ctx.problem.input_names;
    rewrite_rows_.inputs = fit_.columns;
    rewrite_rows_.target = fit_.target;
    rewrite_rows_.weights = fit_.weights;
  }

  Expression x;
  x.variables = {"x"};
  x.nodes = {Node::variable(0)};
  x.update_lengths();
  scaling_cost_ =
      expression_cost(with_linear_scaling(x, 2.0, 1.0), o.cost) - expression_cost(x, o.cost);

  const int count = o.islands > 0 ? o.islands : 4;
  for (int i = 0; i < count; ++i) islands_.push_back(Island{Rng(rng()), {}, {}, 0});
  // The race rows, from the rows that are not fit rows (drawn after the islands' generators, so
  // that those are as without racing).
  if (rows > m + kRaceRows) {
    std::vector<std::size_t> rest(pick.begin() + static_cast<std::ptrdiff_t>(m), pick.end());
    std::vector<double> scale;
    const std::vector<std::size_t> race =
        race_rows(ctx.problem.target, std::move(rest), rng, &scale);
    race_ = RowSample(ctx.problem, race, scale);
  }
  for (std::size_t i = 0; i < islands_.size(); ++i) owner_.push_back(ctx.ranks.owner(i));
  for (std::size_t i = 0; i < islands_.size(); ++i)
    if (owns(i)) owned_.push_back(i);
  if (ctx.device == ComputeDevice::Cuda)
    gpu_ = std::make_unique<GpuEvaluator>(fit_.pointers, fit_.target, fit_.weights);
}

Evolution::RowSample::RowSample(const SearchProblem& p, std::span<const std::size_t> rows,
                                std::span<const double> scale) {
  columns.assign(p.inputs.size(), std::vector<double>(rows.size()));
  target.resize(rows.size());
  const bool weighted = !p.weights.empty() || !scale.empty();
  if (weighted) weights.resize(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t v = 0; v < p.inputs.size(); ++v) columns[v][i] = p.inputs[v][rows[i]];
    target[i] = p.target[rows[i]];
    if (weighted)
      weights[i] =
          (p.weights.empty() ? 1.0 : p.weights[rows[i]]) * (scale.empty() ? 1.0 : scale[i]);
  }
  for (const auto& c : columns) pointers.push_back(c.data());
}

SavedIndividual Evolution::saved(const Individual& ind) {
  return {ind.expr, ind.loss,   ind.cost, ind.raw_loss, ind.raw_cost,
          ind.hash, ind.scaled, ind.a,    ind.b};
}

Evolution::Individual Evolution::restored(const SavedIndividual& s) {
  return {s.expr, s.loss, s.cost, s.hash, s.raw_loss, s.raw_cost, s.scaled, s.a, s.b};
}

SavedIsland Evolution::saved_island(const Island& island) {
  SavedIsland out;
  out.rng = rng_text(island.rng);
  for (const Individual& ind : island.population) out.population.push_back(saved(ind));
  return out;
}

bool Evolution::owns(std::size_t island) const {
  return owner_[island] == ctx_.ranks.rank();
}

bool Evolution::out_of_time() const {
  return ctx_.stopped() || ctx_.elapsed() >= ctx_.options.time_limit_s ||
         (ctx_.options.interrupt != nullptr &&
          ctx_.options.interrupt->load(std::memory_order_relaxed));
}

void Evolution::fit_constants(Individual& ind) const {
  fit_constants(ind.expr, fit_, kFitIterations);
}

void Evolution::fit_constants(Expression& e, const RowSample& rows, int steps) const {
  if (e.parameters.empty()) return;
  FitOptions fo;
  fo.max_iterations = steps;
  FitProblem fp{&e, rows.pointers, rows.target, rows.weights};
  FitSummary fs;
  fit_parameters(fo, fp, &fs);
  e.parameter_values = fs.parameters;
  ctx_.node_evaluations.fetch_add(static_cast<std::uint64_t>(fs.iterations + 1) * e.size() *
                                      rows.size() * (1 + e.parameters.size()),
                                  std::memory_order_relaxed);
}

void Evolution::evaluate_batch(std::vector<Individual>& batch, Island& island,
                               std::vector<double>& values) const {
  if (gpu_ != nullptr) return evaluate_on_gpu(batch, island);
  for (Individual& ind : batch) evaluate(ind, island, values);
}

bool Evolution::evaluate(Individual& ind, Island& island, std::vector<double>& values) const {
  ++island.evaluated;
  Expression& e = ind.expr;
  values.resize(fit_.target.size());
  fit_constants(ind);
  shaderfit::evaluate(e, fit_.pointers, values, {.threads = 1});
  ctx_.node_evaluations.fetch_add(e.size() * fit_.target.size(), std::memory_order_relaxed);
  ind.raw_loss = ind.loss = loss_of(ctx_.options.loss, values, fit_.target, fit_.weights);
  ind.raw_cost = ind.cost = formula_cost(e, ctx_.options);
  ind.hash = structural_hash(e);
  ind.scaled = false;
  // The scaled form p0 * e + p1 has 4 more nodes; it must still fit in max_nodes.
  if (ctx_.options.linear_scaling && std::isfinite(ind.loss) &&
      e.size() + 4 <= static_cast<std::size_t>(limits_.max_nodes)) {
    const LinearScaling ls = fit_linear_scaling(values, fit_.target, fit_.weights);
    if (std::isfinite(ls.mse) && ls.a != 0.0) {
      for (double& v : values) v = ls.a * v + ls.b;
      const double loss = loss_of(ctx_.options.loss, values, fit_.target, fit_.weights);
      if (loss < ind.loss) {
        ind.loss = loss;
        ind.cost += scaling_cost_;
        ind.scaled = true;
        ind.a = ls.a;
        ind.b = ls.b;
      }
    }
  }
  return std::isfinite(ind.loss);
}

Evolution::Candidate Evolution::score_on_all_rows(Expression e, double front_loss) const {
  if (!racing()) e = fit_on_all_rows(std::move(e), ctx_, {.least_squares_steps = kRefitIterations});
  Candidate c;
  c.metrics = ctx_.score(e);
  const Loss loss = ctx_.options.loss;
  if (fits_minimax(loss) && !e.parameters.empty() &&
      loss_value(loss, c.metrics) <= kMinimaxMargin * front_loss) {
    Expression m = e;
    fit_minimax(&m, loss, fit_.pointers, fit_.target, fit_.weights, kRefitPasses, kRefitSteps);
    const ErrorMetrics mm = ctx_.score(m);
    if (loss_value(loss, mm) < loss_value(loss, c.metrics)) {
      e = std::move(m);
      c.metrics = mm;
    }
  }
  c.expr = std::move(e);
  return c;
}

void Evolution::consider(const Individual& ind, Island& island, const Snapshot& front,
                         std::vector<double>& values) const {
  const auto offer = [&](Expression e, double cost, double fit_loss) {
    const double at = best_at(front, cost);
    if (!(fit_loss <= kFrontMargin * at)) return;
    if (racing()) {
      fit_constants(e, race_, kRefitIterations);
      values.resize(race_.size());
      shaderfit::evaluate(e, race_.pointers, values, {.threads = 1});
      ctx_.node_evaluations.fetch_add(e.size() * race_.size(), std::memory_order_relaxed);
      if (!(loss_of(ctx_.options.loss, values, race_.target, race_.weights) <= kFrontMargin * at))
        return;
    }
    island.found.push_back(score_on_all_rows(std::move(e), at));
    island.found.back().generation = generations_;
  };
  offer(ind.expr, ind.raw_cost, ind.raw_loss);
  if (ind.scaled) offer(with_linear_scaling(ind.expr, ind.a, ind.b), ind.cost, ind.loss);
}

const Evolution::Individual& Evolution::tournament(Island& island, const std::vector<int>& rank,
                                                   const std::vector<double>& crowd) const {
  const std::size_t n = island.population.size();
  const std::size_t a = uniform_index(island.rng, n), b = uniform_index(island.rng, n);
  const bool a_better = rank[a] != rank[b] ? rank[a] < rank[b] : crowd[a] >= crowd[b];
  return island.population[a_better ? a : b];
}

void Evolution::init_island(Island& island, const std::vector<Expression>& seeds, std::size_t first,
                            std::size_t stride) {
  const std::size_t size = ctx_.options.population;
  std::vector<Expression> start;
  // This island's share of the seeds (every stride-th from first), each also with a fitted
  // linear scaling.
  for (std::size_t i = first; i < seeds.size(); i += stride) {
    start.push_back(seeds[i]);
    if (limits_.max_parameters >= 2) start.push_back(with_linear_scaling(seeds[i], 1.0, 0.0));
  }
  std::vector<double> values;
  std::set<std::uint64_t> seen;
  auto add = [&](Expression e) {
    e = normalize_parameters(std::move(e), limits_);
    if (e.empty()) return;
    Individual ind{std::move(e), 0, 0, 0};
    if (!evaluate(ind, island, values) || !seen.insert(ind.hash).second) return;
    island.population.push_back(std::move(ind));
  };
  for (Expression& e : start) {
    if (island.population.size() >= size) break;
    add(std::move(e));
  }
  for (std::size_t attempts = 0; island.population.size() < size && attempts < 20 * size;
       ++attempts)
    add(random_formula(island.rng, limits_, 1 + static_cast<int>(uniform_index(island.rng, 4))));
}

bool Evolution::generation(Island& island, const Snapshot& front) {
  const std::size_t size = ctx_.options.population;
  std::vector<Objectives> obj;
  for (const Individual& ind : island.population) obj.push_back({ind.loss, ind.cost});
  std::vector<int> rank;
  std::vector<double> crowd;
  rank_and_crowding(obj, &rank, &crowd);
  std::set<std::uint64_t> seen;
  for (const Individual& ind : island.population) seen.insert(ind.hash);

  // A quarter of the children are mutants of the island's most accurate individual: a local
  // search at the front's accurate end, where the large formulas are.
  std::size_t best = 0;
  for (std::size_t i = 1; i < island.population.size(); ++i)
    if (island.population[i].loss < island.population[best].loss) best = i;
  std::vector<Individual> offspring;
  std::vector<double> values;
  // Children are scored in batches: on the CPU one at a time, as soon as each is made; on the GPU
  // as many as are still missing, in one launch. The children made are the same either way.
  const std::size_t batch_limit = gpu_ != nullptr ? size : 1;
  std::vector<Individual> batch;
  const auto score_batch = [&] {
    evaluate_batch(batch, island, values);
    for (Individual& ind : batch) {
      if (!std::isfinite(ind.loss) || !seen.insert(ind.hash).second) continue;
      consider(ind, island, front, values);
      offspring.push_back(std::move(ind));
    }
    batch.clear();
  };
  bool complete = true;
  for (std::size_t attempts = 0; offspring.size() + batch.size() < size && attempts < 4 * size;
       ++attempts) {
    if ((attempts & 15) == 15 && out_of_time()) {
      complete = false;
      break;
    }
    const bool local = attempts % 4 == 3;
    const Individual& a = local ? island.population[best] : tournament(island, rank, crowd);
    Expression child =
        rewrites_ && local && bernoulli(island.rng, 0.25)
            ? normalize_parameters(random_rewrite(island.rng, a.expr, ctx_.options, rewrite_rows_),
                                   limits_)
        : !local && bernoulli(island.rng, 0.5)
            ? crossover(island.rng, a.expr, tournament(island, rank, crowd).expr, limits_)
            : mutate(island.rng, a.expr, limits_);
    if (child.empty()) continue;
    if (bernoulli(island.rng, 0.3) && !child.empty()) child = mutate(island.rng, child, limits_);
    if (child.empty()) continue;
    child = normalize_parameters(simplify(child), limits_);
    if (child.empty()) continue;
    const std::uint64_t hash = structural_hash(child);
    const auto same = [&](const Individual& b) { return b.hash == hash; };
    if (seen.count(hash) != 0 || std::any_of(batch.begin(), batch.end(), same)) continue;
    batch.push_back(Individual{std::move(child), 0, 0, hash});
    if (batch.size() >= batch_limit || offspring.size() + batch.size() >= size) score_batch();
  }
  score_batch();  // what a stop left in the batch (GPU only)
  for (Individual& ind : offspring) island.population.push_back(std::move(ind));
  obj.clear();
  for (const Individual& ind : island.population) obj.push_back({ind.loss, ind.cost});
  std::vector<Individual> next;
  for (std::size_t i : nsga2_select(obj, size)) next.push_back(std::move(island.population[i]));
  island.population = std::move(next);
  return complete;
}

void Evolution::polish_front() {
  // A polished member keeps the strategy that found it. In one process members are polished
  // while the time limit allows (a fit on all rows of a large formula, a shader reference of
  // dozens of constants, takes long): those left keep their constants.
  std::vector<Expression> todo;
  std::vector<SearchPhase> origins;
  for (const FrontMember& m : ctx_.front.members())
    if (!m.expression.parameters.empty()) {
      todo.push_back(m.expression);
      origins.push_back(m.origin);
    }
  std::vector<Candidate> done(todo.size());
  parallel_for(
      todo.size(), 1,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          // (Across ranks every rank polishes the whole front, which they share.)
          if (!ctx_.ranks.distributed() && ctx_.elapsed() >= ctx_.options.time_limit_s)
            continue;  // not polished
          Expression x = fit_on_all_rows(todo[i], ctx_,
                                         {.least_squares_steps = kPolishIterations,
                                          .minimax_passes = kPolishPasses,
                                          .minimax_steps = kRefitIterations});
          done[i].metrics = ctx_.score(x);
          done[i].expr = std::move(x);
        }
      },
      ctx_.threads);
  for (std::size_t i = 0; i < done.size(); ++i)
    if (!done[i].expr.empty())
      ctx_.offer(std::move(done[i].expr), loss_value(ctx_.options.loss, done[i].metrics),
                 origins[i]);
}

void Evolution::restart_island() {
  const std::size_t i = static_cast<std::size_t>(generations_ / kRestartEvery) % islands_.size();
  if (!owns(i)) return;
  Island& island = islands_[i];
  std::vector<Expression> seeds;
  const std::vector<FrontMember>& front = ctx_.front.members();
  for (std::size_t k = 0; k < (front.size() + 1) / 2; ++k) seeds.push_back(front[k].expression);
  island.population.clear();
  init_island(island, seeds, 0, 1);
}

void Evolution::migrate() {
  const std::size_t n = islands_.size();
  if (n < 2) return;
  std::vector<std::vector<Individual>> emigrants(n);
  for (std::size_t i : owned_) {
    std::vector<const Individual*> best;
    for (const Individual& ind : islands_[i].population) best.push_back(&ind);
    std::sort(best.begin(), best.end(), [](const Individual* a, const Individual* b) {
      return a->loss < b->loss || (a->loss == b->loss && a->hash < b->hash);
    });
    for (std::size_t k = 0; k < std::min(kMigrants, best.size()); ++k)
      emigrants[i].push_back(*best[k]);
  }
  if (ctx_.ranks.distributed()) {
    // Island i's emigrants go to island i + 1; those whose destination another rank owns travel
    // in one message per rank, sent without waiting, then each rank receives its islands'
    // immigrants from the ranks that own their sources.
    std::map<int, nlohmann::json> sends;
    std::set<int> from;
    for (std::size_t i : owned_) {
      const std::size_t to = (i + 1) % n;
      if (!owns(to)) {
        nlohmann::json people = nlohmann::json::array();
        for (const Individual& ind : emigrants[i])
          people.push_back(saved_individual_json(saved(ind)));
        nlohmann::json& message = sends[owner_[to]];
        if (message.is_null()) message = nlohmann::json::array();
        message.push_back({i, people});
      }
      const std::size_t source = (i + n - 1) % n;
      if (!owns(source)) from.insert(owner_[source]);
    }
    const std::vector<nlohmann::json> received = ctx_.ranks.exchange(
        {sends.begin(), sends.end()}, std::vector<int>(from.begin(), from.end()));
    for (const nlohmann::json& message : received)
      for (const nlohmann::json& batch : message) {
        const auto source = exact_integer_from<std::size_t>(batch.at(0), "island");
        if (source >= n) throw BadExactJson("migrants from an island out of range");
        for (const nlohmann::json& j : batch.at(1))
          emigrants[source].push_back(restored(saved_individual_from(j)));
      }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!owns((i + 1) % n)) continue;
    Island& to = islands_[(i + 1) % n];
    for (Individual& ind : emigrants[i]) to.population.push_back(std::move(ind));
    std::vector<Objectives> obj;
    for (const Individual& ind : to.population) obj.push_back({ind.loss, ind.cost});
    std::vector<Individual> next;
    for (std::size_t k : nsga2_select(obj, ctx_.options.population))
      next.push_back(std::move(to.population[k]));
    to.population = std::move(next);
  }
}

Evolution::Joint Evolution::gather_found(bool cut) {
  const SearchOptions& o = ctx_.options;
  nlohmann::json islands = nlohmann::json::array();
  for (std::size_t i : owned_) {
    nlohmann::json found = nlohmann::json::array();
    for (const Candidate& c : islands_[i].found)
      found.push_back({exact_expression_json(c.expr), metrics_json(c.metrics), c.generation});
    islands.push_back({i, islands_[i].evaluated, found, exact_number(islands_[i].busy_s)});
  }
  const nlohmann::json mine = {{"islands", islands},
                               {"interrupted", o.interrupt != nullptr && o.interrupt->load()},
                               {"cut", cut}};
  Joint joint;
  for (const nlohmann::json& r : ctx_.ranks.gather(mine)) {  // empty on the others
    for (const nlohmann::json& is : r.at("islands")) {
      const auto i = exact_integer_from<std::size_t>(is.at(0), "island");
      if (i >= islands_.size()) throw BadExactJson("an island out of range");
      Island& island = islands_[i];
      island.evaluated = exact_integer_from<std::uint64_t>(is.at(1), "evaluated");
      island.busy_s = exact_number_from(is.at(3));
      island.found.clear();
      for (const nlohmann::json& c : is.at(2))
        island.found.push_back({exact_expression_from(c.at(0)), metrics_from(c.at(1)),
                                exact_integer_from<std::uint64_t>(c.at(2), "generation")});
    }
    joint.interrupted = joint.interrupted || r.at("interrupted").get<bool>();
    joint.cut = joint.cut || r.at("cut").get<bool>();
  }
  if (ctx_.ranks.leader()) {
    const double now = ctx_.elapsed();
    joint.time_up = now >= o.time_limit_s;
    joint.polish = !polished_ && now >= kPolishAt * o.time_limit_s;
    joint.checkpoint = ctx_.checkpointer != nullptr && ctx_.checkpointer->due();
  }
  return joint;
}

Evolution::Joint Evolution::share_entrants(Joint joint, const std::vector<FrontMember>& entered,
                                           std::uint64_t* evaluated) {
  nlohmann::json mine;
  if (ctx_.ranks.leader()) {
    nlohmann::json members = nlohmann::json::array();
    for (const FrontMember& m : entered) members.push_back(front_member_json(m, FrontJson::Exact));
    mine = {{"entered", members},
            {"evaluated", *evaluated},
            {"votes",
             {joint.time_up, joint.interrupted, joint.polish, joint.checkpoint, joint.cut}},
            {"target", ctx_.stopped() && ctx_.stop_reason() == Termination::TargetReached},
            {"owners", balanced_owners()}};
  }
  const nlohmann::json all = ctx_.ranks.broadcast(mine, 0);
  std::vector<int> owners;
  for (const nlohmann::json& r : all.at("owners")) {
    owners.push_back(exact_integer_from<int>(r, "owner"));
    if (owners.back() < 0 || owners.back() >= ctx_.ranks.size())
      throw BadExactJson("an island's owner out of range");
  }
  if (owners.size() != islands_.size()) throw BadExactJson("owners of other islands");
  move_islands(owners);
  if (ctx_.ranks.leader()) return joint;
  for (const nlohmann::json& m : all.at("entered"))
    ctx_.front.offer(front_member_from_json(m, ctx_.problem.input_names, {}, "rank 0").member);
  *evaluated = exact_integer_from<std::uint64_t>(all.at("evaluated"), "evaluated");
  const nlohmann::json& v = all.at("votes");
  joint = {v.at(0).get<bool>(), v.at(1).get<bool>(), v.at(2).get<bool>(), v.at(3).get<bool>(),
           v.at(4).get<bool>()};
  if (all.at("target").get<bool>()) ctx_.stop(Termination::TargetReached);
  return joint;
}

std::vector<int> Evolution::balanced_owners() const {
  const auto ranks = static_cast<std::size_t>(ctx_.ranks.size());
  std::vector<double> load(ranks, 0.0);
  double total = 0;
  for (std::size_t i = 0; i < islands_.size(); ++i) {
    load[static_cast<std::size_t>(owner_[i])] += islands_[i].busy_s;
    total += islands_[i].busy_s;
  }
  const double mean = total / static_cast<double>(ranks);
  const double busiest = *std::max_element(load.begin(), load.end());
  if (!(total > 0) || busiest <= kRebalanceAbove * mean) return owner_;
  std::vector<std::size_t> order(islands_.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return islands_[a].busy_s > islands_[b].busy_s;
  });
  std::vector<int> owners(islands_.size());
  std::vector<std::size_t> count(ranks, 0);
  std::fill(load.begin(), load.end(), 0.0);
  for (const std::size_t i : order) {
    // The least loaded rank (every rank keeps at least one island: the emptiest first).
    std::size_t best = 0;
    for (std::size_t r = 1; r < ranks; ++r)
      if ((count[r] == 0) != (count[best] == 0) ? count[r] == 0 : load[r] < load[best]) best = r;
    owners[i] = static_cast<int>(best);
    load[best] += islands_[i].busy_s;
    ++count[best];
  }
  // Moving islands costs their states on the wire: only for a real gain.
  if (*std::max_element(load.begin(), load.end()) > kRebalanceGain * busiest) return owner_;
  return owners;
}

void Evolution::move_islands(const std::vector<int>& owners) {
  if (owners == owner_) return;
  const int me = ctx_.ranks.rank();
  std::map<int, nlohmann::json> sends;
  std::set<int> from;
  for (std::size_t i = 0; i < islands_.size(); ++i) {
    if (owners[i] == owner_[i]) continue;
    if (owner_[i] == me) {
      nlohmann::json& message = sends[owners[i]];
      if (message.is_null()) message = nlohmann::json::array();
      message.push_back({i, saved_island_json(saved_island(islands_[i]))});
      islands_[i].population.clear();
    } else if (owners[i] == me) {
      from.insert(owner_[i]);
    }
  }
  const std::vector<nlohmann::json> received = ctx_.ranks.exchange(
      {sends.begin(), sends.end()}, std::vector<int>(from.begin(), from.end()));
  for (const nlohmann::json& message : received)
    for (const nlohmann::json& moved : message) {
      const auto i = exact_integer_from<std::size_t>(moved.at(0), "island");
      if (i >= islands_.size() || owners[i] != me) throw BadExactJson("an island not this rank's");
      const SavedIsland saved = saved_island_from(moved.at(1));
      Island& island = islands_[i];
      rng_from_text(saved.rng, &island.rng);
      island.population.clear();
      for (const SavedIndividual& ind : saved.population) island.population.push_back(restored(ind));
    }
  owner_ = owners;
  owned_.clear();
  for (std::size_t i = 0; i < islands_.size(); ++i)
    if (owns(i)) owned_.push_back(i);
}

EvolutionState Evolution::gathered_state() {
  nlohmann::json mine = nlohmann::json::array();
  for (std::size_t i : owned_) {
    SavedIsland out = saved_island(islands_[i]);
    mine.push_back({i, saved_island_json(out)});
  }
  EvolutionState s;
  s.generations = generations_;
  s.polished = polished_;
  s.islands.resize(islands_.size());
  for (const nlohmann::json& r : ctx_.ranks.gather(mine))
    for (const nlohmann::json& is : r) {
      const auto i = exact_integer_from<std::size_t>(is.at(0), "island");
      if (i >= islands_.size()) throw BadExactJson("an island out of range");
      s.islands[i] = saved_island_from(is.at(1));
    }
  return s;
}

void Evolution::run(const std::vector<Expression>& seeds) {
  std::vector<Expression> all = seeds;
  for (const FrontMember& m : ctx_.front.members()) all.insert(all.begin(), m.expression);
  parallel_for(
      owned_.size(), 1,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k)
          init_island(islands_[owned_[k]], all, owned_[k], islands_.size());
      },
      ctx_.threads);
  evolve();
}

EvolutionState Evolution::state() const {
  EvolutionState s;
  s.generations = generations_;
  s.polished = polished_;
  for (const Island& is : islands_) s.islands.push_back(saved_island(is));
  return s;
}

void Evolution::resume(const EvolutionState& state) {
  if (state.islands.size() != islands_.size())
    throw Error("the checkpoint has " + std::to_string(state.islands.size()) +
                    " islands; this search has " + std::to_string(islands_.size()),
                {"SearchOptions::resume_path"});
  for (std::size_t i = 0; i < islands_.size(); ++i) {
    Island& is = islands_[i];
    rng_from_text(state.islands[i].rng, &is.rng);  // checked when the checkpoint was read
    is.population.clear();
    for (const SavedIndividual& s : state.islands[i].population)
      is.population.push_back(restored(s));
  }
  generations_ = state.generations;
  polished_ = state.polished;
  evolve();
}

void Evolution::evolve() {
  const auto threads = static_cast<std::size_t>(ctx_.threads);
  const bool distributed = ctx_.ranks.distributed();
  if (distributed) ctx_.joint_stop = true;
  const auto interval = static_cast<std::uint64_t>(ctx_.options.migration_interval);
  Checkpointer* checkpoints = ctx_.checkpointer;  // rank 0's only, across ranks
  const bool checkpointing = !ctx_.options.checkpoint_path.empty();
  bool cut = false;  // the last generation stopped early: its islands are not a boundary state
  while (true) {
    // One process synchronises its islands after every generation; ranks every interval.
    if (!distributed || generations_ % interval == 0) {
      Joint joint;
      if (distributed) joint = gather_found(cut);
      // Offered at this synchronisation point in the order (generation, island); across ranks by
      // rank 0, which then sends the others what entered.
      std::vector<Candidate*> found;
      std::uint64_t evaluated = 0;
      for (Island& is : islands_) {
        for (Candidate& c : is.found) found.push_back(&c);
        evaluated += is.evaluated;
        is.evaluated = 0;
      }
      std::stable_sort(found.begin(), found.end(), [](const Candidate* a, const Candidate* b) {
        return a->generation < b->generation;
      });
      std::vector<FrontMember> entered;
      if (ctx_.ranks.leader()) {
        for (Candidate* c : found) {
          Expression tidy = simplify(c->expr);
          ctx_.offer(formula_cost(tidy, ctx_.options) <= formula_cost(c->expr, ctx_.options)
                         ? tidy
                         : c->expr,
                     loss_value(ctx_.options.loss, c->metrics), SearchPhase::Evolution,
                     distributed ? &entered : nullptr);
        }
      }
      for (Island& is : islands_) is.found.clear();
      if (distributed) joint = share_entrants(joint, entered, &evaluated);
      for (Island& is : islands_) is.busy_s = 0;
      // The front's parts, for the mutations (the same on every rank: the front is).
      const std::vector<FrontMember> members = ctx_.front.members();
      std::vector<const Expression*> parts;
      for (const Expression& t : ctx_.terminals) parts.push_back(&t);
      for (const FrontMember& m : members) parts.push_back(&m.expression);
      limits_.blocks = subtree_blocks(parts);
      ctx_.candidates.fetch_add(evaluated, std::memory_order_relaxed);
      ctx_.maybe_progress(SearchPhase::Evolution);
      if (joint.interrupted) ctx_.stop(Termination::Interrupted);
      if (joint.time_up) ctx_.stop(Termination::TimeLimit);
      if (ctx_.should_stop()) break;
      if (!polished_ &&
          (distributed ? joint.polish : ctx_.elapsed() >= kPolishAt * ctx_.options.time_limit_s)) {
        polish_front();
        polished_ = true;
      }
      // A generation boundary: what a checkpoint records, and where a resumed run starts. Across
      // ranks the islands are gathered only when rank 0 is due to write.
      if (!distributed && checkpoints != nullptr) checkpoints->at_boundary(state());
      if (distributed && joint.checkpoint) {
        const EvolutionState s = gathered_state();
        if (checkpoints != nullptr) checkpoints->at_boundary(s);
      }
    }
    // The front an island ranks against: the synchronised one and, across ranks, its own finds
    // since (one process has none waiting). Not the other islands' finds: an island evolves the
    // same wherever it is (balanced_owners).
    Snapshot front;
    for (const FrontMember& m : ctx_.front.members()) front.emplace_back(m.cost, m.loss);
    std::vector<char> complete(owned_.size(), 1);
    parallel_for(
        owned_.size(), 1,
        [&](std::size_t b, std::size_t e) {
          for (std::size_t k = b; k < e; ++k) {
            Island& island = islands_[owned_[k]];
            Snapshot own = front;
            for (const Candidate& c : island.found)
              own.emplace_back(formula_cost(c.expr, ctx_.options),
                               loss_value(ctx_.options.loss, c.metrics));
            const auto start = std::chrono::steady_clock::now();
            complete[k] = generation(island, own) ? 1 : 0;
            island.busy_s +=
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          }
        },
        static_cast<int>(threads));
    cut = std::find(complete.begin(), complete.end(), 0) != complete.end();
    ++generations_;
    if (generations_ % interval == 0) migrate();
    if (generations_ % kRestartEvery == 0) restart_island();
  }
  if (!distributed && checkpoints != nullptr) checkpoints->at_end(cut, state());
  // Across ranks the state where the run stopped (a generation cut short by the clock or an
  // interrupt included: such stops are not reproducible anyway).
  if (distributed && checkpointing) {
    const EvolutionState s = gathered_state();
    if (checkpoints != nullptr) checkpoints->at_end(false, s);
  }
}

}  // namespace shaderfit::search_detail
