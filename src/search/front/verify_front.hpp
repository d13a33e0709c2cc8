// The front checked against the function behind the data (internal; docs/reference.md, "Worst
// case" and "Certification"): run_search's last step where SearchProblem::reference is set.
//
//   summary.front = verify_front(options, problem, std::move(summary.front), &summary);
#pragma once

#include <vector>

#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

// Each member's max error searched for between the samples (WorstCaseSearch). Where it exceeds
// the error at the rows by more than kRefitExcess (relative), the worst points join the member's
// rows (a subset of the problem's: every k-th row and those near its largest error) and its
// parameters are refitted for options.loss, kept when the error found everywhere falls; again
// until it no longer does or kMaxRefits rounds. metrics.max_abs and max_rel then hold the
// largest error found, mse and the others stay on the rows; the loss is recomputed, float32
// errors include the points checked. Members NaN or infinite somewhere are dropped (counted in
// summary->dropped_not_finite); with options.certify each remaining member is certified. The
// front is then recomputed (a member whose loss rose may now be dominated), cheapest first.
// Members are checked in parallel (options.threads). Adds summary->check_time_s.
inline constexpr int kMaxRefits = 4;
inline constexpr double kRefitExcess = 1e-3;
std::vector<FrontMember> verify_front(const SearchOptions& options, const SearchProblem& problem,
                                      std::vector<FrontMember> front, SearchSummary* summary);

}  // namespace shaderfit::search_detail
