// A reference in the reference language over a domain, for the tests of verify/.
#pragma once

#include <string>
#include <vector>

#include "shaderfit/reference/domain.hpp"
#include "shaderfit/reference/function.hpp"
#include "shaderfit/reference/language.hpp"

namespace shaderfit::test {

// `formula` over the domain's variables ("x=-1:1", ...), with `definitions` ("t = x * y").
inline reference::ReferenceFunction make_reference(
    const std::string& formula, const std::vector<std::string>& domain,
    const std::vector<std::string>& definitions = {}) {
  reference::ReferenceFunction f;
  reference::ReferenceText t;
  t.formula = formula;
  t.definitions = definitions;
  for (const std::string& d : domain) {
    f.domain.push_back(reference::parse_domain_axis(d, "domain"));
    t.variables.push_back(f.domain.back().name);
  }
  f.program = reference::compile_reference(t);
  f.target = std::string(reference::kReferenceOutput);
  return f;
}

}  // namespace shaderfit::test
