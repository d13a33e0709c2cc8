#include "shaderfit/data/fresnel_sweep.hpp"

#include <charconv>
#include <cmath>
#include <numbers>

#include "data/fresnel_rows.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit {

std::vector<Material> named_materials() {
  const std::string src = "632.8 nm, Sopra material library (Filmetrics refractive-index database)";
  return {{"aluminium", 1.37289, 7.617691, src}, {"gold", 0.18104, 3.068099, src}};
}

namespace {

bool read_number(std::string_view s, double& v) {
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size() && std::isfinite(v);
}

std::string label(double n, double k) {
  if (k == 0) return "ior" + format_number(n);
  return "metal " + format_number(n) + "+" + format_number(k) + "i";
}

}  // namespace

Material parse_material(std::string_view text, const SourceLocation& where) {
  for (const Material& m : named_materials())
    if (text == m.name) return m;
  std::string_view t = text;
  if (t.rfind("metal ", 0) == 0) t.remove_prefix(6);
  if (t.rfind("ior", 0) == 0) t.remove_prefix(3);
  double n = 0, k = 0;
  bool ok = false;
  if (!t.empty() && t.back() == 'i') {
    const auto plus = t.find('+', 1);
    ok = plus != std::string_view::npos && read_number(t.substr(0, plus), n) &&
         read_number(t.substr(plus + 1, t.size() - plus - 2), k);
  } else {
    ok = read_number(t, n);
  }
  if (!ok) {
    std::string names;
    for (const Material& m : named_materials()) names += ", " + m.name;
    throw Error("unknown material '" + std::string(text) +
                    "': give an IOR such as 1.5, a complex IOR such as "
                    "0.3+3i, or a name (" +
                    names.substr(2) + ")",
                where);
  }
  if (!(n > 0) || k < 0) {
    throw Error("material '" + std::string(text) + "' needs n > 0 and k >= 0", where);
  }
  return Material{label(n, k), n, k, ""};
}

std::vector<Material> seed_materials() {
  std::vector<Material> m = {parse_material("1.5")};
  for (const char* metal :
       {"0.3+3i", "0.15+4i", "0.3+3.35i", "1.4+7i", "1.84+3.73i", "2.1+4i", "2.9+3.1i"})
    m.push_back(parse_material(metal));
  return m;
}

Dataset make_fresnel_sweep(const std::vector<Material>& materials, int angles) {
  if (angles < 2)
    throw Error("a sweep needs at least 2 angles, got " + std::to_string(angles),
                {"fresnel_sweep::angles"});
  if (materials.empty())
    throw Error("a sweep needs at least one material", {"fresnel_sweep::materials"});
  std::vector<double> deg;
  data_detail::FresnelRows rows;
  for (const Material& m : materials) {
    for (int a = 0; a < angles; ++a) {
      const double d = 90.0 * a / (angles - 1);
      // cos(90 deg) is 6e-17 in double; the sweep ends at exactly grazing incidence.
      const double c = a == angles - 1 ? 0.0 : std::cos(d * std::numbers::pi / 180.0);
      deg.push_back(d);
      rows.add(c, m.n, m.k, m.name);
    }
  }
  Dataset d;
  d.source = "fresnel-sweep";
  d.add_numeric("theta_deg", std::move(deg));
  rows.move_into(d);
  return d;
}

}  // namespace shaderfit
