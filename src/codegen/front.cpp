#include "shaderfit/codegen/front.hpp"

#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {

std::vector<FrontFormula> read_front(const std::string& path, const FrontReadOptions& options) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error("cannot open the front file", SourceLocation{path});
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw Error("cannot read the front file", SourceLocation{path});
  return parse_front(text.str(), path, options);
}

std::vector<FrontFormula> parse_front(std::string_view json, const std::string& path,
                                      const FrontReadOptions& options) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(json.begin(), json.end());
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("not valid JSON: ") + e.what(), SourceLocation{path});
  }
  if (!doc.is_object() || !doc.contains("front") || !doc["front"].is_array()) {
    throw Error("expected an object with a \"front\" list", SourceLocation{path});
  }
  std::vector<std::string> inputs = options.inputs;
  if (inputs.empty() && doc.contains("inputs")) {
    if (!doc["inputs"].is_array()) throw Error("\"inputs\" must be a list of names", SourceLocation{path});
    for (const auto& n : doc["inputs"]) {
      if (!n.is_string()) throw Error("\"inputs\" must be a list of names", SourceLocation{path});
      inputs.push_back(n.get<std::string>());
    }
  }
  std::vector<FrontFormula> out;
  const auto& front = doc["front"];
  for (std::size_t i = 0; i < front.size(); ++i) {
    const std::string where = path + ": front[" + std::to_string(i) + "]";
    const auto& m = front[i];
    if (!m.is_object() || !m.contains("formula") || !m["formula"].is_string()) {
      throw Error("member has no \"formula\" string", SourceLocation{where});
    }
    ParseOptions po;
    po.variables = inputs;
    po.parameters = options.parameters;
    po.source = where;
    FrontFormula f;
    if (m.contains("parameters")) {
      const auto& p = m["parameters"];
      if (p.is_array()) {
        for (const auto& n : p) {
          if (!n.is_string()) throw Error("\"parameters\" must be names or an object of numbers", SourceLocation{where});
          po.parameters.push_back(n.get<std::string>());
        }
      } else if (p.is_object()) {
        f.parameters_have_values = true;
        po.parameter_values.assign(po.parameters.size(), 0.0);
        for (const auto& [name, value] : p.items()) {
          if (!value.is_number()) throw Error("parameter '" + name + "' has no numeric value", SourceLocation{where});
          po.parameters.push_back(name);
          po.parameter_values.push_back(value.get<double>());
        }
      } else {
        throw Error("\"parameters\" must be names or an object of numbers", SourceLocation{where});
      }
    }
    f.formula = m["formula"].get<std::string>();
    f.expression = parse_formula(f.formula, po);
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace shaderfit
