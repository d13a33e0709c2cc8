// The enumeration across ranks (docs/distributed.md, "How the work is split").
//
// A batch's tiles are cut into rounds; in each round rank r computes the tiles i with
// i mod R == r. A candidate that survives its tile (new to the tile and to the committed classes)
// is sent to the rank that owns its hash, which computes its column again from the recipe and
// deduplicates it against the batch's classes of that hash, in the tiles' order: the decisions
// one process's merge takes, since equivalent columns share a hash. Every rank then applies all
// owners' decisions in the tiles' order (class ids, level lists; rank 0 also the front), so
// every rank holds the classes one process would. A class's column lives on its owner until the
// next batch needs it as an operand; then every rank computes it from the recipe (replicate).
// Columns are bit for bit those of one process: the same kernels on the same operands.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <string>
#include <type_traits>

#include "core/cpu_clock.hpp"
#include "search/distributed.hpp"
#include "search/enum_tile.hpp"
#include "search/enumerator.hpp"
#include "shaderfit/core/parallel.hpp"

namespace shaderfit::search_detail {

namespace {

// A candidate new to its tile and to the committed classes, on its way to its owner.
struct Survivor {
  std::uint32_t tile, pos;
  std::int64_t improves;  // a committed class it is a cheaper recipe for, or -1
  ClassRecord record;
  ColumnStats stats;
  FusedBest fused;
};

enum class Verdict : std::uint8_t { New, ImprovesPending, ImprovesCommitted };

// An owner's decision that changes the classes (dropped survivors are not sent).
struct Decision {
  std::uint32_t tile, pos;
  std::uint32_t target;  // ImprovesPending: the owner's handle; ImprovesCommitted: the class
  Verdict verdict;
  ClassRecord record;
  ColumnStats stats;
  FusedBest fused;
};

// What each rank adds to a round's decisions.
struct RoundVote {
  std::uint64_t evaluated;  // candidates this rank computed in the round
  std::uint8_t stop;        // kInterrupted | kTimeUp | kEnough
};
constexpr std::uint8_t kInterrupted = 1, kTimeUp = 2, kEnough = 4;

// Records are sent as their bytes: every rank runs the same build.
template <typename T>
void append(std::string& bytes, const T& value) {
  static_assert(std::is_trivially_copyable_v<T>);
  bytes.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <typename T>
T read_at(const std::string& bytes, std::size_t at) {
  static_assert(std::is_trivially_copyable_v<T>);
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

// High bits: the tables index by the low ones.
int owner_of(std::uint64_t hash, int ranks) {
  return static_cast<int>((hash >> 40) % static_cast<std::uint64_t>(ranks));
}

bool unary_kind(EKind kind) { return kind == EKind::Unary || kind == EKind::IPow; }

}  // namespace

bool Enumerator::replicate_columns() {
  std::vector<std::uint32_t>& ids = missing_columns_;
  if (ids.empty()) return true;
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  float* block = store_->allocate_block(ids.size());
  if (block == nullptr) return false;
  // Operands are classes of earlier batches, which have their columns already.
  parallel_for(
      ids.size(), 256,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
          const ClassRecord& r = store_->record(ids[k]);
          float* dst = block + k * screen_rows_;
          compute_column(r.kind, r.op, r.k, store_->column(r.a),
                         unary_kind(r.kind) ? nullptr : store_->column(r.b),
                         r.has(ClassRecord::kNegA), r.has(ClassRecord::kNegB), dst, screen_rows_);
          store_->set_column(ids[k], dst);
        }
      },
      ctx_.threads);
  ids.clear();
  return true;
}

bool Enumerator::run_batch_ranks(const std::vector<Step>& steps, const std::vector<Tile>& tiles,
                                 std::size_t complete, bool materialize) {
  RankGroup& ranks = ctx_.ranks;
  ctx_.joint_stop = true;  // the clock and the interrupt flag are voted on (below)
  const int R = ranks.size(), me = ranks.rank();
  const bool leader = ranks.leader();
  const std::size_t n = tiles.size();
  if (!shard_) shard_ = std::make_unique<Shard>();
  Shard& shard = *shard_;
  shard.received.store = store_.get();
  shard.clear(R, screen_rows_);
  bool local_full = !replicate_columns();
  const auto threads = static_cast<std::size_t>(ctx_.threads);
  const std::size_t per_round = 32 * threads * static_cast<std::size_t>(R);
  const std::size_t verify_rows = store_->verify_rows();

  // The owner's pending classes: probe and insert, as ClassStore's pending table.
  auto find = [&](const float* column, const ColumnStats& st) -> std::int64_t {
    const std::size_t mask = shard.table.size() - 1;
    const std::uint64_t fp = st.hash >> 32;
    for (std::size_t i = st.hash & mask;; i = (i + 1) & mask) {
      const std::uint64_t slot = shard.table[i];
      if (slot == 0) return -1;
      if ((slot >> 32) != fp) continue;
      const std::size_t h = (slot & 0xffffffffu) - 1;
      const Shard::Entry& e = shard.entries[h];
      if (columns_equivalent(column, e.column, e.canonical_neg != st.canonical_neg, st.scale,
                             verify_rows))
        return static_cast<std::int64_t>(h);
    }
  };
  auto place = [&](std::size_t h) {
    const std::size_t mask = shard.table.size() - 1;
    const std::uint64_t hash = shard.entries[h].hash;
    std::size_t i = hash & mask;
    while (shard.table[i] != 0) i = (i + 1) & mask;
    shard.table[i] = ((hash >> 32) << 32) | (h + 1);
  };

  std::size_t applied = 0;
  bool ended = false;
  for (std::size_t start = 0; start < n && !ended; start += per_round) {
    const std::size_t end = std::min(n, start + per_round);
    // 1. This rank's tiles of the round.
    std::vector<std::size_t> mine;
    for (std::size_t i = start; i < end; ++i)
      if (static_cast<int>(i % static_cast<std::size_t>(R)) == me) mine.push_back(i);
    std::vector<std::unique_ptr<TileOutput>> outputs(mine.size());
    for (auto& out : outputs) {
      if (!output_pool_.empty()) {
        out = std::move(output_pool_.back());
        output_pool_.pop_back();
      } else {
        out = std::make_unique<TileOutput>();
        out->store = store_.get();
      }
      out->clear(screen_rows_);
    }
    // Room freed last round (columns sent away or dropped) goes to this round's tiles first.
    for (std::size_t k = 0; !shard.received.spare.empty(); k = (k + 1) % outputs.size()) {
      if (outputs.empty()) break;
      outputs[k]->spare.push_back(shard.received.spare.back());
      shard.received.spare.pop_back();
    }
    std::atomic<std::size_t> next{0};
    std::atomic<bool> full{local_full};
    parallel_for(
        threads, 1,
        [&](std::size_t, std::size_t) {
          for (std::size_t k; (k = next.fetch_add(1)) < mine.size();) {
            if (full.load(std::memory_order_relaxed)) return;
            TileOutput& out = *outputs[k];
            const Tile& t = tiles[mine[k]];
            process_tile(steps[t.step], t, out);
            if (out.full) full.store(true, std::memory_order_relaxed);
          }
        },
        static_cast<int>(threads));
    local_full = full.load();
    std::uint64_t evaluated = 0;
    for (const auto& out : outputs) evaluated += out->evaluated;
    ctx_.candidates.fetch_add(evaluated, std::memory_order_relaxed);
    ctx_.node_evaluations.fetch_add(evaluated * screen_rows_, std::memory_order_relaxed);

    // 2. Survivors to their owners; this rank keeps those it owns, with their columns.
    struct Owned {
      Survivor s;
      const float* column;
      TileOutput* room;  // where the column goes back when the survivor is dropped
    };
    std::vector<Owned> kept;  // in the tiles' order
    std::vector<std::string> sends(static_cast<std::size_t>(R));
    std::size_t survivors = 0;
    for (const auto& out : outputs) survivors += out->records.size();
    for (std::string& m : sends)
      m.reserve(survivors * sizeof(Survivor) / static_cast<std::size_t>(R) * 5 / 4);
    for (std::size_t k = 0; k < mine.size(); ++k) {
      TileOutput& out = *outputs[k];
      for (std::size_t i = 0; i < out.records.size(); ++i) {
        Survivor s{};
        s.tile = static_cast<std::uint32_t>(mine[k]);
        s.pos = static_cast<std::uint32_t>(i);
        s.improves = out.improves[i];
        s.record = out.records[i];
        s.stats = out.stats[i];
        s.fused = out.fused[i];
        const int o = owner_of(s.stats.hash, R);
        if (o == me) {
          kept.push_back({s, out.column(i), &out});
        } else {
          append(sends[static_cast<std::size_t>(o)], s);
          out.spare.push_back(const_cast<float*>(out.column(i)));
        }
      }
    }
    std::vector<std::pair<int, std::string>> messages;
    std::vector<int> from;
    for (int r = 0; r < R; ++r) {
      if (r == me) continue;
      messages.emplace_back(r, std::move(sends[static_cast<std::size_t>(r)]));
      from.push_back(r);
    }
    shard.received.clear(screen_rows_);
    for (auto& out : outputs) {  // the room of the survivors sent away serves those received
      shard.received.spare.insert(shard.received.spare.end(), out->spare.begin(), out->spare.end());
      out->spare.clear();
    }
    std::vector<std::vector<Owned>> sources;  // kept, then each rank's: each in the tiles' order
    sources.push_back(std::move(kept));
    for (const std::string& m : ranks.exchange_bytes(messages, from)) {
      std::vector<Owned>& got = sources.emplace_back();
      for (std::size_t at = 0; at + sizeof(Survivor) <= m.size(); at += sizeof(Survivor)) {
        const auto s = read_at<Survivor>(m, at);
        float* dst = shard.received.next_column();
        if (dst == nullptr) {
          local_full = true;
          break;
        }
        const ClassRecord& r = s.record;
        compute_column(r.kind, r.op, r.k, store_->column(r.a),
                       unary_kind(r.kind) ? nullptr : store_->column(r.b),
                       r.has(ClassRecord::kNegA), r.has(ClassRecord::kNegB), dst, screen_rows_);
        shard.received.keep_column();
        got.push_back({s, dst, &shard.received});
      }
    }
    std::vector<Owned> owned;
    {
      std::size_t total = 0;
      for (const auto& src : sources) total += src.size();
      owned.reserve(total);
      std::vector<std::size_t> pos(sources.size(), 0);
      while (owned.size() < total) {
        std::size_t best = sources.size();
        for (std::size_t k = 0; k < sources.size(); ++k) {
          if (pos[k] == sources[k].size()) continue;
          const Survivor& c = sources[k][pos[k]].s;
          if (best == sources.size()) {
            best = k;
            continue;
          }
          const Survivor& b = sources[best][pos[best]].s;
          if (c.tile < b.tile || (c.tile == b.tile && c.pos < b.pos)) best = k;
        }
        owned.push_back(sources[best][pos[best]++]);
      }
    }

    // 3. The owner's decisions, in the tiles' order (Enumerator::merge's, for this hash share).
    std::string decided;
    decided.reserve(sizeof(RoundVote) + owned.size() * sizeof(Decision));
    RoundVote vote{};
    vote.evaluated = evaluated;
    const bool interrupted = ctx_.options.interrupt != nullptr &&
                             ctx_.options.interrupt->load(std::memory_order_relaxed);
    if (interrupted) vote.stop |= kInterrupted;
    if (leader && ctx_.elapsed() >= ctx_.options.time_limit_s) vote.stop |= kTimeUp;
    const bool share_spent = [&] {  // this rank's own clock: the vote makes it joint
      const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - wall_start_;
      if (wall.count() < time_share_s_) return false;
      return (process_cpu_seconds() - cpu_start_s_) / ctx_.threads >= time_share_s_;
    }();
    if (local_full || share_spent || ctx_.stopped()) vote.stop |= kEnough;
    append(decided, vote);
    std::vector<const float*> decided_columns;
    // The shard's table and columns are larger than the cache: as in Enumerator::merge, the slot
    // is fetched 2k survivors ahead and the entry and column it names k ahead.
    constexpr std::size_t k_ahead = 8;
    auto prefetch_slot = [&](std::size_t i) {
      if (i < owned.size())
        __builtin_prefetch(&shard.table[owned[i].s.stats.hash & (shard.table.size() - 1)]);
    };
    auto prefetch_column = [&](std::size_t i) {
      if (i >= owned.size()) return;
      const std::uint64_t hash = owned[i].s.stats.hash;
      const std::uint64_t slot = shard.table[hash & (shard.table.size() - 1)];
      if (slot == 0 || (slot >> 32) != (hash >> 32)) return;
      const auto* c = reinterpret_cast<const char*>(shard.entries[(slot & 0xffffffffu) - 1].column);
      for (std::size_t b = 0; b < verify_rows * sizeof(float); b += 64) __builtin_prefetch(c + b);
    };
    for (std::size_t i = 0; i < 2 * k_ahead; ++i) prefetch_slot(i);
    for (std::size_t i = 0; i < k_ahead; ++i) prefetch_column(i);
    for (std::size_t i = 0; i < owned.size(); ++i) {
      prefetch_slot(i + 2 * k_ahead);
      prefetch_column(i + k_ahead);
      const Owned& o = owned[i];
      const Survivor& s = o.s;
      const int level = s.record.cost;
      Decision d{};
      d.tile = s.tile;
      d.pos = s.pos;
      d.record = s.record;
      d.stats = s.stats;
      d.fused = s.fused;
      bool keep = true;
      if (s.improves >= 0) {
        d.verdict = Verdict::ImprovesCommitted;
        d.target = static_cast<std::uint32_t>(s.improves);
        keep = shard.improved.insert(d.target).second;  // the first in the tiles' order wins
      } else if (const std::int64_t h = find(o.column, s.stats); h >= 0) {
        Shard::Entry& e = shard.entries[static_cast<std::size_t>(h)];
        keep = e.cost > level;
        if (keep) {  // a cheaper recipe for a class of this batch
          e.column = o.column;
          e.canonical_neg = s.stats.canonical_neg;
          e.cost = level;
          d.verdict = Verdict::ImprovesPending;
          d.target = static_cast<std::uint32_t>(h);
        }
      } else {
        d.verdict = Verdict::New;
        d.target = static_cast<std::uint32_t>(shard.entries.size());
        shard.entries.push_back({o.column, s.stats.hash, s.stats.canonical_neg, level});
        if (2 * shard.entries.size() > shard.table.size()) {  // at most half full
          shard.table.assign(2 * shard.table.size(), 0);
          for (std::size_t j = 0; j < shard.entries.size(); ++j) place(j);
        } else {
          place(shard.entries.size() - 1);
        }
      }
      if (!keep) {
        o.room->spare.push_back(const_cast<float*>(o.column));
        continue;
      }
      append(decided, d);
      decided_columns.push_back(o.column);
    }
    for (auto& out : outputs) output_pool_.push_back(std::move(out));

    // 4. Every owner's decisions, applied by every rank in the tiles' order.
    const std::vector<std::string> all = ranks.all_gather_bytes(std::move(decided));
    std::uint8_t stop = 0;
    std::vector<std::size_t> at(all.size(), sizeof(RoundVote));
    for (std::size_t r = 0; r < all.size(); ++r) {
      const auto v = read_at<RoundVote>(all[r], 0);
      stop |= v.stop;
      if (static_cast<int>(r) != me) ctx_.candidates.fetch_add(v.evaluated);
    }
    std::vector<std::size_t> own_index(all.size(), 0);
    while (true) {
      int src = -1;
      Decision best{};
      for (std::size_t r = 0; r < all.size(); ++r) {
        if (at[r] + sizeof(Decision) > all[r].size()) continue;
        const auto d = read_at<Decision>(all[r], at[r]);
        if (src < 0 || d.tile < best.tile || (d.tile == best.tile && d.pos < best.pos)) {
          src = static_cast<int>(r);
          best = d;
        }
      }
      if (src < 0) break;
      const auto S = static_cast<std::size_t>(src);
      at[S] += sizeof(Decision);
      const float* column = src == me ? decided_columns[own_index[S]++] : nullptr;
      const ClassRecord& rec = best.record;
      const ColumnStats& st = best.stats;
      const int level = rec.cost;
      const auto L = static_cast<std::size_t>(level);
      if (best.verdict == Verdict::ImprovesCommitted) {  // applied after the batch
        deferred_.push_back({best.target, column, st, rec, best.fused});
        continue;
      }
      if (best.verdict == Verdict::ImprovesPending) {
        const std::uint32_t id = shard.ids[S][best.target];
        const int old = store_->record(id).cost;
        store_->improve(id, column, st, rec);
        if (column == nullptr) missing_columns_.push_back(id);
        moved_.emplace_back(id, old);
        if (materialize || !leader) continue;
        consider_for_front(id, st, level);
        if (best.fused.leaf >= 0) consider_fused_for_front(id, best.fused, level);
        continue;
      }
      if (store_->full()) {
        exhausted_.store(true, std::memory_order_relaxed);
        ended = true;
        break;
      }
      const std::uint32_t id = store_->insert(column, st, rec);
      if (column == nullptr) missing_columns_.push_back(id);
      shard.ids[S].push_back(id);
      level_ids_[L].push_back(id);
      if (rec.has(ClassRecord::kFusable)) fusable_ids_[L].push_back(id);
      if (materialize) {
        elite_levels_[L].push_back(
            {std::min(st.loss_pos, st.loss_neg), id, st.loss_neg < st.loss_pos});
        continue;
      }
      if (!leader) continue;
      consider_for_front(id, st, level);
      if (best.fused.leaf >= 0) consider_fused_for_front(id, best.fused, level);
    }
    if (!ended) applied = end;
    if (leader) ctx_.maybe_progress(SearchPhase::Enumeration);
    // The joint decision: any rank's vote, or the candidate count, the same on every rank.
    if ((stop & kInterrupted) != 0) ctx_.stop(Termination::Interrupted);
    if ((stop & kTimeUp) != 0) ctx_.stop(Termination::TimeLimit);
    const auto& limit = ctx_.options.max_candidates;
    const bool counted_out = limit && ctx_.candidates.load() >= static_cast<std::uint64_t>(*limit);
    if (counted_out) ctx_.stop(Termination::CandidateLimit);
    if (stop != 0 || counted_out) ended = true;
    if (ended) exhausted_.store(true, std::memory_order_relaxed);
  }
  finish_improvements(materialize);
  store_->commit();
  return applied >= complete;
}

}  // namespace shaderfit::search_detail
