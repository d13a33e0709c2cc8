// Reading and writing data sets as CSV.
//
//   Dataset d = read_csv("measured.csv");   // header row of names, then one row per sample
//   write_csv(d, "copy.csv");               // reads back with bit-identical numbers
//
// The format read: the first non-blank line is a header of column names; cells are separated by
// commas; a cell may be wrapped in double quotes (a quote inside is written ""; a quoted cell may
// hold commas and line breaks); spaces and tabs around a cell are trimmed; CRLF line ends and a
// UTF-8 byte-order mark are accepted; blank lines at the end are ignored. A column is numeric when
// every one of its cells is a whole number in std::from_chars's general format (an optional
// leading '+' is allowed), and text when fewer than half of its cells are. A column of numbers
// with gaps (at least half its cells numbers, some empty or not numbers) is an error at its
// first gap, or with CsvOptions::drop_missing_rows its rows with a gap are dropped and counted
// (Dataset::dropped_rows): a column is never taken as text for one stray cell.
//
// Errors are shaderfit::Error located at {path, line, column} (1-based; the column counts
// characters and points at the first character of the offending cell): a file that cannot be
// opened or read, an empty file, an empty or duplicate header name, a row with the wrong number of
// cells, an unterminated quote or text after a closing quote, a NaN or infinite cell (nan, inf,
// -inf, infinity in any case; also numbers beyond the range of a double), and a file with no data
// rows. A text column asked for as numbers is reported by Dataset::numeric, at its first
// non-number cell.
#pragma once

#include <string>
#include <string_view>

#include "shaderfit/data/dataset.hpp"

namespace shaderfit {

struct CsvOptions {
  // Drop the rows with a gap in a column of numbers (an empty or non-number cell) instead of
  // the error. Every row dropped is still an error.
  bool drop_missing_rows = false;
};

// Reads and parses a CSV file; the Dataset's source is `path`.
Dataset read_csv(const std::string& path, const CsvOptions& options = {});

// Parses CSV text; `source` names it in error locations and becomes the Dataset's source.
Dataset parse_csv(std::string_view text, const std::string& source,
                  const CsvOptions& options = {});

// CSV text for a data set: a header, then one line per row, "\n" line ends. Numbers are written in
// their shortest round-trip form (std::to_chars), so parse_csv gives back the same doubles; cells
// are quoted when needed (commas, quotes, line breaks, surrounding spaces, empty text). A text
// column whose every label looks like a number reads back as numeric. Throws Error for a NaN or
// infinite value, which the reader would reject.
std::string to_csv(const Dataset& data);

// Writes to_csv(data) to `path`. Throws Error "cannot write 'path': <reason>" on failure.
void write_csv(const Dataset& data, const std::string& path);

}  // namespace shaderfit
