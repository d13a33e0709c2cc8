// The enumeration across the ranks of a distributed search (docs/distributed.md, "How the work
// is split"): each rank computes its part of every batch with no exchange while it works; the
// ranks agree on counts and stops after every round, share a level once (as recipes) when a
// batch needs it whole, and join their fronts and best classes at rank 0 at the end.
#include <algorithm>
#include <cstring>
#include <string>
#include <unordered_map>

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
  if (*at + sizeof(T) > in.size())
    throw Error("a rank sent a short message", {"SearchOptions::communicator"});
  T v;
  std::memcpy(&v, in.data() + *at, sizeof(T));
  *at += sizeof(T);
  return v;
}

// What a rank reports after a round.
struct RoundReport {
  std::uint64_t candidates;  // counted by this rank so far (before the enumeration included)
  std::uint64_t classes;     // this rank's classes not yet shared
  std::int32_t stop;         // its Termination when it stopped the search, or -1
  std::uint8_t exhausted;    // its store is full or its share of the time is spent
  std::uint8_t complete;     // it merged its share of the batch's level
  std::uint8_t done;         // it merged all its tiles of the batch
};

// A class as one rank tells the others of it: its recipe (operands named by their place among
// the shared classes) and its key.
struct SharedClass {
  ClassRecord record;
  std::uint64_t hash;
  std::uint64_t found_at;
};

bool has_operand_a(const ClassRecord& r) {
  return r.kind != EKind::Var && r.kind != EKind::Literal;
}
bool has_operand_b(const ClassRecord& r) {
  return has_operand_a(r) && r.kind != EKind::Unary && r.kind != EKind::IPow;
}

}  // namespace

bool Enumerator::step_over_shared(const Step& s) const {
  for (std::size_t k = 0; k < level_ids_.size(); ++k) {
    if (shared_[k]) continue;
    for (const std::span<const std::uint32_t> list : {s.a, s.b})
      if (!list.empty() &&
          (list.data() == level_ids_[k].data() || list.data() == fusable_ids_[k].data()))
        return false;
  }
  return true;
}

bool Enumerator::run_batch_across_ranks(const std::vector<Step>& steps,
                                        const std::vector<Tile>& tiles, std::size_t complete,
                                        bool materialize) {
  const auto ranks = static_cast<std::size_t>(ctx_.ranks.size());
  const auto me = static_cast<std::size_t>(ctx_.ranks.rank());
  std::vector<bool> dealt(steps.size());
  for (std::size_t s = 0; s < steps.size(); ++s) dealt[s] = step_over_shared(steps[s]);
  // The tiles of steps over shared levels (the same on every rank, in the same order) are dealt
  // out; those over this rank's part of a level are all its own.
  std::vector<Tile> own;
  std::vector<std::uint32_t> positions;
  std::size_t own_complete = 0, next_dealt = 0;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    if (dealt[tiles[i].step] && next_dealt++ % ranks != me) continue;
    own.push_back(tiles[i]);
    positions.push_back(static_cast<std::uint32_t>(i));
    if (i < complete) ++own_complete;
  }
  ++batches_;
  const std::size_t per_round = kRoundTiles * static_cast<std::size_t>(ctx_.threads);
  std::size_t merged = 0;
  bool level_complete = false;
  // Rounds until every rank has merged all its tiles or the ranks agree to stop. A round that
  // ends early (its share of a count budget spent) leaves its tiles to the next.
  while (true) {
    const std::size_t end = std::min(own.size(), merged + per_round);
    if (merged < end && !enumeration_should_stop())
      merged += run_tiles(steps, std::span<const Tile>(own).subspan(merged, end - merged),
                          materialize,
                          std::span<const std::uint32_t>(positions).subspan(merged, end - merged));
    bool all_done = false;
    if (agree(merged >= own_complete, merged == own.size(), &level_complete, &all_done)) break;
    if (all_done) break;
  }
  finish_improvements(materialize);
  store_->commit();
  return level_complete;
}

bool Enumerator::agree(bool complete, bool done, bool* level_complete, bool* all_done) {
  RoundReport mine{};
  mine.candidates = prior_candidates_ + own_evaluated_.load();
  mine.classes = store_->size() - shared_ids_.size();
  mine.stop = ctx_.stopped() ? static_cast<std::int32_t>(ctx_.stop_reason()) : -1;
  mine.exhausted = exhausted_.load() ? 1 : 0;
  mine.complete = complete ? 1 : 0;
  mine.done = done ? 1 : 0;
  std::string bytes;
  put(bytes, mine);
  std::uint64_t candidates = 0, classes = shared_ids_.size();
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
  // Each rank's store holds the shared levels and its own part (options.max_classes each).
  joint_classes_ = classes;
  if (stop >= 0) ctx_.stop(static_cast<Termination>(stop));  // keeps a reason of its own
  if (exhausted) exhausted_.store(true);
  *level_complete = all_complete;
  *all_done = every_done;
  joint_end_ = stop >= 0 || exhausted;
  return joint_end_;
}

void Enumerator::share_levels_for(int level) {
  const int shared_below = costs_->leaf + 3;  // shared once complete (enumerator.hpp)
  for (int k = 0; k < level && !joint_end_; ++k)
    if (k <= level - 2 || k < shared_below) share_level(k);
}

void Enumerator::share_level(int level) {
  const auto L = static_cast<std::size_t>(level);
  if (shared_[L]) return;
  shared_index_.resize(store_->size(), kNotShared);
  // This rank's classes of the level with their keys, their operands named by their place among
  // the shared classes or (kOwnRef) by their place in this list (a fused sum m + c of the same
  // level as m).
  constexpr std::uint32_t kOwnRef = 0x80000000u;
  const std::vector<std::uint32_t> own = level_ids_[L];
  std::unordered_map<std::uint32_t, std::uint32_t> place;
  for (std::size_t i = 0; i < own.size(); ++i) place.emplace(own[i], static_cast<std::uint32_t>(i));
  const auto name = [&](std::uint32_t id) {
    if (shared_index_[id] != kNotShared) return shared_index_[id];
    const auto p = place.find(id);
    if (p == place.end())
      throw Error("internal: a class of cost " + std::to_string(level) +
                      " refers to a class not shared yet",
                  {"SearchOptions::communicator"});
    return kOwnRef | p->second;
  };
  std::string mine;
  put(mine, static_cast<std::uint64_t>(own.size()));
  put(mine, static_cast<std::uint64_t>(store_->size()));
  put(mine, static_cast<std::uint64_t>(store_->columns_left()));
  for (const std::uint32_t id : own) {
    ClassRecord r = store_->record(id);
    if (has_operand_a(r)) r.a = name(r.a);
    if (has_operand_b(r)) r.b = name(r.b);
    put(mine, SharedClass{r, store_->hash(id), id < found_at_.size() ? found_at_[id] : 0});
  }
  const std::vector<std::string> all = ctx_.ranks.all_gather_bytes(mine);
  struct Part {
    std::uint64_t count, size, left;
    std::size_t at;
  };
  std::vector<Part> parts;
  std::uint64_t total = 0;
  for (const std::string& msg : all) {
    Part p{};
    p.count = take<std::uint64_t>(msg, &p.at);
    p.size = take<std::uint64_t>(msg, &p.at);
    p.left = take<std::uint64_t>(msg, &p.at);
    if (msg.size() != p.at + p.count * sizeof(SharedClass))
      throw Error("a rank sent a malformed level", {"SearchOptions::communicator"});
    total += p.count;
    parts.push_back(p);
  }
  // Every rank must have room for the others' classes: when one has not, the enumeration ends.
  for (const Part& p : parts) {
    const std::uint64_t others = total - p.count;
    if (p.size + others > ctx_.options.max_classes || others > p.left) {
      exhausted_.store(true);
      joint_end_ = true;
      return;
    }
  }
  // In the order they were found (ranks' order among equals), as one process lists a level; a
  // class whose key (its column's hash and sign) a shared class has already is that class
  // (decided on the keys the ranks sent, so that every rank decides alike).
  struct Entry {
    std::uint64_t found_at;
    std::uint32_t rank, index;
  };
  std::vector<std::vector<SharedClass>> sent(parts.size());
  std::vector<Entry> order;
  for (std::size_t q = 0; q < parts.size(); ++q) {
    for (std::uint64_t i = 0; i < parts[q].count; ++i) {
      sent[q].push_back(take<SharedClass>(all[q], &parts[q].at));
      order.push_back({sent[q].back().found_at, static_cast<std::uint32_t>(q),
                       static_cast<std::uint32_t>(i)});
    }
  }
  std::sort(order.begin(), order.end(), [](const Entry& x, const Entry& y) {
    return x.found_at != y.found_at ? x.found_at < y.found_at
           : x.rank != y.rank       ? x.rank < y.rank
                                    : x.index < y.index;
  });
  const auto me = static_cast<std::size_t>(ctx_.ranks.rank());
  const std::size_t rows = screen_rows_;
  std::vector<float> column(rows);
  std::vector<std::uint32_t> list, fusable;
  std::vector<std::vector<std::uint32_t>> at_place(parts.size());
  for (std::size_t q = 0; q < parts.size(); ++q) at_place[q].assign(parts[q].count, kNotShared);
  // A class listed before the class of its level it is made from (a fused sum m + c of an m
  // improved later) waits for it.
  const auto ready = [&](const Entry& e) {
    const ClassRecord& r = sent[e.rank][e.index].record;
    for (const bool b : {false, true}) {
      if (b ? !has_operand_b(r) : !has_operand_a(r)) continue;
      const std::uint32_t n = b ? r.b : r.a;
      if ((n & kOwnRef) != 0 && ((n & ~kOwnRef) >= at_place[e.rank].size() ||
                                 at_place[e.rank][n & ~kOwnRef] == kNotShared))
        return false;
    }
    return true;
  };
  std::vector<Entry> waiting;
  for (std::size_t next = 0; next < order.size() || !waiting.empty();) {
    Entry e{};
    if (const auto w = std::find_if(waiting.begin(), waiting.end(), ready); w != waiting.end()) {
      e = *w;
      waiting.erase(w);
    } else if (next < order.size()) {
      e = order[next++];
      if (!ready(e)) {
        waiting.push_back(e);
        continue;
      }
    } else {
      throw Error("a rank sent a class of unknown operands", {"SearchOptions::communicator"});
    }
    const SharedClass& c = sent[e.rank][e.index];
    ClassRecord r = c.record;
    const bool negative = r.has(ClassRecord::kCanonicalNeg);
    if (const auto k = shared_keys_.find(c.hash);
        k != shared_keys_.end() && shared_negative_[k->second] == negative) {
      at_place[e.rank][e.index] = k->second;
      if (e.rank == me) shared_index_[own[e.index]] = k->second;
      continue;
    }
    std::uint32_t id = 0;
    if (e.rank == me) {
      id = own[e.index];
    } else {
      const auto local = [&](std::uint32_t n) {
        const std::uint32_t k =
            (n & kOwnRef) != 0
                ? ((n & ~kOwnRef) < at_place[e.rank].size() ? at_place[e.rank][n & ~kOwnRef]
                                                            : kNotShared)
                : n;
        if (k >= shared_ids_.size())
          throw Error("a rank sent a class of unknown operands", {"SearchOptions::communicator"});
        return shared_ids_[k];
      };
      if (has_operand_a(r)) r.a = local(r.a);
      if (has_operand_b(r)) r.b = local(r.b);
      compute_column(r.kind, r.op, r.k, store_->column(r.a),
                     has_operand_b(r) ? store_->column(r.b) : nullptr, r.has(ClassRecord::kNegA),
                     r.has(ClassRecord::kNegB), column.data(), rows);
      ColumnStats st;
      column_key(column.data(), rows, &st);
      id = store_->insert_copy(column.data(), st, r);
      shared_index_.resize(store_->size(), kNotShared);
    }
    const auto index = static_cast<std::uint32_t>(shared_ids_.size());
    at_place[e.rank][e.index] = index;
    shared_index_[id] = index;
    shared_ids_.push_back(id);
    shared_negative_.push_back(negative);
    shared_keys_.emplace(c.hash, index);
    list.push_back(id);
    if (r.has(ClassRecord::kFusable)) fusable.push_back(id);
  }
  level_ids_[L] = std::move(list);
  fusable_ids_[L] = std::move(fusable);
  shared_[L] = true;
  store_->commit();
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
  std::vector<std::size_t> sizes;
  for (const auto& lv : picked) sizes.push_back(lv.size());
  return pick_seeds(sizes, count, [&](std::size_t level, std::size_t k) -> std::optional<Expression> {
    if (picked[level][k].empty()) return std::nullopt;
    return picked[level][k];
  });
}

}  // namespace shaderfit::search_detail
