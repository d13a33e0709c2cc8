// The distinct candidates of the enumeration ("classes": one per set of observationally
// equivalent formulas) with their screen columns, and hash tables over those columns (internal).
//
// Columns live in one big arena, handed out in blocks of many columns to the
// workers (any thread may allocate_block), which write their survivors' columns there; the
// serial merge then records where a new class's column is and never copies it. The hashes and
// both hash tables live in the same reservation, each sized for the capacity: a table grows in
// place, with no reallocation or copy, and its memory is touched once.
// Work happens in batches. During a batch, worker threads read the committed classes (records,
// columns, and the committed table, none of which change), while the one merging thread appends
// new classes and indexes them in a small pending table. commit() between batches folds the
// pending classes into the committed table. Capacity is fixed at construction, so the record
// arrays are never reallocated under a reader.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>

#include "search/enumeration/enum_kernels.hpp"

namespace shaderfit::search_detail {

struct ClassRecord {
  enum Flags : std::uint8_t {
    kNegA = 1,
    kNegB = 2,
    kFusable = 4,
    kLiteral = 8,
    kCanonicalNeg = 16
  };
  // Trivial on purpose: the record array is allocated without being touched.
  std::uint32_t a, b;  // operand classes
  std::uint16_t cost;  // enumeration (additive) cost
  EKind kind;
  Op op;          // Unary: the operator
  std::int8_t k;  // IPow: exponent; Var: input index; Literal: literal index
  std::uint8_t flags;
  float scale;  // root mean square of the screen column

  [[nodiscard]] bool has(Flags f) const { return (flags & f) != 0; }
};

ClassRecord make_record(EKind kind, std::uint16_t cost);

class ClassStore {
 public:
  // Equivalence is checked on the first `verify_rows` screen rows (the key, column_key, covers
  // every screen row).
  ClassStore(std::size_t screen_rows, std::size_t capacity, std::size_t verify_rows);
  ~ClassStore();
  ClassStore(const ClassStore&) = delete;
  ClassStore& operator=(const ClassStore&) = delete;

  [[nodiscard]] std::size_t rows() const { return rows_; }
  [[nodiscard]] std::uint32_t size() const { return size_; }
  [[nodiscard]] std::uint32_t committed() const { return committed_; }
  [[nodiscard]] bool full() const { return size_ >= capacity_; }
  [[nodiscard]] const float* column(std::uint32_t id) const { return columns_[id]; }
  [[nodiscard]] const ClassRecord& record(std::uint32_t id) const { return records_[id]; }
  // The hash of the class's column as it was inserted (equivalent columns share it).
  [[nodiscard]] std::uint64_t hash(std::uint32_t id) const { return hashes_[id]; }

  // A committed class equivalent to `column` (up to sign), or -1. Safe from any thread.
  [[nodiscard]] std::int64_t find_committed(const float* column, const ColumnStats& stats) const;
  // A class of the current batch equivalent to `column`, or -1. Merging thread only.
  [[nodiscard]] std::int64_t find_pending(const float* column, const ColumnStats& stats) const;
  // Asks the cache for the pending-table slot find_pending(stats) reads first: the table is
  // larger than the cache, so the merge prefetches a few survivors ahead. Merging thread only.
  void prefetch_pending(const ColumnStats& stats) const {
    __builtin_prefetch(&pending_table_[stats.hash & (pending_table_.size() - 1)]);
  }
  // Then, once that slot is in the cache, the column of the class it names when the fingerprint
  // matches (the column find_pending compares first).
  void prefetch_pending_column(const ColumnStats& stats) const {
    prefetch_column(pending_table_, stats);
  }
  // The same two for find_committed (workers stage a few candidates and check them together).
  void prefetch_committed(const ColumnStats& stats) const {
    __builtin_prefetch(&committed_table_[stats.hash & (committed_table_.size() - 1)]);
  }
  void prefetch_committed_column(const ColumnStats& stats) const {
    prefetch_column(committed_table_, stats);
  }
  // Appends a class (the caller checked it is new and !full()); returns its id. Merging thread.
  // `column` must be in a block from allocate_block (insert_copy copies it into one).
  std::uint32_t insert(const float* column, const ColumnStats& stats, ClassRecord record);
  std::uint32_t insert_copy(const float* column, const ColumnStats& stats, ClassRecord record);
  // Gives class `id` a cheaper recipe `record` whose column (`column`, in an arena block) is
  // equivalent to its own up to sign. A pending class: merging thread, during the batch; a
  // committed one: only between batches (workers read committed records and columns).
  void improve(std::uint32_t id, const float* column, const ColumnStats& stats, ClassRecord record);
  // Room for `columns` columns in the arena, or null when it is spent. Thread-safe.
  float* allocate_block(std::size_t columns);
  // Ends a batch: the pending classes become committed. No batch may be running.
  void commit();
  // Columns the arena still has room for.
  [[nodiscard]] std::size_t columns_left() const;

 private:
  [[nodiscard]] std::int64_t probe(std::span<const std::uint64_t> table, const float* column,
                                   const ColumnStats& stats) const;
  void prefetch_column(std::span<const std::uint64_t> table, const ColumnStats& stats) const;
  // Slot: (hash >> 33) << 33 | canonical sign << 32 | (id + 1); 0 is empty.
  void place(std::span<std::uint64_t> table, std::uint32_t id) const;
  // The first `slots` slots of a table's reservation, zeroed (slots: a power of two).
  static std::span<std::uint64_t> cleared(std::span<std::uint64_t> table, std::size_t slots);

  std::size_t rows_, verify_rows_, capacity_;
  const float** columns_ = nullptr;
  ClassRecord* records_ = nullptr;
  std::size_t arena_bytes_ = 0;
  void* arena_ = nullptr;
  float* column_arena_ = nullptr;
  std::size_t column_arena_columns_ = 0;
  std::atomic<std::size_t> column_arena_used_{0};
  // The tables in use: the first part of their reservations (slots as place() writes them).
  std::span<std::uint64_t> committed_table_, pending_table_;
  std::uint64_t* hashes_ = nullptr;  // per class, for rebuilding
  std::uint32_t size_ = 0, committed_ = 0;
};

}  // namespace shaderfit::search_detail
