// The output of one tile of enumeration work, waiting to be merged (internal).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "search/enumeration/class_store.hpp"
#include "search/enumeration/enumerator.hpp"

namespace shaderfit::search_detail {

struct Enumerator::TileOutput {
  // Survivors: candidates new with respect to the committed classes and to each other.
  std::vector<ClassRecord> records;
  std::vector<ColumnStats> stats;
  std::vector<FusedBest> fused;  // the best fused sum m +- c of each product survivor
  // Per survivor: the committed class (of a higher cost) it is a cheaper recipe for, or -1.
  std::vector<std::int64_t> improves;
  // Screen columns: survivor i's at cols[i], in blocks of kBlockColumns columns from the
  // store's arena (the merge records those of new classes where they are); then room for the
  // next candidate's column. A spent arena leaves `full` set and the tile unfinished.
  static constexpr std::size_t kBlockColumns = 256;
  ClassStore* store = nullptr;
  float* block = nullptr;
  std::size_t used = kBlockColumns;  // columns used in `block`
  std::vector<const float*> cols;
  // Room the merge gave back: columns of survivors it dropped (a class made earlier in the batch
  // computes the same values), used again before new room. Kept across tiles: about half the
  // survivors are dropped, and their room would otherwise be fresh memory the kernel must zero.
  std::vector<float*> spare;
  float* next = nullptr;  // what next_column() returned
  bool next_is_spare = false;
  bool full = false;
  // Candidates computed but not yet checked (Enumerator::stage, then check_staged): the
  // committed table's slots of a group's keys are fetched together, not one miss at a time.
  static constexpr std::size_t kStaged = 8;
  struct Staged {
    ClassRecord record;
    ColumnStats stats;
  };
  std::array<Staged, kStaged> staged{};
  std::size_t staged_count = 0;
  std::vector<float> staging;  // kStaged columns
  bool screen_sums = false;    // a product survivor's fused sums m +- c are screened at once
  std::vector<std::uint64_t> table;  // local dedup: (fingerprint << 32) | (index + 1)
  std::vector<float> scratch;        // a fused sum's column (losses without a closed form)
  std::uint64_t evaluated = 0;
  std::size_t rows = 0;

  void clear(std::size_t screen_rows) {
    records.clear();
    stats.clear();
    fused.clear();
    improves.clear();
    cols.clear();
    full = false;
    rows = screen_rows;
    table.assign(table.empty() ? 4096 : table.size(), 0);
    scratch.resize(rows);
    staging.resize(kStaged * rows);
    staged_count = 0;
    evaluated = 0;
  }
  [[nodiscard]] const float* column(std::size_t i) const { return cols[i]; }
  // Room for the next candidate's column; keep() makes it survivor records.size()'s.
  // A tile's unused room stays with its output for the next tile (blocks are never returned).
  float* next_column() {
    next_is_spare = !spare.empty();
    if (next_is_spare) return next = spare.back();
    if (used == kBlockColumns) {
      float* b = store->allocate_block(kBlockColumns);
      if (b == nullptr) return nullptr;
      block = b;
      used = 0;
    }
    return next = block + used * rows;
  }
  void keep_column() {
    cols.push_back(next);
    if (next_is_spare)
      spare.pop_back();
    else
      ++used;
  }
};

}  // namespace shaderfit::search_detail
