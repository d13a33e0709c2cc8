#include "shaderfit/report/search_json.hpp"

#include <nlohmann/json.hpp>

#include "core/overloaded.hpp"

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
                {"ranks", s.ranks},
                {"bytes_sent", s.bytes_sent},
                {"symmetry", s.symmetry ? json{{"input", s.symmetry->input_name},
                                               {"kind", symmetry_kind_name(s.symmetry->kind)},
                                               {"center", s.symmetry->center},
                                               {"sign", s.symmetry->sign}}
                                        : json(nullptr)}}},
              {"front", front}};
  return out.dump(2) + "\n";
}

}  // namespace shaderfit
