#include "shaderfit/reference/domain.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/reference/language.hpp"

namespace shaderfit::reference {

namespace {

constexpr const char* kShape = "name=lo:hi[:count[:midpoints|endpoints]]";

[[noreturn]] void fail(const std::string& message, const std::string& source) {
  throw Error(message, SourceLocation{source});
}

std::string trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())) != 0) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())) != 0) s.remove_suffix(1);
  return std::string(s);
}

bool is_identifier(std::string_view s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) != 0 || s[0] == '_'))
    return false;
  for (const char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_')) return false;
  return true;
}

double bound(const std::string& field, const std::string& name, const char* which,
             const std::string& source) {
  if (field.empty())
    fail("the " + std::string(which) + " bound of '" + name + "' is missing", source);
  try {
    return evaluate_constant(field, source);
  } catch (const Error& e) {
    fail("the " + std::string(which) + " bound of '" + name + "', '" + field +
             "', is not a finite number: " + e.message(),
         source);
  }
}

}  // namespace

double DomainAxis::at(std::size_t i) const {
  if (count == 0) return 0.5 * lo + 0.5 * hi;
  const double n = static_cast<double>(count);
  if (spacing == Spacing::Endpoints) {
    if (count == 1) return 0.5 * lo + 0.5 * hi;
    // The ends exactly, whatever the rounding of lo + (hi - lo) * 1.
    if (i == 0) return lo;
    if (i + 1 >= count) return hi;
    return lo + (hi - lo) * (static_cast<double>(i) / (n - 1));
  }
  return lo + (hi - lo) * ((static_cast<double>(i) + 0.5) / n);
}

DomainAxis parse_domain_axis(std::string_view text, const std::string& source) {
  const std::size_t eq = text.find('=');
  if (eq == std::string_view::npos)
    fail("expected '" + std::string(kShape) + "', got '" + std::string(text) + "'", source);
  DomainAxis axis;
  axis.name = trim(text.substr(0, eq));
  if (!is_identifier(axis.name)) {
    fail("the domain's variable '" + axis.name + "' is not a name (letters, digits and '_')",
         source);
  }
  std::vector<std::string> fields;
  std::string_view rest = text.substr(eq + 1);
  while (true) {
    const std::size_t colon = rest.find(':');
    fields.push_back(trim(rest.substr(0, colon)));
    if (colon == std::string_view::npos) break;
    rest.remove_prefix(colon + 1);
  }
  if (fields.size() < 2 || fields.size() > 4)
    fail("expected '" + std::string(kShape) + "', got '" + std::string(text) + "'", source);
  axis.lo = bound(fields[0], axis.name, "lower", source);
  axis.hi = bound(fields[1], axis.name, "upper", source);
  if (axis.lo == axis.hi) {
    fail("the domain of '" + axis.name + "' is empty: lo = hi = " + fields[0] +
             "; lo must be below hi",
         source);
  }
  if (axis.lo > axis.hi) {
    fail("the domain of '" + axis.name + "' is reversed: lo " + fields[0] + " is above hi " +
             fields[1] + "; write " + axis.name + "=" + fields[1] + ":" + fields[0],
         source);
  }
  if (!std::isfinite(axis.hi - axis.lo))
    fail("the domain of '" + axis.name + "' is too wide for a double", source);
  if (fields.size() >= 3) {
    const std::string& c = fields[2];
    unsigned long long v = 0;
    const auto [ptr, ec] = std::from_chars(c.data(), c.data() + c.size(), v);
    if (c.empty() || ec != std::errc() || ptr != c.data() + c.size())
      fail("the sample count of '" + axis.name + "', '" + c + "', is not a whole number", source);
    if (v == 0) fail("the sample count of '" + axis.name + "' must be at least 1, got 0", source);
    axis.count = static_cast<std::size_t>(v);
  }
  if (fields.size() == 4) {
    if (fields[3] == "endpoints")
      axis.spacing = Spacing::Endpoints;
    else if (fields[3] != "midpoints")
      fail("unknown spacing '" + fields[3] + "' (midpoints, endpoints)", source);
  }
  return axis;
}

}  // namespace shaderfit::reference
