#include "shaderfit/data/csv.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <memory>
#include <system_error>
#include <utility>
#include <vector>

#include "data/number.hpp"

namespace shaderfit {

namespace {

using data_detail::NumberParse;

struct Cell {
  std::string text;
  int line = 0;
  int column = 0;
  bool quoted = false;
};

// Splits CSV text into records of cells, tracking each cell's line and character column.
class Tokenizer {
 public:
  Tokenizer(std::string_view text, const std::string& source) : text_(text), source_(source) {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);  // UTF-8 byte-order mark
  }

  [[nodiscard]] bool done() const { return pos_ >= text_.size(); }

  // Reads one record (one line, or more when a quoted cell holds line breaks).
  std::vector<Cell> record() {
    std::vector<Cell> cells;
    for (;;) {
      cells.push_back(cell());
      if (peek() == ',') {
        advance();
        continue;
      }
      if (peek() == '\r') advance();  // the \r of \r\n (a lone \r was trimmed as space)
      if (peek() == '\n') advance();
      return cells;
    }
  }

 private:
  [[nodiscard]] char peek(std::size_t ahead = 0) const {
    return pos_ + ahead < text_.size() ? text_[pos_ + ahead] : '\0';
  }
  [[nodiscard]] bool at_line_end() const {
    return done() || peek() == '\n' || (peek() == '\r' && peek(1) == '\n');
  }
  // Spaces and tabs, and a \r that does not end a line.
  [[nodiscard]] bool at_space() const {
    return peek() == ' ' || peek() == '\t' || (peek() == '\r' && peek(1) != '\n' && !done());
  }

  char advance() {
    char c = text_[pos_++];
    if (c == '\n') {
      ++line_;
      column_ = 1;
    } else if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) {
      ++column_;  // count characters, not UTF-8 continuation bytes
    }
    return c;
  }

  [[nodiscard]] SourceLocation here() const { return {source_, line_, column_}; }

  Cell cell() {
    while (at_space()) advance();
    Cell c{"", line_, column_, false};
    if (peek() == '"') {
      c.quoted = true;
      advance();
      for (;;) {
        if (done()) throw Error("unterminated quoted cell", {source_, c.line, c.column});
        char ch = advance();
        if (ch == '"') {
          if (peek() != '"') break;
          advance();
        }
        c.text += ch;
      }
      while (at_space()) advance();
      if (peek() != ',' && !at_line_end())
        throw Error("unexpected text after a closing quote", here());
      return c;
    }
    while (peek() != ',' && !at_line_end()) c.text += advance();
    while (!c.text.empty() &&
           (c.text.back() == ' ' || c.text.back() == '\t' || c.text.back() == '\r')) {
      c.text.pop_back();
    }
    return c;
  }

  std::string_view text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int column_ = 1;
};

bool blank(const std::vector<Cell>& record) {
  return record.size() == 1 && !record[0].quoted && record[0].text.empty();
}

std::string cells_phrase(std::size_t n) {
  return std::to_string(n) + (n == 1 ? " cell" : " cells");
}

// A column being read: every cell's text and value (NaN where the cell is not a number), how
// many cells are numbers, and where the first that is not is.
struct Pending {
  std::string name;
  std::vector<std::string> cells;
  std::vector<double> values;
  std::size_t numbers = 0;
  SourceLocation first_non_number;  // set once a cell is not a number
  std::string first_non_number_text;
};

void add_cell(Pending& col, const Cell& cell, const std::string& source) {
  SourceLocation where{source, cell.line, cell.column};
  double value = 0.0;
  switch (data_detail::parse_number(cell.text, value)) {
    case NumberParse::kNumber:
      col.values.push_back(value);
      ++col.numbers;
      break;
    case NumberParse::kNotNumber:
      col.values.push_back(std::nan(""));
      if (col.first_non_number.source.empty()) {
        col.first_non_number = where;
        col.first_non_number_text = cell.text;
      }
      break;
    case NumberParse::kNaN: throw Error("NaN in column '" + col.name + "'", where);
    case NumberParse::kInfinite:
      throw Error("infinite value '" + cell.text + "' in column '" + col.name + "'", where);
    case NumberParse::kOutOfRange:
      throw Error("number out of range '" + cell.text + "' in column '" + col.name + "'", where);
  }
  col.cells.push_back(cell.text);
}

// A column of numbers with some cells that are not (empty, or a stray word): at least as many
// numbers as other cells, and some of each. Its rows are an error, or dropped.
bool numbers_with_gaps(const Pending& col) {
  const std::size_t others = col.cells.size() - col.numbers;
  return col.numbers > 0 && others > 0 && col.numbers >= others;
}

// A cell that starts with the UTF-8 byte-order mark is quoted too: first in the file, the reader
// would drop the mark as the file's own.
std::string quoted_if_needed(const std::string& s) {
  bool needs = s.empty() || s.front() == ' ' || s.front() == '\t' || s.back() == ' ' ||
               s.back() == '\t' || s.find_first_of(",\"\r\n") != std::string::npos ||
               s.starts_with("\xEF\xBB\xBF");
  if (!needs) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string system_reason() { return std::generic_category().message(errno); }

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

Dataset parse_csv(std::string_view text, const std::string& source, const CsvOptions& options) {
  Tokenizer tokens(text, source);
  std::vector<std::vector<Cell>> records;
  while (!tokens.done()) records.push_back(tokens.record());
  while (!records.empty() && blank(records.back())) records.pop_back();  // trailing blank lines
  std::size_t first = 0;
  while (first < records.size() && blank(records[first])) ++first;  // leading blank lines
  if (first == records.size()) throw Error("empty file: no header row", {source, 1, 0});

  const std::vector<Cell>& header = records[first];
  std::vector<Pending> columns(header.size());
  for (std::size_t i = 0; i < header.size(); ++i) {
    const Cell& h = header[i];
    SourceLocation where{source, h.line, h.column};
    if (h.text.empty()) {
      throw Error("empty column name in the header (column " + std::to_string(i + 1) + ")", where);
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (columns[j].name == h.text) throw Error("duplicate column name '" + h.text + "'", where);
    }
    columns[i].name = h.text;
  }
  if (first + 1 == records.size()) {
    throw Error("no data rows (only a header)", {source, header.front().line, 0});
  }

  std::vector<int> lines;  // each data row's line
  for (std::size_t r = first + 1; r < records.size(); ++r) {
    const std::vector<Cell>& row = records[r];
    lines.push_back(row.front().line);
    if (row.size() != header.size()) {
      int column = row.size() > header.size() ? row[header.size()].column : 1;
      throw Error("row has " + cells_phrase(row.size()) + ", the header has " +
                      std::to_string(header.size()),
                  {source, row.front().line, column});
    }
    for (std::size_t i = 0; i < row.size(); ++i) add_cell(columns[i], row[i], source);
  }

  // Numbers with gaps: an error at the first gap, or the rows with a gap dropped.
  const std::size_t rows = lines.size();
  std::vector<char> keep(rows, 1);
  for (const Pending& p : columns) {
    if (!numbers_with_gaps(p)) continue;
    const std::size_t gaps = p.cells.size() - p.numbers;
    if (!options.drop_missing_rows) {
      const std::string cell = p.first_non_number_text.empty()
                                   ? "this one is empty"
                                   : "this one is '" + p.first_non_number_text + "'";
      throw Error("column '" + p.name + "' is numbers but for " + cells_phrase(gaps) + ": " +
                      cell + " (fix them, or drop their rows: CsvOptions::drop_missing_rows)",
                  p.first_non_number);
    }
    for (std::size_t r = 0; r < rows; ++r)
      if (std::isnan(p.values[r])) keep[r] = 0;
  }
  Dataset data;
  data.source = source;
  data.header_line = header.front().line;
  for (std::size_t r = 0; r < rows; ++r) {
    if (keep[r] != 0) continue;
    if (data.dropped_rows++ == 0) data.first_dropped_line = lines[r];
  }
  if (data.dropped_rows == rows)
    throw Error("every data row has an empty or non-number cell in a column of numbers",
                {source, header.front().line, 0});
  for (Pending& p : columns) {
    Column c;
    c.name = std::move(p.name);
    const bool numeric = p.numbers == p.cells.size() || numbers_with_gaps(p);
    for (std::size_t r = 0; r < rows; ++r) {
      if (keep[r] == 0) continue;
      if (numeric)
        c.values.push_back(p.values[r]);
      else
        c.labels.push_back(std::move(p.cells[r]));
    }
    if (!numeric) c.first_non_number = std::move(p.first_non_number);
    data.columns.push_back(std::move(c));
  }
  return data;
}

Dataset read_csv(const std::string& path, const CsvOptions& options) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw Error("cannot open '" + path + "': " + system_reason(), {path, 0, 0});
  std::string text;
  char buffer[1 << 16];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, file.get())) > 0) text.append(buffer, n);
  if (std::ferror(file.get())) {
    throw Error("cannot read '" + path + "': " + system_reason(), {path, 0, 0});
  }
  return parse_csv(text, path, options);
}

std::string to_csv(const Dataset& data) {
  std::string out;
  for (std::size_t i = 0; i < data.columns.size(); ++i) {
    if (i) out += ',';
    out += quoted_if_needed(data.columns[i].name);
  }
  out += '\n';
  for (std::size_t r = 0; r < data.rows(); ++r) {
    for (std::size_t i = 0; i < data.columns.size(); ++i) {
      const Column& c = data.columns[i];
      if (i) out += ',';
      if (!c.numeric()) {
        out += quoted_if_needed(c.labels[r]);
      } else if (std::isfinite(c.values[r])) {
        out += data_detail::format_number(c.values[r]);
      } else {
        throw Error("cannot write " +
                        std::string(std::isnan(c.values[r]) ? "NaN" : "an infinite value") +
                        " in column '" + c.name + "' (row " + std::to_string(r + 1) + ")",
                    {data.source, 0, 0});
      }
    }
    out += '\n';
  }
  return out;
}

void write_csv(const Dataset& data, const std::string& path) {
  std::string text = to_csv(data);
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) throw Error("cannot write '" + path + "': " + system_reason(), {path, 0, 0});
  bool ok = std::fwrite(text.data(), 1, text.size(), file.get()) == text.size();
  ok = std::fflush(file.get()) == 0 && ok;
  if (!ok) throw Error("cannot write '" + path + "': " + system_reason(), {path, 0, 0});
  std::FILE* raw = file.release();
  if (std::fclose(raw) != 0)
    throw Error("cannot write '" + path + "': " + system_reason(), {path, 0, 0});
}

}  // namespace shaderfit
