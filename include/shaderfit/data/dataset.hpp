// A data set: a table of named columns of equal length, each numeric (the variables and targets a
// formula is fitted to) or text (group labels, such as the material).
//
//   Dataset d = read_csv("fresnel.csv");          // shaderfit/data/csv.hpp
//   const std::vector<double>& r = d.numeric("R").values;  // throws if missing or not numeric
//   if (const Column* m = d.find("material")) { ... m->labels ... }
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/core.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit {

// One column. A text column has its cells in `labels` and nothing in `values`; a numeric column the
// reverse. (A column with no rows counts as numeric.)
struct Column {
  std::string name;
  std::vector<double> values;       // numeric columns
  std::vector<std::string> labels;  // text columns
  // For a text column read from a file: where its first cell that is not a number is, so that
  // asking for it as numbers can point there. Empty for columns built in code.
  SourceLocation first_non_number;

  [[nodiscard]] bool numeric() const { return labels.empty(); }
  [[nodiscard]] std::size_t size() const { return numeric() ? values.size() : labels.size(); }
};

struct Dataset {
  // Where the data came from: a file path, or a built-in name such as "fresnel-seed".
  std::string source;
  // The line of the header row in `source`, or 0 for data not read from a file.
  int header_line = 0;
  std::vector<Column> columns;
  // Rows the reader dropped for a gap in a column of numbers (CsvOptions::drop_missing_rows),
  // and the line of the first of them (0: none).
  std::size_t dropped_rows = 0;
  int first_dropped_line = 0;

  // Number of rows (every column has this many cells); 0 with no columns.
  [[nodiscard]] std::size_t rows() const;

  // The column with this name, or nullptr.
  [[nodiscard]] const Column* find(std::string_view name) const;

  // The column with this name. Throws Error "no column 'R' in data.csv (columns: r0, x, ...)",
  // located at the header line.
  [[nodiscard]] const Column& column(std::string_view name) const;

  // The numeric column with this name. Throws as column() when it is missing, and Error
  // "column 'R' is not numeric: 'abc' in row 17" (rows counted from 1, the header not counted),
  // located at that cell, when it is text.
  [[nodiscard]] const Column& numeric(std::string_view name) const;

  // Column names, in order.
  [[nodiscard]] std::vector<std::string> names() const;

  // Append a column. Throws Error if the name is empty or already used, or if the length differs
  // from rows() (when there are columns already).
  Column& add_numeric(std::string name, std::vector<double> values);
  Column& add_text(std::string name, std::vector<std::string> labels);
};

}  // namespace shaderfit
