// Which member of a Pareto front is "the chosen formula" (the report's, the search's closing
// line): the rule is written here once; the command line maps its --choose flag to it.
//
//   ChoiceRule rule = parse_choice_rule("cost=6", {"ChoiceRule"});   // or ChoiceRule{} (the knee)
//   Choice c = choose_member(summary.front, rule, "mse");
//   std::cout << summary.front[c.index].formula << ": " << c.why << "\n";
//
// The knee (the default): on the front drawn as log10(error) against cost, both scaled to
// [0, 1] between the cheapest and the most accurate member, the member farthest below the
// straight line joining those two, i.e. where spending more cost stops buying much accuracy.
// A front with no member below that line (two members, or a straight or bulging front) has no
// knee; its most accurate member is chosen. Errors of 0 count as 1e-300.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "shaderfit/core/error.hpp"
#include "shaderfit/search/front_member.hpp"

namespace shaderfit {

struct ChoiceRule {
  enum class Kind {
    Knee,      // the knee of the front (the default)
    MaxCost,   // the most accurate member that costs at most `limit`
    MaxError,  // the cheapest member whose error is at most `limit`
  } kind = Kind::Knee;
  double limit = 0;
};

// Whether `text` is written as a rule: "knee", or "cost=..." or "error=..." (anything else may
// be, say, a formula).
bool is_choice_rule(std::string_view text);

// "knee", "cost=N" or "error=E" (a finite number >= 0). Throws shaderfit::Error located at
// `where` for anything else.
ChoiceRule parse_choice_rule(std::string_view text, const SourceLocation& where);

// The rule as parse_choice_rule reads it: "knee", "cost=5", "error=0.001".
std::string choice_rule_text(const ChoiceRule& rule);

// The rule in words, e.g. "the knee of the front (the default)".
std::string choice_rule_description(const ChoiceRule& rule);

struct Choice {
  std::size_t index = 0;  // into the front
  std::string why;        // one line: why this member, with the figures that decided it
};

// The member `rule` picks from `front` (cheapest first, as a search returns it), its error being
// member.loss, or metrics.mse where loss is NaN, named `error_name` in `why`. Members without a
// cost or an error are passed over; when none has both, the last member is chosen. The knee
// passes over the reference's own member (origin "reference") while there is another. When no
// member meets a cost or error limit, the nearest is chosen (the cheapest, the most accurate) and
// `why` says so. Throws shaderfit::Error for an empty front.
Choice choose_member(std::span<const FrontMember> front, const ChoiceRule& rule,
                     std::string_view error_name = "error");

}  // namespace shaderfit
