// The output of one tile of enumeration work, waiting to be merged (internal).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "search/class_store.hpp"
#include "search/enumerator.hpp"

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
  bool full = false;
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
    evaluated = 0;
  }
  [[nodiscard]] const float* column(std::size_t i) const { return cols[i]; }
  // Room for the next candidate's column; keep() makes it survivor records.size()'s.
  // A tile's unused room stays with its output for the next tile (blocks are never returned).
  float* next_column() {
    if (used == kBlockColumns) {
      float* b = store->allocate_block(kBlockColumns);
      if (b == nullptr) return nullptr;
      block = b;
      used = 0;
    }
    return block + used * rows;
  }
  void keep_column() {
    cols.push_back(block + used * rows);
    ++used;
  }
};

}  // namespace shaderfit::search_detail
