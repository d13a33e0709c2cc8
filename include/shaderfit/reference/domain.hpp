// The domain of a reference's variables: one interval per variable, as users write it
// ("x=-1:1", "theta=0:pi/2:90"), and how many samples it asks for.
//
//   DomainAxis x = parse_domain_axis("x=-1:1", "domain");             // the default design
//   DomainAxis t = parse_domain_axis("theta=0:pi/2:90", "domain");    // 90 midpoints
//   DomainAxis e = parse_domain_axis("u=0:1:33:endpoints", "domain"); // 33 points, ends included
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace shaderfit::reference {

enum class Spacing { Midpoints, Endpoints };

struct DomainAxis {
  std::string name;
  double lo = 0, hi = 1;
  // 0: the sample design chooses (data/sampling.hpp); else this many points on a regular grid,
  // at the midpoints of equal intervals (never the ends) or from lo to hi inclusive.
  std::size_t count = 0;
  Spacing spacing = Spacing::Midpoints;

  // Point i of the regular grid of `count` points (count > 0).
  [[nodiscard]] double at(std::size_t i) const;
  [[nodiscard]] double width() const { return hi - lo; }
  [[nodiscard]] bool contains(double v) const { return v >= lo && v <= hi; }
};

// "name=lo:hi[:count[:midpoints|endpoints]]"; lo and hi are constant expressions of the reference
// language (pi/2). Throws shaderfit::Error located at `source` for a bad shape, a name that is
// not an identifier, a bound that does not evaluate to a finite number, an empty or reversed
// domain (lo >= hi; the message says which), a count of zero or one that is not a whole number,
// an unknown spacing.
DomainAxis parse_domain_axis(std::string_view text, const std::string& source);

}  // namespace shaderfit::reference
