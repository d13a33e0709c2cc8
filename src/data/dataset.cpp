#include "shaderfit/data/dataset.hpp"

#include <utility>

#include "data/number.hpp"

namespace shaderfit {

std::size_t Dataset::rows() const { return columns.empty() ? 0 : columns.front().size(); }

const Column* Dataset::find(std::string_view name) const {
  for (const Column& c : columns) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

const Column& Dataset::column(std::string_view name) const {
  if (const Column* c = find(name)) return *c;
  std::string list;
  for (const Column& c : columns) list += (list.empty() ? "" : ", ") + c.name;
  throw Error("no column '" + std::string(name) + "' in " + source + " (columns: " + list + ")",
              SourceLocation{source, header_line, 0});
}

const Column& Dataset::numeric(std::string_view name) const {
  const Column& c = column(name);
  if (c.numeric()) return c;
  // The first label that is not a number; for columns read from a file that is the cell that
  // made the column text, and first_non_number says where it is.
  std::size_t row = 0;
  double ignored = 0.0;
  while (row + 1 < c.labels.size() &&
         data_detail::parse_number(c.labels[row], ignored) == data_detail::NumberParse::kNumber) {
    ++row;
  }
  SourceLocation where = c.first_non_number;
  if (where.source.empty()) where.source = source;
  throw Error("column '" + c.name + "' is not numeric: '" + c.labels[row] + "' in row " +
                  std::to_string(row + 1),
              where);
}

std::vector<std::string> Dataset::names() const {
  std::vector<std::string> out;
  out.reserve(columns.size());
  for (const Column& c : columns) out.push_back(c.name);
  return out;
}

namespace {

void check_new_column(const Dataset& d, const std::string& name, std::size_t size) {
  SourceLocation where{d.source, 0, 0};
  if (name.empty()) throw Error("empty column name", where);
  if (d.find(name) != nullptr) throw Error("duplicate column name '" + name + "'", where);
  if (!d.columns.empty() && size != d.rows()) {
    throw Error("column '" + name + "' has " + std::to_string(size) + " rows, the data set has " +
                    std::to_string(d.rows()),
                where);
  }
}

}  // namespace

Column& Dataset::add_numeric(std::string name, std::vector<double> values) {
  check_new_column(*this, name, values.size());
  Column c;
  c.name = std::move(name);
  c.values = std::move(values);
  columns.push_back(std::move(c));
  return columns.back();
}

Column& Dataset::add_text(std::string name, std::vector<std::string> labels) {
  check_new_column(*this, name, labels.size());
  Column c;
  c.name = std::move(name);
  c.labels = std::move(labels);
  columns.push_back(std::move(c));
  return columns.back();
}

}  // namespace shaderfit
