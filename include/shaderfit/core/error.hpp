// Errors raised by the library for bad input. Library code never ends the process: it throws
// shaderfit::Error, which carries where the problem is (a file or formula, a line and a column),
// and the command-line tool turns it into one line on stderr and exit status 2.
//
//   try { parse_formula("x +", {"x"}); }
//   catch (const shaderfit::Error& e) { std::cerr << e.what(); }  // "formula:1:4: expected ..."
#pragma once

#include <stdexcept>
#include <string>

namespace shaderfit {

// Where a bad input is. `source` names a file path, or a pseudo-source such as "formula" or
// a field, "SearchOptions::seed"; line and column are 1-based, 0 when not known.
struct SourceLocation {
  std::string source;
  int line = 0;
  int column = 0;

  // "source:line:column", dropping the parts that are not known.
  [[nodiscard]] std::string to_string() const;
};

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message, SourceLocation where = {});

  [[nodiscard]] const SourceLocation& where() const noexcept { return where_; }
  // The message alone, without the location prefix that what() carries.
  [[nodiscard]] const std::string& message() const noexcept { return message_; }

 private:
  SourceLocation where_;
  std::string message_;
};

}  // namespace shaderfit
