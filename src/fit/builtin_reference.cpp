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

std::vector<double> evaluate_reference(const BuiltinFunction& function, const Dataset& data) {
  std::vector<const std::vector<double>*> columns;
  for (std::string_view a : function.arguments) columns.push_back(&data.numeric(a).values);
  std::vector<double> out(data.rows()), args(columns.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    for (std::size_t k = 0; k < columns.size(); ++k) args[k] = (*columns[k])[i];
    out[i] = reference::evaluate_builtin(function, args);
  }
  return out;
}

}  // namespace shaderfit
