// A search on the half of symmetric data, seen from the whole data (internal; docs/search.md,
// "Symmetric data"): run_search searches symmetric_half(problem) and this turns what it finds
// into formulas for every row.
//
//   SymmetricFront whole(options, problem, symmetry);
//   half_options.on_new_member = whole.forward_new_members();   // reflected as they come
//   ... search the half into `summary` ...
//   whole.finish(starts, &summary);   // the front of the whole data
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "search/search_context.hpp"
#include "search/starts/start.hpp"
#include "shaderfit/search/symmetry.hpp"

namespace shaderfit::search_detail {

class SymmetricFront {
 public:
  // `options` and `problem` (the whole data) must outlive this.
  SymmetricFront(const SearchOptions& options, const SearchProblem& problem,
                 const DataSymmetry& symmetry);

  // A member found on the half, reflected and scored on every row (cost, metrics, loss);
  // its time and origin are kept.
  FrontMember reflected(const FrontMember& half);

  // options.on_new_member called with each new member of the half reflected; empty when
  // options.on_new_member is.
  std::function<void(const FrontMember&)> forward_new_members();

  // Replaces summary->front (the half's) by the front of the whole data: each half member
  // reflected and as it is (m + g for point symmetry), the start formulas (fitted on every row),
  // scored on every row, float32-checked; sets summary->symmetry and adds the evaluations.
  void finish(const std::vector<StartFormula>& starts, SearchSummary* summary);

 private:
  SearchOptions options_;  // the caller's, without callbacks or stop target
  const std::function<void(const FrontMember&)>& on_new_member_;
  DataSymmetry symmetry_;
  SearchContext whole_;
};

}  // namespace shaderfit::search_detail
