#include "search/class_store.hpp"

#include <sys/mman.h>

#include <algorithm>
#include <cstring>
#include <new>

namespace shaderfit::search_detail {

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;

// Anonymous memory: zero pages committed by the OS on first touch, in 2 MiB pages where the
// kernel allows it (far fewer page faults while the arena fills).
void* map_arena(std::size_t bytes) {
  void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
  madvise(p, bytes, MADV_HUGEPAGE);
#endif
  return p;
}

std::size_t table_size_for(std::size_t entries) {
  std::size_t n = 1024;
  while (n < 4 * entries) n *= 2;  // at most a quarter full: short probes
  return n;
}

}  // namespace

ClassRecord make_record(EKind kind, std::uint16_t cost) {
  ClassRecord r{};
  r.kind = kind;
  r.cost = cost;
  r.op = Op::Const;
  return r;
}

ClassStore::ClassStore(std::size_t screen_rows, std::size_t capacity)
    : rows_(screen_rows), capacity_(capacity) {
  const std::size_t column_bytes = capacity * rows_ * sizeof(float);
  const std::size_t record_bytes = (capacity * sizeof(ClassRecord) + 63) / 64 * 64;
  arena_bytes_ = (column_bytes + record_bytes + kHugePage - 1) / kHugePage * kHugePage;
  auto* base = static_cast<unsigned char*>(map_arena(arena_bytes_));
  columns_ = reinterpret_cast<float*>(base);
  records_ = reinterpret_cast<ClassRecord*>(base + column_bytes);
  committed_table_.assign(1024, 0);
  pending_table_.assign(1024, 0);
}

ClassStore::~ClassStore() { munmap(columns_, arena_bytes_); }

std::int64_t ClassStore::probe(const std::vector<std::uint64_t>& table, const float* column,
                               const ColumnStats& stats) const {
  const std::size_t mask = table.size() - 1;
  const std::uint64_t fingerprint = stats.hash >> 32;
  for (std::size_t i = stats.hash & mask;; i = (i + 1) & mask) {
    const std::uint64_t slot = table[i];
    if (slot == 0) return -1;
    if ((slot >> 32) != fingerprint) continue;
    const auto id = static_cast<std::uint32_t>((slot & 0xffffffffu) - 1);
    const ClassRecord& r = records_[id];
    const bool negate = r.has(ClassRecord::kCanonicalNeg) != stats.canonical_neg;
    if (columns_equivalent(column, this->column(id), negate, std::max(stats.scale, r.scale), rows_)) return id;
  }
}

std::int64_t ClassStore::find_committed(const float* column, const ColumnStats& stats) const {
  return probe(committed_table_, column, stats);
}

std::int64_t ClassStore::find_pending(const float* column, const ColumnStats& stats) const {
  return probe(pending_table_, column, stats);
}

void ClassStore::place(std::vector<std::uint64_t>& table, std::uint64_t hash, std::uint32_t id) {
  const std::size_t mask = table.size() - 1;
  std::size_t i = hash & mask;
  while (table[i] != 0) i = (i + 1) & mask;
  table[i] = ((hash >> 32) << 32) | (std::uint64_t{id} + 1);
}

std::uint32_t ClassStore::insert(const float* column, const ColumnStats& stats, ClassRecord record) {
  const std::uint32_t id = size_++;
  record.scale = stats.scale;
  if (stats.canonical_neg) record.flags |= ClassRecord::kCanonicalNeg;
  records_[id] = record;
  std::memcpy(columns_ + std::size_t{id} * rows_, column, rows_ * sizeof(float));
  hashes_.push_back(stats.hash);
  const std::uint32_t pending = size_ - committed_;
  if (pending_table_.size() < 2 * pending) {  // keep it at most half full
    std::vector<std::uint64_t> bigger(2 * pending_table_.size(), 0);
    for (std::uint32_t j = committed_; j + 1 < size_; ++j) place(bigger, hashes_[j], j);
    pending_table_.swap(bigger);
  }
  place(pending_table_, stats.hash, id);
  return id;
}

void ClassStore::commit() {
  if (committed_table_.size() < 2 * std::size_t{size_}) {  // over half full: rebuild bigger
    committed_table_.assign(table_size_for(size_), 0);
    for (std::uint32_t j = 0; j < size_; ++j) place(committed_table_, hashes_[j], j);
  } else {
    for (std::uint32_t j = committed_; j < size_; ++j) place(committed_table_, hashes_[j], j);
  }
  committed_ = size_;
  // Cleared, not shrunk: reallocating it every batch would fault its pages in again.
  std::fill(pending_table_.begin(), pending_table_.end(), 0);
}

}  // namespace shaderfit::search_detail
