#include "shaderfit/report/search_json.hpp"

#include <nlohmann/json.hpp>

#include "core/overloaded.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit {

nlohmann::json search_options_json(const SearchOptions& o) {
  using nlohmann::json;
  using O = SearchOptions;
  json out = json::object();
  for (const SearchOptionField& f : search_option_fields()) {
    out[std::string(f.name)] = std::visit(
        Overloaded{[&](std::string O::*m) { return json(o.*m); },
                   [&](std::optional<std::int64_t> O::*m) { return o.*m ? json(*(o.*m)) : json(); },
                   [&](std::optional<SearchTarget> O::*m) {
                     return o.*m ? json{{"max_loss", (o.*m)->max_loss},
                                        {"max_cost", (o.*m)->max_cost}}
                                 : json();
                   },
                   [&](std::vector<double> O::*m) { return json(o.*m); },
                   [&](std::vector<Op> O::*) { return json(search_option_text(o, f)); },
                   [&](Loss O::*) { return json(search_option_text(o, f)); },
                   [&](CostTarget O::*) { return json(search_option_text(o, f)); },
                   [&](ComputeDevice O::*) { return json(search_option_text(o, f)); },
                   [&](Precision O::*) { return json(search_option_text(o, f)); },
                   [&](auto m) { return json(o.*m); }},
        f.member);
  }
  return out;
}

std::string search_json(const SearchSummary& s, const SearchOptions& o, const SearchDataInfo& d) {
  using nlohmann::json;
  json front = json::array();
  for (const FrontMember& m : s.front) front.push_back(front_member_json(m, FrontJson::Result));
  json out = {{"inputs", d.inputs},
              {"data",
               {{"source", d.source},
                {"rows", d.rows},
                {"target", d.target},
                {"load_time_s", d.load_time_s}}},
              {"problem", d.problem ? problem_source_json(*d.problem) : json(nullptr)},
              {"uniform", o.uniform},
              {"options", search_options_json(o)},
              {"summary",
               {{"termination", termination_name(s.termination)},
                {"interrupted", s.interrupted},
                {"total_time_s", s.total_time_s},
                {"enumeration_time_s", s.enumeration_time_s},
                {"evolution_time_s", s.evolution_time_s},
                {"candidates", s.candidates},
                {"node_evaluations", s.node_evaluations},
                {"distinct_candidates", s.distinct_candidates},
                {"enumeration_cost_completed", s.enumeration_cost_completed},
                {"generations", s.generations},
                {"check_time_s", s.check_time_s},
                {"dropped_not_finite", s.dropped_not_finite},
                {"dropped_no_bound", s.dropped_no_bound},
                {"dropped_notes", s.dropped_notes},
                {"ranks", s.ranks},
                {"bytes_sent", s.bytes_sent},
                {"bytes_per_rank", s.bytes_per_rank},
                {"symmetry",
                 s.symmetry ? json{{"input", s.symmetry->input_name},
                                   {"kind", symmetry_kind_name(s.symmetry->kind)},
                                   {"center", s.symmetry->center},
                                   {"sign", s.symmetry->sign},
                                   {"method", symmetry_method_name(s.symmetry->evidence.method)},
                                   {"rows_compared", s.symmetry->evidence.rows_compared},
                                   {"max_residual", s.symmetry->evidence.max_residual},
                                   {"noise", s.symmetry->evidence.noise}}
                            : json(nullptr)}}},
              {"front", front}};
  return out.dump(2) + "\n";
}

nlohmann::json problem_source_json(const ProblemSource& p) {
  using nlohmann::json;
  json j = json::object();
  if (!p.csv_path.empty()) j["data"] = p.csv_path;
  if (!p.dataset.empty()) {
    j["dataset"] = p.dataset;
    j["dataset_seed"] = p.dataset_seed;
  }
  const reference::ReferenceText& r = p.reference;
  if (!r.formula.empty()) j["reference"] = r.formula;
  if (!r.shader_source.empty()) {
    j["reference_file"] = r.shader_path;
    j["function"] = r.function;
    j["shader_source"] = r.shader_source;
  }
  if (!r.definitions.empty()) j["define"] = r.definitions;
  if (!p.domain.empty()) j["domain"] = p.domain;
  if (p.samples != 0) j["samples"] = p.samples;
  if (p.drop_nonfinite) j["drop_nonfinite"] = true;
  if (p.drop_missing_rows) j["drop_missing"] = true;
  if (p.scene) {
    const SceneSpec& s = *p.scene;
    json scene = {{"kind", scene_kind_name(s.kind)}, {"size", s.size}, {"exposure", s.exposure}};
    if (s.term) scene["term"] = shading_term_name(*s.term);
    if (!s.materials.empty()) {
      scene["materials"] = json::array();
      for (const SceneMaterial& m : s.materials)
        scene["materials"].push_back({{"roughness", m.roughness}, {"f0", m.f0}});
    }
    j["scene"] = scene;
  }
  j["inputs"] = p.inputs;
  j["target"] = p.target;
  return j;
}

ProblemSource problem_source_from_json(const nlohmann::json& j, const std::string& where) {
  auto bad = [&](const std::string& why) -> Error {
    return Error("\"problem\": " + why, SourceLocation{where});
  };
  if (!j.is_object()) throw bad("not an object");
  ProblemSource p;
  auto text = [&](const char* key, std::string* out) {
    if (!j.contains(key)) return;
    if (!j[key].is_string()) throw bad(std::string("\"") + key + "\" is not text");
    *out = j[key].get<std::string>();
  };
  auto texts = [&](const char* key, std::vector<std::string>* out) {
    if (!j.contains(key)) return;
    if (!j[key].is_array()) throw bad(std::string("\"") + key + "\" is not a list");
    for (const auto& v : j[key]) {
      if (!v.is_string()) throw bad(std::string("\"") + key + "\" holds something not text");
      out->push_back(v.get<std::string>());
    }
  };
  auto count = [&](const char* key, auto* out) {
    if (!j.contains(key)) return;
    if (!j[key].is_number_unsigned()) throw bad(std::string("\"") + key + "\" is not a count");
    *out = j[key].get<std::remove_pointer_t<decltype(out)>>();
  };
  text("data", &p.csv_path);
  text("dataset", &p.dataset);
  count("dataset_seed", &p.dataset_seed);
  text("reference", &p.reference.formula);
  text("reference_file", &p.reference.shader_path);
  text("function", &p.reference.function);
  text("shader_source", &p.reference.shader_source);
  texts("define", &p.reference.definitions);
  texts("domain", &p.domain);
  count("samples", &p.samples);
  if (j.contains("drop_nonfinite")) {
    if (!j["drop_nonfinite"].is_boolean()) throw bad("\"drop_nonfinite\" is not true or false");
    p.drop_nonfinite = j["drop_nonfinite"].get<bool>();
  }
  if (j.contains("drop_missing")) {
    if (!j["drop_missing"].is_boolean()) throw bad("\"drop_missing\" is not true or false");
    p.drop_missing_rows = j["drop_missing"].get<bool>();
  }
  if (j.contains("scene")) {
    const nlohmann::json& s = j["scene"];
    if (!s.is_object()) throw bad("\"scene\" is not an object");
    SceneSpec spec;
    const std::optional<SceneKind> kind =
        scene_kind_from_name(s.value("kind", std::string("sphere")));
    if (!kind) throw bad("\"scene\": an unknown kind");
    spec.kind = *kind;
    if (s.contains("term")) {
      spec.term = shading_term_from_name(s.value("term", std::string()));
      if (!spec.term) throw bad("\"scene\": an unknown term");
    }
    if (s.contains("size") && s["size"].is_number_integer()) spec.size = s["size"].get<int>();
    if (s.contains("exposure") && s["exposure"].is_number())
      spec.exposure = s["exposure"].get<double>();
    if (s.contains("materials") && s["materials"].is_array())
      for (const nlohmann::json& m : s["materials"])
        spec.materials.push_back(
            {m.value("roughness", SceneMaterial{}.roughness), m.value("f0", SceneMaterial{}.f0)});
    p.scene = spec;
  }
  texts("inputs", &p.inputs);
  text("target", &p.target);
  return p;
}

}  // namespace shaderfit
