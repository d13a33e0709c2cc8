// Fuzz target: a CSV data file (shaderfit eval/search/fit/plot --data). parse_csv must read it or
// throw shaderfit::Error; a data set it read must write back with to_csv and read again to the same
// column names, rows and numbers (csv.hpp's round-trip contract).
#include <bit>
#include <cstdint>

#include "fuzz_targets.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/data/csv.hpp"

namespace shaderfit::fuzz {

namespace {

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

void check_same(const Dataset& a, const Dataset& b, const std::string& written) {
  if (a.columns.size() != b.columns.size() || a.rows() != b.rows())
    throw FuzzFailure("CSV round trip changed the shape:\n" + written);
  for (std::size_t i = 0; i < a.columns.size(); ++i) {
    const Column& x = a.columns[i];
    const Column& y = b.columns[i];
    if (x.name != y.name) throw FuzzFailure("CSV round trip changed column name '" + x.name + "'");
    // A text column read from a file has a cell that is not a number, so it stays text.
    if (x.numeric() != y.numeric())
      throw FuzzFailure("CSV round trip changed the kind of column '" + x.name + "'");
    for (std::size_t r = 0; r < x.size(); ++r) {
      const bool same =
          x.numeric() ? same_bits(x.values[r], y.values[r]) : x.labels[r] == y.labels[r];
      if (!same)
        throw FuzzFailure("CSV round trip changed column '" + x.name + "' row " +
                          std::to_string(r + 1) + ":\n" + written);
    }
  }
}

}  // namespace

void csv(const std::uint8_t* data, std::size_t size) {
  Dataset d;
  try {
    d = parse_csv(as_text(data, size), "fuzz.csv");
  } catch (const Error&) {
    return;  // the expected outcome for bad input
  }
  for (const Column& c : d.columns) {
    try {
      (void)d.numeric(c.name);
    } catch (const Error&) {
      // a text column asked for as numbers: documented
    }
  }
  std::string written;
  try {
    written = to_csv(d);
  } catch (const Error& e) {
    throw FuzzFailure(std::string("a data set parse_csv read cannot be written: ") + e.what());
  }
  Dataset back;
  try {
    back = parse_csv(written, "written.csv");
  } catch (const Error& e) {
    throw FuzzFailure(std::string("to_csv output does not read back: ") + e.what() + "\n" +
                      written);
  }
  check_same(d, back, written);
}

}  // namespace shaderfit::fuzz

SHADERFIT_FUZZ_ENTRY(csv)
