#include "shaderfit/search/front/choice.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <vector>

namespace shaderfit {

namespace {

double error_of(const FrontMember& m) { return std::isnan(m.loss) ? m.metrics.mse : m.loss; }

bool scored(const FrontMember& m) { return std::isfinite(m.cost) && !std::isnan(error_of(m)); }

std::string_view value_after(std::string_view text, std::string_view key) {
  return text.substr(key.size());
}

}  // namespace

bool is_choice_rule(std::string_view text) {
  return text == "knee" || text.starts_with("cost=") || text.starts_with("error=");
}

ChoiceRule parse_choice_rule(std::string_view text, const SourceLocation& where) {
  if (text == "knee") return {};
  ChoiceRule rule;
  std::string_view value;
  if (text.starts_with("cost=")) {
    rule.kind = ChoiceRule::Kind::MaxCost;
    value = value_after(text, "cost=");
  } else if (text.starts_with("error=")) {
    rule.kind = ChoiceRule::Kind::MaxError;
    value = value_after(text, "error=");
  } else {
    throw Error("unknown choice '" + std::string(text) + "' (known: knee, cost=N, error=E)", where);
  }
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), rule.limit);
  if (value.empty() || ec != std::errc() || end != value.data() + value.size() ||
      !std::isfinite(rule.limit) || rule.limit < 0)
    throw Error("expected a number >= 0 after '" +
                    std::string(text.substr(0, text.size() - value.size())) + "', got '" +
                    std::string(value) + "'",
                where);
  return rule;
}

std::string choice_rule_text(const ChoiceRule& rule) {
  switch (rule.kind) {
    case ChoiceRule::Kind::MaxCost: return fmt::format("cost={:g}", rule.limit);
    case ChoiceRule::Kind::MaxError: return fmt::format("error={:g}", rule.limit);
    case ChoiceRule::Kind::Knee: break;
  }
  return "knee";
}

std::string choice_rule_description(const ChoiceRule& rule) {
  switch (rule.kind) {
    case ChoiceRule::Kind::MaxCost:
      return fmt::format("the most accurate member that costs at most {:g}", rule.limit);
    case ChoiceRule::Kind::MaxError:
      return fmt::format("the cheapest member whose error is at most {:g}", rule.limit);
    case ChoiceRule::Kind::Knee: break;
  }
  return "the knee of the front (the default): where more cost stops buying much accuracy";
}

Choice choose_member(std::span<const FrontMember> front, const ChoiceRule& rule,
                     std::string_view error_name) {
  if (front.empty()) throw Error("no front to choose from: it is empty");
  std::vector<std::size_t> members;  // scored, cheapest first
  for (std::size_t i = 0; i < front.size(); ++i)
    if (scored(front[i])) members.push_back(i);
  if (members.empty())
    return {front.size() - 1, "the front has no costs or errors; its last member"};
  std::stable_sort(members.begin(), members.end(),
                   [&](std::size_t a, std::size_t b) { return front[a].cost < front[b].cost; });
  const auto cost = [&](std::size_t i) { return front[i].cost; };
  const auto err = [&](std::size_t i) { return error_of(front[i]); };
  // The most accurate member (the cheapest of equals).
  std::size_t best = members.front();
  for (std::size_t i : members)
    if (err(i) < err(best)) best = i;
  std::size_t cheapest = members.front();

  switch (rule.kind) {
    case ChoiceRule::Kind::MaxCost: {
      std::size_t pick = front.size();
      for (std::size_t i : members)
        if (cost(i) <= rule.limit && (pick == front.size() || err(i) < err(pick))) pick = i;
      if (pick == front.size())
        return {cheapest, fmt::format("no member costs at most {:g}; the cheapest costs {:g}",
                                      rule.limit, cost(cheapest))};
      return {pick,
              fmt::format("the most accurate member costing at most {:g}: {} {:.3g} at cost {:g}",
                          rule.limit, error_name, err(pick), cost(pick))};
    }
    case ChoiceRule::Kind::MaxError: {
      for (std::size_t i : members)
        if (err(i) <= rule.limit)
          return {i, fmt::format("the cheapest member with {} at most {:g}: {} {:.3g} at cost {:g}",
                                 error_name, rule.limit, error_name, err(i), cost(i))};
      return {best, fmt::format("no member has {} at most {:g}; the most accurate has {:.3g}",
                                error_name, rule.limit, err(best))};
    }
    case ChoiceRule::Kind::Knee: break;
  }
  // The knee is a formula to use instead of the reference: the reference's own member (the
  // function as written) takes no part while there is another, nor do the minor steps the front
  // does not show (a cost or error limit above takes the best of every member).
  // One other member alone is no front to find a knee on: beside the reference (a constant,
  // say) it is chosen only where it is as accurate.
  std::vector<std::size_t> others;
  for (std::size_t i : members)
    if (front[i].origin != SearchPhase::Reference && !front[i].minor_step) others.push_back(i);
  if (others.size() == 1 && others.size() < members.size() && err(best) < err(others[0]) &&
      front[best].origin == SearchPhase::Reference) {
    return {best, fmt::format("the only other member (cost {:g}) has {} {:.3g}: the reference as "
                              "written, {} {:.3g} at cost {:g}",
                              cost(others[0]), error_name, err(others[0]), error_name, err(best),
                              cost(best))};
  }
  if (!others.empty() && others.size() < members.size()) {
    members = std::move(others);
    cheapest = best = members.front();
    for (std::size_t i : members)
      if (err(i) < err(best)) best = i;
  }

  if (members.size() == 1 || cost(best) <= cost(cheapest) || !(err(best) < err(cheapest)))
    return {best, fmt::format("the front has one point that matters: {} {:.3g} at cost {:g}",
                              error_name, err(best), cost(best))};
  const auto log_err = [&](std::size_t i) { return std::log10(std::max(err(i), 1e-300)); };
  const double c0 = cost(cheapest), c1 = cost(best), e0 = log_err(cheapest), e1 = log_err(best);
  std::size_t knee = best;
  double farthest = 1e-9;  // below the line by more than rounding
  for (std::size_t i : members) {
    if (cost(i) > c1) continue;  // costlier than the most accurate: not on the front proper
    const double u = (cost(i) - c0) / (c1 - c0), v = (log_err(i) - e1) / (e0 - e1);
    const double below = 1 - u - v;
    if (below > farthest) {
      farthest = below;
      knee = i;
    }
  }
  if (knee == best)
    return {best,
            fmt::format("the front has no knee (no member lies below the line from the "
                        "cheapest to the most accurate); the most accurate: {} {:.3g} at cost {:g}",
                        error_name, err(best), cost(best))};
  const double first = err(cheapest) / std::max(err(knee), 1e-300),
               further = err(knee) / std::max(err(best), 1e-300);
  return {knee,
          fmt::format("the knee of the front: cost {:g} cuts the {} {:.3g}x from the cheapest "
                      "member (cost {:g}); the most accurate (cost {:g}) cuts it {}{:.3g}x more",
                      cost(knee), error_name, first, c0, c1, further < first ? "only " : "",
                      further)};
}

}  // namespace shaderfit
