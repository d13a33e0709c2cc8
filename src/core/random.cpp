#include "shaderfit/core/random.hpp"

#include <locale>
#include <sstream>

namespace shaderfit {

std::string rng_text(const Rng& rng) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out << rng;
  return out.str();
}

bool rng_from_text(std::string_view text, Rng* rng) {
  std::istringstream in{std::string(text)};
  in.imbue(std::locale::classic());
  Rng read;
  if (!(in >> read)) return false;
  *rng = read;
  return true;
}

}  // namespace shaderfit
