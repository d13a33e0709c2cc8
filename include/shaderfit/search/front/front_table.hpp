// Search results for people: the front as a table, and the line printed for each new member.
// (For programs: shaderfit/report/search_json.hpp.)
//
//   SearchSummary s;
//   run_search(options, problem, &s);
//   std::cout << front_table(s);
#pragma once

#include <string>

#include "shaderfit/expr/print.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {

// The search's termination, times and counts: the lines before the table in
// SearchSummary::brief_report.
std::string search_summary_lines(const SearchSummary& summary);

// The front as a table: cost, nodes, the loss (unless it is mse or max_abs, shown anyway), mse,
// max_abs, when found, and the formula (printed with `print`), marked "!" (with a note below the
// table) when it is not stable in float32. Members marked FrontMember::minor_step are left out
// and counted in a line below the table.
std::string front_table(const SearchSummary& summary, Loss loss = Loss::Mse,
                        const PrintOptions& print = PrintOptions::for_people());

// One line for a new front member, as printed while searching:
//   "[28.1 ms] mse=3.43e-04 cost=4  r0 + (x - r0) * x^4"
std::string front_member_line(const FrontMember& m, Loss loss,
                              const PrintOptions& print = PrintOptions::for_people());

}  // namespace shaderfit
