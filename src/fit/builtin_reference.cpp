#include "shaderfit/fit/builtin_reference.hpp"

namespace shaderfit {

using reference::BuiltinFunction;

std::vector<const BuiltinFunction*> builtin_references() {
  std::vector<const BuiltinFunction*> out;
  for (const BuiltinFunction& f : reference::builtin_functions())
    if (f.listed_in(reference::FitReference)) out.push_back(&f);
  return out;
}

const BuiltinFunction* find_builtin_reference(std::string_view name) {
  return reference::find_builtin(name, reference::FitReference);
}

std::string describe_builtin_references() {
  std::string s;
  for (const BuiltinFunction* r : builtin_references()) {
    std::string args;
    for (std::string_view a : r->arguments) args += (args.empty() ? "" : ", ") + std::string(a);
    s += std::string(r->name) + "(" + args + "): " + std::string(r->description) + "\n";
  }
  return s;
}

}  // namespace shaderfit
