#include "shaderfit/search/front_member.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "search/exact_json.hpp"
#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit {

using nlohmann::json;

std::string_view search_phase_name(SearchPhase phase) {
  switch (phase) {
    case SearchPhase::Enumeration: return "enumeration";
    case SearchPhase::Evolution: return "evolution";
    case SearchPhase::Start: return "start";
    case SearchPhase::PowerSum: return "power_sum";
    case SearchPhase::Polynomial: return "polynomial";
    case SearchPhase::Material: return "material";
    case SearchPhase::Reference: return "reference";
    case SearchPhase::Rewrite: return "rewrite";
    case SearchPhase::Shape: return "shape";
  }
  return "enumeration";
}

std::optional<SearchPhase> search_phase_from_name(std::string_view name) {
  if (name == "enumeration") return SearchPhase::Enumeration;
  if (name == "evolution") return SearchPhase::Evolution;
  if (name == "start") return SearchPhase::Start;
  if (name == "power_sum") return SearchPhase::PowerSum;
  if (name == "polynomial") return SearchPhase::Polynomial;
  if (name == "material") return SearchPhase::Material;
  if (name == "reference") return SearchPhase::Reference;
  if (name == "rewrite") return SearchPhase::Rewrite;
  if (name == "shape") return SearchPhase::Shape;
  return std::nullopt;
}

namespace search_detail {

json exact_number(double v) {
  if (std::isfinite(v)) return v;  // nlohmann writes the shortest text that reads back exactly
  return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
}

double exact_number_from(const json& j) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    const auto& s = j.get_ref<const std::string&>();
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
  }
  throw BadExactJson("a number was expected");
}

json exact_expression_json(const Expression& e) {
  json nodes = json::array();
  for (const Node& n : e.nodes)
    nodes.push_back({static_cast<int>(n.op), n.index, exact_number(n.value)});
  json values = json::array();
  for (double v : e.parameter_values) values.push_back(exact_number(v));
  return {{"variables", e.variables},
          {"parameters", e.parameters},
          {"values", values},
          {"nodes", nodes}};
}

Expression exact_expression_from(const json& j) {
  Expression e;
  e.variables = j.at("variables").get<std::vector<std::string>>();
  e.parameters = j.at("parameters").get<std::vector<std::string>>();
  for (const json& v : j.at("values")) e.parameter_values.push_back(exact_number_from(v));
  if (e.parameter_values.size() != e.parameters.size())
    throw BadExactJson("a formula has parameters without values");
  for (const json& n : j.at("nodes")) {
    const int op = exact_integer_from<int>(n.at(0), "a node's operator");
    const int index = exact_integer_from<std::int16_t>(n.at(1), "a node's index");
    if (op < 0 || op >= kOpCount) throw BadExactJson("an unknown operator");
    Node node = Node::op_node(static_cast<Op>(op));
    node.index = static_cast<std::int16_t>(index);
    node.value = exact_number_from(n.at(2));
    const auto bound =
        static_cast<int>(node.op == Op::Var ? e.variables.size() : e.parameters.size());
    if ((node.op == Op::Var || node.op == Op::Param) && (index < 0 || index >= bound))
      throw BadExactJson("a variable or parameter out of range");
    e.nodes.push_back(node);
  }
  if (e.nodes.empty()) throw BadExactJson("an empty formula");
  e.update_lengths();  // throws on a malformed tree
  return e;
}

}  // namespace search_detail

namespace {

using search_detail::exact_number;
using search_detail::exact_number_from;

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(); }

std::string code_for(const FrontMember& m, Language lang) {
  try {
    CodegenOptions o;
    o.language = lang;
    o.name = "shaderfit_formula";
    o.bake_parameters = true;
    o.uniform = m.uniform;
    return generate_function(m.expression, o);
  } catch (const std::exception&) {
    return {};
  }
}

// A number of the Result form: absent or null is NaN.
double result_number(const json& m, const char* key, const std::string& where) {
  const auto it = m.find(key);
  if (it == m.end() || it->is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!it->is_number())
    throw Error(std::string("\"") + key + "\" must be a number", SourceLocation{where});
  return it->get<double>();
}

}  // namespace

json front_member_json(const FrontMember& m, FrontJson style) {
  const bool exact = style == FrontJson::Exact;
  auto number = [&](double v) { return exact ? exact_number(v) : number_or_null(v); };
  json j = {{"formula", m.formula},
            {"cost", number(m.cost)},
            {"nodes", m.nodes},
            {"loss", number(m.loss)},
            {"mse", number(m.metrics.mse)},
            {"rmse", number(m.metrics.rmse)},
            {"max_abs", number(m.metrics.max_abs)},
            {"max_rel", number(m.metrics.max_rel)},
            {"rel", number(m.metrics.rel)},
            {"log", number(m.metrics.log)},
            {"time_s", number(m.time_s)},
            {"origin", search_phase_name(m.origin)},
            {"float32_max_abs_diff", number(m.float32_max_abs_diff)},
            {"float32_stable", m.float32_stable},
            {"float32_max_abs", number(m.float32_max_abs)},
            {"float32_max_rel", number(m.float32_max_rel)},
            {"half_max_abs", number(m.half_max_abs)},
            {"half_max_rel", number(m.half_max_rel)}};
  if (!m.uniform.empty()) {
    j["uniform"] = m.uniform;
    j["material_cost"] = number(m.material_cost);
  }
  if (m.checked_between_samples) {
    j["max_abs_checked"] = "between samples";
    j["worst_point"] = m.worst_point;
  }
  if (m.certified_max_abs) {
    // Infinite (no finite bound) is written as null in both forms: a reader takes it as such.
    j["certified_max_abs"] =
        std::isfinite(*m.certified_max_abs) ? json(*m.certified_max_abs) : json();
    j["certified_converged"] = m.certified_converged;
    j["certify_time_s"] = number(m.certify_time_s);
    if (!m.certify_note.empty()) j["certify_note"] = m.certify_note;
  }
  if (m.minor_step) j["minor_step"] = true;
  if (exact) {
    j["expression"] = search_detail::exact_expression_json(m.expression);
    return j;
  }
  json params = json::object();
  for (std::size_t i = 0; i < m.expression.parameters.size(); ++i)
    params[m.expression.parameters[i]] = m.expression.parameter_values[i];
  j["formula_display"] = to_infix(m.expression, PrintOptions::for_people());
  j["formula_parametric"] = to_infix(m.expression);
  j["fitted_parameters"] = params;
  j["latex"] = to_latex(m.expression, PrintOptions::for_people());
  j["code"] = {{"glsl", code_for(m, Language::Glsl)}, {"cuda", code_for(m, Language::Cuda)}};
  return j;
}

namespace {

// The exact form: every field of a checkpoint's member (the float32 and half checks, the check
// between the samples and the certificate are optional: they are filled in for the final front
// only).
FrontMember exact_member_from(const json& j) {
  FrontMember m;
  m.expression = search_detail::exact_expression_from(j.at("expression"));
  m.formula = j.at("formula").get<std::string>();
  m.cost = exact_number_from(j.at("cost"));
  if (j.contains("uniform")) {
    m.uniform = j.at("uniform").get<std::vector<std::string>>();
    m.material_cost = exact_number_from(j.at("material_cost"));
  }
  m.nodes = search_detail::exact_integer_from<std::size_t>(j.at("nodes"), "nodes");
  m.loss = exact_number_from(j.at("loss"));
  m.metrics.mse = exact_number_from(j.at("mse"));
  m.metrics.rmse = exact_number_from(j.at("rmse"));
  m.metrics.max_abs = exact_number_from(j.at("max_abs"));
  m.metrics.rel = exact_number_from(j.at("rel"));
  m.metrics.log = exact_number_from(j.at("log"));
  if (j.contains("max_rel")) m.metrics.max_rel = exact_number_from(j.at("max_rel"));
  m.time_s = exact_number_from(j.at("time_s"));
  const auto origin = search_phase_from_name(j.at("origin").get<std::string>());
  if (!origin) throw search_detail::BadExactJson("an unknown origin");
  m.origin = *origin;
  if (j.contains("float32_max_abs_diff"))
    m.float32_max_abs_diff = exact_number_from(j.at("float32_max_abs_diff"));
  if (j.contains("float32_stable")) m.float32_stable = j.at("float32_stable").get<bool>();
  for (const auto& [key, field] : {std::pair{"float32_max_abs", &FrontMember::float32_max_abs},
                                   std::pair{"float32_max_rel", &FrontMember::float32_max_rel},
                                   std::pair{"half_max_abs", &FrontMember::half_max_abs},
                                   std::pair{"half_max_rel", &FrontMember::half_max_rel}})
    if (j.contains(key)) m.*field = exact_number_from(j.at(key));
  if (j.contains("max_abs_checked")) {
    m.checked_between_samples = true;
    m.worst_point = j.at("worst_point").get<std::vector<double>>();
  }
  if (j.contains("certified_max_abs")) {
    const json& c = j.at("certified_max_abs");
    m.certified_max_abs = c.is_null() ? std::numeric_limits<double>::infinity() : c.get<double>();
    m.certified_converged = j.at("certified_converged").get<bool>();
    m.certify_time_s = exact_number_from(j.at("certify_time_s"));
    m.certify_note = j.value("certify_note", "");
  }
  if (j.contains("minor_step")) m.minor_step = j.at("minor_step").get<bool>();
  return m;
}

}  // namespace

ReadFrontMember front_member_from_json(const json& m, const std::vector<std::string>& inputs,
                                       const FrontReadOptions& options, const std::string& where) {
  ReadFrontMember out;
  if (m.is_object() && m.contains("expression")) {
    out.member = exact_member_from(m);
    out.parameters_have_values = true;
    return out;
  }
  if (!m.is_object() || !m.contains("formula") || !m["formula"].is_string())
    throw Error("member has no \"formula\" string", SourceLocation{where});
  ParseOptions po;
  po.variables = inputs;
  po.parameters = options.parameters;
  po.source = where;
  if (m.contains("parameters")) {
    const auto& p = m["parameters"];
    if (p.is_array()) {
      for (const auto& n : p) {
        if (!n.is_string())
          throw Error("\"parameters\" must be names or an object of numbers",
                      SourceLocation{where});
        po.parameters.push_back(n.get<std::string>());
      }
    } else if (p.is_object()) {
      out.parameters_have_values = true;
      po.parameter_values.assign(po.parameters.size(), 0.0);
      for (const auto& [name, value] : p.items()) {
        if (!value.is_number())
          throw Error("parameter '" + name + "' has no numeric value", SourceLocation{where});
        po.parameters.push_back(name);
        po.parameter_values.push_back(value.get<double>());
      }
    } else {
      throw Error("\"parameters\" must be names or an object of numbers", SourceLocation{where});
    }
  }
  FrontMember& f = out.member;
  f.formula = m["formula"].get<std::string>();
  f.expression = parse_formula(f.formula, po);
  f.nodes = f.expression.size();
  f.cost = result_number(m, "cost", where);
  if (m.contains("uniform") && m["uniform"].is_array()) {
    for (const auto& n : m["uniform"])
      if (n.is_string()) f.uniform.push_back(n.get<std::string>());
    f.material_cost = result_number(m, "material_cost", where);
  }
  f.loss = result_number(m, "loss", where);
  f.metrics.mse = result_number(m, "mse", where);
  f.metrics.rmse = result_number(m, "rmse", where);
  f.metrics.max_abs = result_number(m, "max_abs", where);
  f.metrics.rel = result_number(m, "rel", where);
  f.metrics.log = result_number(m, "log", where);
  if (m.contains("max_rel")) f.metrics.max_rel = result_number(m, "max_rel", where);
  f.time_s = result_number(m, "time_s", where);
  f.float32_max_abs_diff = result_number(m, "float32_max_abs_diff", where);
  f.float32_max_abs = result_number(m, "float32_max_abs", where);
  f.float32_max_rel = result_number(m, "float32_max_rel", where);
  if (m.contains("half_max_abs")) f.half_max_abs = result_number(m, "half_max_abs", where);
  if (m.contains("half_max_rel")) f.half_max_rel = result_number(m, "half_max_rel", where);
  f.checked_between_samples = m.contains("max_abs_checked");
  if (m.contains("certified_max_abs")) {
    // null: no finite bound was found.
    const double b = result_number(m, "certified_max_abs", where);
    f.certified_max_abs = std::isnan(b) ? std::numeric_limits<double>::infinity() : b;
    if (m.contains("certified_converged") && m["certified_converged"].is_boolean())
      f.certified_converged = m["certified_converged"].get<bool>();
    f.certify_time_s = result_number(m, "certify_time_s", where);
    if (m.contains("certify_note") && m["certify_note"].is_string())
      f.certify_note = m["certify_note"].get<std::string>();
  }
  if (m.contains("origin") && m["origin"].is_string())
    f.origin =
        search_phase_from_name(m["origin"].get<std::string>()).value_or(SearchPhase::Enumeration);
  if (m.contains("float32_stable") && m["float32_stable"].is_boolean())
    f.float32_stable = m["float32_stable"].get<bool>();
  if (m.contains("minor_step") && m["minor_step"].is_boolean())
    f.minor_step = m["minor_step"].get<bool>();
  return out;
}

FrontFile read_front_file(const std::string& path, const FrontReadOptions& options) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error("cannot open the front file", SourceLocation{path});
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw Error("cannot read the front file", SourceLocation{path});
  return parse_front_file(text.str(), path, options);
}

FrontFile parse_front_file(std::string_view text, const std::string& path,
                           const FrontReadOptions& options) {
  json doc;
  try {
    doc = json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {
    throw Error(std::string("not valid JSON: ") + e.what(), SourceLocation{path});
  }
  return front_file_from_json(doc, path, options);
}

FrontFile front_file_from_json(const json& doc, const std::string& path,
                               const FrontReadOptions& options) {
  if (!doc.is_object() || !doc.contains("front") || !doc["front"].is_array())
    throw Error("expected an object with a \"front\" list", SourceLocation{path});
  FrontFile out;
  out.inputs = options.inputs;
  if (out.inputs.empty() && doc.contains("inputs")) {
    if (!doc["inputs"].is_array())
      throw Error("\"inputs\" must be a list of names", SourceLocation{path});
    for (const auto& n : doc["inputs"]) {
      if (!n.is_string()) throw Error("\"inputs\" must be a list of names", SourceLocation{path});
      out.inputs.push_back(n.get<std::string>());
    }
  }
  if (doc.contains("uniform")) {
    if (!doc["uniform"].is_array())
      throw Error("\"uniform\" must be a list of names", SourceLocation{path});
    for (const auto& n : doc["uniform"]) {
      if (!n.is_string()) throw Error("\"uniform\" must be a list of names", SourceLocation{path});
      out.uniform.push_back(n.get<std::string>());
    }
  }
  const auto& front = doc["front"];
  for (std::size_t i = 0; i < front.size(); ++i) {
    const std::string where = path + ": front[" + std::to_string(i) + "]";
    try {
      out.front.push_back(front_member_from_json(front[i], out.inputs, options, where));
    } catch (const Error&) {
      throw;
    } catch (const std::exception& e) {
      throw Error(std::string("not a front member: ") + e.what(), SourceLocation{where});
    }
  }
  return out;
}

}  // namespace shaderfit
