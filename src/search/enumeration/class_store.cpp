#include "search/enumeration/class_store.hpp"

#include <sys/mman.h>

#include <algorithm>
#include <cstring>
#include <new>

namespace shaderfit::search_detail {

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;
// The first columns' memory, asked for in huge pages (below).
constexpr std::size_t kHugeColumnBytes = std::size_t{32} << 20;

// Anonymous memory: zero pages committed by the OS on first touch.
void* map_arena(std::size_t bytes) {
  void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  return p;
}

constexpr std::size_t kFirstSlots = 1024;

std::size_t table_size_for(std::size_t entries) {
  std::size_t n = kFirstSlots;
  while (n < 4 * entries) n *= 2;  // at most a quarter full: short probes
  return n;
}

// The pending table is kept at most half full.
std::size_t pending_reserve_for(std::size_t entries) {
  std::size_t n = kFirstSlots;
  while (n < 2 * entries) n *= 2;
  return n;
}

std::size_t lines(std::size_t bytes) { return (bytes + 63) / 64 * 64; }

}  // namespace

ClassRecord make_record(EKind kind, std::uint16_t cost) {
  ClassRecord r{};
  r.kind = kind;
  r.cost = cost;
  r.op = Op::Const;
  return r;
}

ClassStore::ClassStore(std::size_t screen_rows, std::size_t capacity, std::size_t verify_rows)
    : rows_(screen_rows), verify_rows_(std::min(verify_rows, screen_rows)), capacity_(capacity) {
  // One reservation: the column pointers, the records, the hashes, the two tables at their
  // largest, then the columns themselves (with room for the candidates that a merge drops after
  // their worker kept them). Only what is used is ever touched.
  const std::size_t pointer_bytes = lines(capacity * sizeof(const float*));
  const std::size_t record_bytes = lines(capacity * sizeof(ClassRecord));
  const std::size_t hash_bytes = lines(capacity * sizeof(std::uint64_t));
  const std::size_t committed_slots = table_size_for(capacity);
  const std::size_t pending_slots = pending_reserve_for(capacity);
  const std::size_t table_bytes = (committed_slots + pending_slots) * sizeof(std::uint64_t);
  column_arena_columns_ = capacity + capacity / 2 + 65536;
  const std::size_t column_bytes = column_arena_columns_ * rows_ * sizeof(float);
  const std::size_t head = pointer_bytes + record_bytes + hash_bytes + table_bytes;
  arena_bytes_ = (head + column_bytes + kHugePage - 1) / kHugePage * kHugePage;
  auto* base = static_cast<unsigned char*>(map_arena(arena_bytes_));
  arena_ = base;
  columns_ = reinterpret_cast<const float**>(base);
  records_ = reinterpret_cast<ClassRecord*>(base + pointer_bytes);
  hashes_ = reinterpret_cast<std::uint64_t*>(base + pointer_bytes + record_bytes);
  auto* tables = hashes_ + hash_bytes / sizeof(std::uint64_t);
  committed_table_ = cleared({tables, committed_slots}, kFirstSlots);
  pending_table_ = cleared({tables + committed_slots, pending_slots}, kFirstSlots);
  column_arena_ = reinterpret_cast<float*>(base + head);
  // The first 32 MiB of columns in huge pages: a short search (the seed task reaches its target
  // within them) faults 512 times less (0.8x the time to target). Not the rest: where the kernel
  // compacts memory for a huge page (defrag "madvise", Debian's default), such a fault costs
  // more than the small pages it saves, and a long enumeration on the 2-core virtual machine
  // took twice as long, most of it in the kernel.
#ifdef MADV_HUGEPAGE
  const std::size_t from = (head + kHugePage - 1) / kHugePage * kHugePage;
  madvise(base + from, std::min(kHugeColumnBytes, arena_bytes_ - from), MADV_HUGEPAGE);
#endif
}

std::span<std::uint64_t> ClassStore::cleared(std::span<std::uint64_t> table, std::size_t slots) {
  std::span<std::uint64_t> used = table.first(std::min(slots, table.size()));
  std::fill(used.begin(), used.end(), 0);
  return used;
}

ClassStore::~ClassStore() { munmap(arena_, arena_bytes_); }

std::int64_t ClassStore::probe(std::span<const std::uint64_t> table, const float* column,
                               const ColumnStats& stats) const {
  // Everything the check needs is in the slot and the two columns: no record is read.
  const std::size_t mask = table.size() - 1;
  const std::uint64_t fingerprint = stats.hash >> 33;
  for (std::size_t i = stats.hash & mask;; i = (i + 1) & mask) {
    const std::uint64_t slot = table[i];
    if (slot == 0) return -1;
    if ((slot >> 33) != fingerprint) continue;
    const auto id = static_cast<std::uint32_t>((slot & 0xffffffffu) - 1);
    const bool negate = (((slot >> 32) & 1u) != 0) != stats.canonical_neg;
    if (columns_equivalent(column, this->column(id), negate, stats.scale, verify_rows_)) return id;
  }
}

void ClassStore::prefetch_column(std::span<const std::uint64_t> table,
                                 const ColumnStats& stats) const {
  const std::uint64_t slot = table[stats.hash & (table.size() - 1)];
  if (slot == 0 || (slot >> 33) != (stats.hash >> 33)) return;
  const auto* column = reinterpret_cast<const char*>(columns_[(slot & 0xffffffffu) - 1]);
  for (std::size_t b = 0; b < verify_rows_ * sizeof(float); b += 64) __builtin_prefetch(column + b);
}

std::int64_t ClassStore::find_committed(const float* column, const ColumnStats& stats) const {
  return probe(committed_table_, column, stats);
}

std::int64_t ClassStore::find_pending(const float* column, const ColumnStats& stats) const {
  return probe(pending_table_, column, stats);
}

void ClassStore::place(std::span<std::uint64_t> table, std::uint32_t id) const {
  const std::uint64_t hash = hashes_[id];
  const std::uint64_t neg = records_[id].has(ClassRecord::kCanonicalNeg) ? 1 : 0;
  const std::size_t mask = table.size() - 1;
  std::size_t i = hash & mask;
  while (table[i] != 0) i = (i + 1) & mask;
  table[i] = ((hash >> 33) << 33) | (neg << 32) | (std::uint64_t{id} + 1);
}

std::uint32_t ClassStore::insert(const float* column, const ColumnStats& stats,
                                 ClassRecord record) {
  const std::uint32_t id = size_++;
  record.scale = stats.scale;
  if (stats.canonical_neg) record.flags |= ClassRecord::kCanonicalNeg;
  records_[id] = record;
  columns_[id] = column;
  hashes_[id] = stats.hash;
  const std::uint32_t pending = size_ - committed_;
  if (pending_table_.size() < 2 * pending) {  // keep it at most half full: grow in place
    pending_table_ = cleared({pending_table_.data(), pending_reserve_for(capacity_)},
                             2 * pending_table_.size());
    for (std::uint32_t j = committed_; j + 1 < size_; ++j) place(pending_table_, j);
  }
  place(pending_table_, id);
  return id;
}

void ClassStore::improve(std::uint32_t id, const float* column, const ColumnStats& stats,
                         ClassRecord record) {
  record.scale = stats.scale;
  record.flags &= static_cast<std::uint8_t>(~ClassRecord::kCanonicalNeg);
  if (stats.canonical_neg) record.flags |= ClassRecord::kCanonicalNeg;
  const bool sign_changed =
      records_[id].has(ClassRecord::kCanonicalNeg) != record.has(ClassRecord::kCanonicalNeg);
  records_[id] = record;
  columns_[id] = column;
  if (!sign_changed) return;
  // The slot records the stored column's canonical sign: flip it.
  const std::span<std::uint64_t> table = id >= committed_ ? pending_table_ : committed_table_;
  const std::size_t mask = table.size() - 1;
  for (std::size_t i = hashes_[id] & mask;; i = (i + 1) & mask) {
    if ((table[i] & 0xffffffffu) == std::uint64_t{id} + 1) {
      table[i] ^= std::uint64_t{1} << 32;
      return;
    }
  }
}

std::uint32_t ClassStore::insert_copy(const float* column, const ColumnStats& stats,
                                      ClassRecord record) {
  float* kept = allocate_block(1);
  if (kept == nullptr) throw std::bad_alloc();
  std::copy(column, column + rows_, kept);
  return insert(kept, stats, record);
}

float* ClassStore::allocate_block(std::size_t columns) {
  const std::size_t at = column_arena_used_.fetch_add(columns, std::memory_order_relaxed);
  if (at + columns > column_arena_columns_) return nullptr;
  return column_arena_ + at * rows_;
}

void ClassStore::commit() {
  if (committed_table_.size() < 2 * std::size_t{size_}) {  // over half full: rebuild bigger
    committed_table_ = cleared({committed_table_.data(), table_size_for(capacity_)},
                               table_size_for(size_));
    for (std::uint32_t j = 0; j < size_; ++j) place(committed_table_, j);
  } else {
    for (std::uint32_t j = committed_; j < size_; ++j) place(committed_table_, j);
  }
  committed_ = size_;
  // Cleared, not shrunk: reallocating it every batch would fault its pages in again.
  std::fill(pending_table_.begin(), pending_table_.end(), 0);
}

std::size_t ClassStore::columns_left() const {
  const std::size_t used = column_arena_used_.load(std::memory_order_relaxed);
  return used >= column_arena_columns_ ? 0 : column_arena_columns_ - used;
}

}  // namespace shaderfit::search_detail
