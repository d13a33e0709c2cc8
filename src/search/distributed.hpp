// The search's side of a Communicator (internal; docs/distributed.md): which rank owns which
// island, and messages as CBOR, counting the bytes this rank sends.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "shaderfit/search/communicator.hpp"

namespace shaderfit::search_detail {

class RankGroup {
 public:
  explicit RankGroup(Communicator* communicator) : comm_(communicator) {}

  // More than one rank: the search is split across them.
  [[nodiscard]] bool distributed() const { return comm_ != nullptr && comm_->size() > 1; }
  [[nodiscard]] int rank() const { return distributed() ? comm_->rank() : 0; }
  [[nodiscard]] int size() const { return distributed() ? comm_->size() : 1; }
  // Rank 0: keeps the front, runs the start formulas, writes checkpoints and reports.
  [[nodiscard]] bool leader() const { return rank() == 0; }
  // The rank that evolves island `island`: round robin. The islands that receive the front's
  // members as seeds (the first ones) are the slowest to evolve, so blocks of consecutive
  // islands would leave the first rank with the most work.
  [[nodiscard]] int owner(std::size_t island) const {
    return static_cast<int>(island % static_cast<std::size_t>(size()));
  }

  // As Communicator's, on JSON values sent as CBOR.
  std::vector<nlohmann::json> all_gather(const nlohmann::json& mine);
  nlohmann::json broadcast(const nlohmann::json& value, int root);
  std::vector<nlohmann::json> exchange(const std::vector<std::pair<int, nlohmann::json>>& sends,
                                       const std::vector<int>& from);
  // Every rank's `mine` at rank 0, in rank order (rank 0's own first); the others get an empty
  // list. A reduction's first half: what each rank sends does not grow with the ranks.
  std::vector<nlohmann::json> gather(const nlohmann::json& mine);
  // all_gather of raw bytes, for bulk data (the enumeration's classes).
  std::vector<std::string> all_gather_bytes(std::string_view mine);

  // The bytes this rank has sent and received (payloads; an all-gather's own part not received).
  [[nodiscard]] std::uint64_t bytes_sent() const { return bytes_sent_; }
  [[nodiscard]] std::uint64_t bytes_received() const { return bytes_received_; }

 private:
  Communicator* comm_;
  std::uint64_t bytes_sent_ = 0, bytes_received_ = 0;
};

}  // namespace shaderfit::search_detail
