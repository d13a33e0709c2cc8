// The output of one tile of enumeration work, waiting to be merged (internal).
#pragma once

#include <cstdint>
#include <vector>

#include "search/enumerator.hpp"

namespace shaderfit::search_detail {

struct Enumerator::TileOutput {
  // Survivors: candidates new with respect to the committed classes and to each other.
  std::vector<ClassRecord> records;
  std::vector<ColumnStats> stats;
  std::vector<FusedBest> fused;      // the best fused sum m +- c of each product survivor
  std::vector<float> columns;        // screen columns of the survivors, then room for one more
  std::vector<std::uint64_t> table;  // local dedup: (fingerprint << 32) | (index + 1)
  std::vector<float> scratch;        // a fused sum's column (losses without a closed form)
  std::uint64_t evaluated = 0;
  std::size_t rows = 0;

  void clear(std::size_t screen_rows) {
    records.clear();
    stats.clear();
    fused.clear();
    rows = screen_rows;
    if (columns.size() < 64 * rows) columns.resize(64 * rows);
    table.assign(table.empty() ? 4096 : table.size(), 0);
    scratch.resize(rows);
    evaluated = 0;
  }
  [[nodiscard]] const float* column(std::size_t i) const { return columns.data() + i * rows; }
  // Room for the column of survivor `records.size()`.
  float* next_column() {
    const std::size_t need = (records.size() + 1) * rows;
    if (columns.size() < need) columns.resize(2 * need);
    return columns.data() + records.size() * rows;
  }
};

}  // namespace shaderfit::search_detail
