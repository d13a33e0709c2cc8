// The enumeration across the ranks of a distributed search (docs/distributed.md, "How the work
// is split"): each rank computes its share of every batch's tiles with no exchange while it
// works; the ranks agree on counts and stops after every round, hold the same classes after
// every batch they all finished (the new classes replicated once per batch, as recipes), and
// join their fronts and best classes at rank 0 at the end.
#include <algorithm>
#include <cstring>
#include <string>

#include "search/enumeration/enum_costs.hpp"
#include "search/enumeration/enum_tile.hpp"
#include "search/enumeration/enumerator.hpp"
#include "search/exact_json.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/search/front_member.hpp"

namespace shaderfit::search_detail {

namespace {

// Tiles per thread in a round: a round is some tens of milliseconds of work, so a stop (a
// target reached, a count spent) on one rank reaches the others soon, and the agreement after
// it (a few bytes per rank) costs nothing beside it.
constexpr std::size_t kRoundTiles = 64;

template <typename T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <typename T>
T take(const std::string& in, std::size_t* at) {
  if (*at + sizeof(T) > in.size()) throw Error("a rank sent a short message", {"communicator"});
  T v;
  std::memcpy(&v, in.data() + *at, sizeof(T));
  *at += sizeof(T);
  return v;
}

// What a rank reports after a round.
struct RoundReport {
  std::uint64_t candidates;  // counted by this rank so far (before the enumeration included)
  std::uint64_t classes;     // this rank's classes not yet replicated
  std::int32_t stop;         // its Termination when it stopped the search, or -1
  std::uint8_t exhausted;    // its store is full or its share of the time is spent
  std::uint8_t complete;     // it merged its share of the batch's level
  std::uint8_t done;         // it merged all its tiles of the batch
};

}  // namespace

bool Enumerator::run_batch_across_ranks(const std::vector<Step>& steps,
                                        const std::vector<Tile>& tiles, std::size_t complete,
                                        bool materialize) {
  const auto ranks = static_cast<std::size_t>(ctx_.ranks.size());
  const auto me = static_cast<std::size_t>(ctx_.ranks.rank());
  // Tile i is rank i mod R's: every rank gets the same mix of steps and of the batch's order.
  std::vector<Tile> own;
  std::size_t own_complete = 0;
  for (std::size_t i = me; i < tiles.size(); i += ranks) {
    own.push_back(tiles[i]);
    if (i < complete) ++own_complete;
  }
  const std::size_t per_round = kRoundTiles * static_cast<std::size_t>(ctx_.threads);
  std::size_t merged = 0;
  bool level_complete = false;
  // Rounds until every rank has merged all its tiles or the ranks agree to stop. A round that
  // ends early (a count budget's share of it spent) leaves its tiles to the next.
  while (true) {
    const std::size_t end = std::min(own.size(), merged + per_round);
    if (merged < end && !enumeration_should_stop())
      merged += run_tiles(steps, std::span<const Tile>(own).subspan(merged, end - merged),
                          materialize);
    bool all_done = false;
    if (agree(merged >= own_complete, merged == own.size(), &level_complete, &all_done)) break;
    if (all_done) break;
  }
  if (!joint_end_) {
    replicate(materialize);
    joint_classes_ = store_->size();
  }
  finish_improvements(materialize);
  store_->commit();
  return level_complete;
}
bool Enumerator::agree(bool complete, bool done, bool* level_complete, bool* all_done) {
  RoundReport mine{};
  mine.candidates = prior_candidates_ + own_evaluated_.load();
  mine.classes = store_->size() - store_->committed();
  mine.stop = ctx_.stopped() ? static_cast<std::int32_t>(ctx_.stop_reason()) : -1;
  mine.exhausted = exhausted_.load() ? 1 : 0;
  mine.complete = complete ? 1 : 0;
  mine.done = done ? 1 : 0;
  std::string bytes;
  put(bytes, mine);
  std::uint64_t candidates = 0, classes = store_->committed();
  bool exhausted = false, all_complete = true, every_done = true;
  std::int32_t stop = -1;
  for (const std::string& b : ctx_.ranks.all_gather_bytes(bytes)) {
    std::size_t at = 0;
    const auto r = take<RoundReport>(b, &at);
    candidates += r.candidates;
    classes += r.classes;
    if (stop < 0) stop = r.stop;  // the lowest rank's reason
    exhausted = exhausted || r.exhausted != 0;
    all_complete = all_complete && r.complete != 0;
    every_done = every_done && r.done != 0;
  }
  ctx_.candidates.store(candidates);
  round_base_ = candidates;
  // The ranks' classes together fill the store (each holds only its own until they are shared).
  if (classes >= ctx_.options.max_classes) exhausted = true;
  joint_classes_ = std::min<std::uint64_t>(classes, ctx_.options.max_classes);
  if (stop >= 0) ctx_.stop(static_cast<Termination>(stop));  // keeps a reason of its own
  if (exhausted) exhausted_.store(true);
  *level_complete = all_complete;
  *all_done = every_done;
  joint_end_ = stop >= 0 || exhausted;
  return joint_end_;
}

void Enumerator::replicate(bool materialize) {
  const std::uint32_t first = store_->committed();
  const std::uint32_t own_count = store_->size() - first;
  // This rank's new classes (their final recipes) and its cheaper recipes for committed ones.
  std::string mine;
  put(mine, own_count);
  for (std::uint32_t id = first; id < store_->size(); ++id) put(mine, store_->record(id));
  put(mine, static_cast<std::uint32_t>(deferred_.size()));
  for (const Improvement& d : deferred_) {
    put(mine, d.id);
    put(mine, d.record);
  }
  const std::vector<std::string> all = ctx_.ranks.all_gather_bytes(mine);

  // Forget the new classes, to insert every rank's in rank order.
  std::vector<const float*> own_columns(own_count);
  for (std::uint32_t i = 0; i < own_count; ++i) own_columns[i] = store_->column(first + i);
  store_->drop_pending();
  const auto pending = [first](std::uint32_t id) { return id >= first; };
  for (auto& ids : level_ids_) std::erase_if(ids, pending);
  for (auto& ids : fusable_ids_) std::erase_if(ids, pending);
  std::vector<Improvement> own_deferred = std::move(deferred_);
  deferred_.clear();
  moved_.clear();
  improved_.clear();

  const auto me = static_cast<std::size_t>(ctx_.ranks.rank());
  const std::size_t rows = screen_rows_;
  std::vector<float> scratch(rows);
  const auto compute = [&](const ClassRecord& r, float* out) {
    const bool unary = r.kind == EKind::Unary || r.kind == EKind::IPow;
    compute_column(r.kind, r.op, r.k, store_->column(r.a), unary ? nullptr : store_->column(r.b),
                   r.has(ClassRecord::kNegA), r.has(ClassRecord::kNegB), out, rows);
  };
  // Where each of this rank's classes went (its elite entries name them), and whether that
  // class holds the negated column.
  std::vector<std::int64_t> own_new(own_count, -1);
  std::vector<bool> own_flipped(own_count, false);
  for (std::size_t q = 0; q < all.size(); ++q) {
    const std::string& msg = all[q];
    std::size_t at = 0;
    const auto count = take<std::uint32_t>(msg, &at);
    for (std::uint32_t i = 0; i < count; ++i) {
      const auto rec = take<ClassRecord>(msg, &at);
      if (rec.a >= first || (rec.kind != EKind::Unary && rec.kind != EKind::IPow &&
                             rec.kind != EKind::Var && rec.kind != EKind::Literal &&
                             rec.b >= first))
        throw Error("a rank sent a class of uncommitted operands", {"communicator"});
      const float* column = nullptr;
      if (q == me) {
        column = own_columns[i];
      } else {
        compute(rec, scratch.data());
        column = scratch.data();
      }
      ColumnStats st;
      column_key(column, &st);
      if (const std::int64_t p = store_->find_pending(column, st); p >= 0) {
        const auto id = static_cast<std::uint32_t>(p);
        const int old = store_->record(id).cost;
        if (old > rec.cost) {  // a cheaper recipe from a later rank
          const float* kept = column;
          if (q != me) {
            float* room = store_->allocate_block(1);
            if (room == nullptr) {
              exhausted_.store(true);
              continue;
            }
            std::copy(column, column + rows, room);
            kept = room;
          }
          store_->improve(id, kept, st, rec);
          moved_.emplace_back(id, old);
        }
        if (q == me) {
          own_new[i] = id;
          own_flipped[i] = st.canonical_neg != store_->record(id).has(ClassRecord::kCanonicalNeg);
        }
        continue;
      }
      if (store_->full()) {  // every rank fills its store at the same class
        exhausted_.store(true);
        joint_end_ = true;
        continue;
      }
      const std::uint32_t id =
          q == me ? store_->insert(column, st, rec) : store_->insert_copy(column, st, rec);
      level_ids_[rec.cost].push_back(id);
      if (rec.has(ClassRecord::kFusable)) fusable_ids_[rec.cost].push_back(id);
      if (q == me) own_new[i] = id;
    }
    const auto improvements = take<std::uint32_t>(msg, &at);
    for (std::uint32_t j = 0; j < improvements; ++j) {
      const auto id = take<std::uint32_t>(msg, &at);
      const auto rec = take<ClassRecord>(msg, &at);
      if (id >= first) throw Error("a rank improved an uncommitted class", {"communicator"});
      if (store_->record(id).cost <= rec.cost || !improved_.insert(id).second) continue;
      if (q == me) {
        deferred_.push_back(own_deferred[j]);
        continue;
      }
      float* room = store_->allocate_block(1);
      if (room == nullptr) {
        exhausted_.store(true);
        continue;
      }
      compute(rec, room);
      ColumnStats st;
      column_key(room, &st);
      deferred_.push_back({id, room, st, rec, FusedBest{}, false});
    }
  }
  // This rank's best classes, under their new ids.
  for (auto& level : elite_levels_) {
    std::erase_if(level, [&](Elite& e) {
      if (e.id < first) return false;
      const std::int64_t to = own_new[e.id - first];
      if (to < 0) return true;
      e.negate = e.negate != own_flipped[e.id - first];
      e.id = static_cast<std::uint32_t>(to);
      return false;
    });
  }
  (void)materialize;
}

std::vector<Expression> Enumerator::gather_at_leader(std::size_t count) {
  using nlohmann::json;
  json front = json::array(), elite = json::array();
  if (!ctx_.ranks.leader())
    for (const FrontMember& m : ctx_.front.members())
      front.push_back(front_member_json(m, FrontJson::Exact));
  // Each level's best classes, best first, as formulas: ids mean nothing on another rank.
  for (std::size_t level = 0; level < elite_levels_.size(); ++level) {
    std::vector<Elite> lv = elite_levels_[level];
    std::sort(lv.begin(), lv.end());
    json entries = json::array();
    for (std::size_t k = 0; k < std::min(lv.size(), count); ++k) {
      const bool literal = store_->record(lv[k].id).kind == EKind::Literal;
      entries.push_back(
          {exact_number(lv[k].loss),
           literal ? json()
                   : exact_expression_json(build_class_expression(
                         *store_, lv[k].id, lv[k].negate, ctx_.problem.input_names,
                         ctx_.options.literals, ctx_.terminals))});
    }
    elite.push_back(std::move(entries));
  }
  const std::vector<json> all = ctx_.ranks.gather({{"front", front}, {"elite", elite}});
  if (!ctx_.ranks.leader()) return {};
  // Members that two ranks both found are one member again here (the front keeps the first).
  for (std::size_t q = 1; q < all.size(); ++q)
    for (const json& m : all[q].at("front"))
      ctx_.front.offer(
          front_member_from_json(m, ctx_.problem.input_names, {}, "rank " + std::to_string(q))
              .member);
  // Per level, every rank's entries by screen loss (rank order among equals), one of each
  // formula; then as seeds() picks them: the best of each level, then the second ...
  std::vector<std::vector<std::pair<double, const json*>>> levels(elite_levels_.size());
  for (const json& r : all) {
    const json& lv = r.at("elite");
    for (std::size_t level = 0; level < std::min(lv.size(), levels.size()); ++level)
      for (const json& e : lv[level])
        levels[level].emplace_back(exact_number_from(e.at(0)), &e.at(1));
  }
  std::vector<Expression> out;
  std::vector<std::vector<Expression>> picked;
  for (auto& lv : levels) {
    std::stable_sort(lv.begin(), lv.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<Expression> distinct;
    std::vector<std::string> seen;
    for (const auto& [loss, e] : lv) {
      if (e->is_null()) {
        distinct.emplace_back();  // a literal: takes its place, never a seed
        continue;
      }
      Expression x = exact_expression_from(*e);
      std::string text = to_infix(x, {.substitute_parameters = true});
      if (std::find(seen.begin(), seen.end(), text) != seen.end()) continue;
      seen.push_back(std::move(text));
      distinct.push_back(std::move(x));
    }
    if (!distinct.empty()) picked.push_back(std::move(distinct));
  }
  for (std::size_t k = 0; out.size() < count; ++k) {
    bool any = false;
    for (const auto& lv : picked) {
      if (k >= lv.size() || out.size() >= count) continue;
      any = true;
      if (!lv[k].empty()) out.push_back(lv[k]);
    }
    if (!any) break;
  }
  return out;
}

}  // namespace shaderfit::search_detail
