#include "search/distributed.hpp"

#include <string>

namespace shaderfit::search_detail {

namespace {

std::string encode(const nlohmann::json& j) {
  const std::vector<std::uint8_t> bytes = nlohmann::json::to_cbor(j);
  return {bytes.begin(), bytes.end()};
}

nlohmann::json decode(const std::string& bytes) {
  return nlohmann::json::from_cbor(bytes.begin(), bytes.end());
}

}  // namespace

std::vector<nlohmann::json> RankGroup::all_gather(const nlohmann::json& mine) {
  const std::string bytes = encode(mine);
  bytes_sent_ += bytes.size();
  std::vector<nlohmann::json> out;
  const std::vector<std::string> all = comm_->all_gather(bytes);
  for (std::size_t r = 0; r < all.size(); ++r) {
    if (static_cast<int>(r) != rank()) bytes_received_ += all[r].size();
    out.push_back(decode(all[r]));
  }
  return out;
}

nlohmann::json RankGroup::broadcast(const nlohmann::json& value, int root) {
  std::string bytes;
  if (rank() == root) {
    bytes = encode(value);
    bytes_sent_ += bytes.size();
  }
  const std::string got = comm_->broadcast(bytes, root);
  if (rank() != root) bytes_received_ += got.size();
  return decode(got);
}

std::vector<nlohmann::json> RankGroup::exchange(
    const std::vector<std::pair<int, nlohmann::json>>& sends, const std::vector<int>& from) {
  std::vector<std::pair<int, std::string>> encoded;
  for (const auto& [to, j] : sends) {
    encoded.emplace_back(to, encode(j));
    bytes_sent_ += encoded.back().second.size();
  }
  std::vector<nlohmann::json> out;
  for (const std::string& b : comm_->exchange(encoded, from)) {
    bytes_received_ += b.size();
    out.push_back(decode(b));
  }
  return out;
}

std::vector<nlohmann::json> RankGroup::gather(const nlohmann::json& mine) {
  if (!leader()) {
    (void)exchange({{0, mine}}, {});
    return {};
  }
  std::vector<int> from;
  for (int r = 1; r < size(); ++r) from.push_back(r);
  std::vector<nlohmann::json> out = exchange({}, from);
  out.insert(out.begin(), mine);
  return out;
}

std::vector<std::string> RankGroup::all_gather_bytes(std::string_view mine) {
  bytes_sent_ += mine.size();
  std::vector<std::string> all = comm_->all_gather(mine);
  for (std::size_t r = 0; r < all.size(); ++r)
    if (static_cast<int>(r) != rank()) bytes_received_ += all[r].size();
  return all;
}

}  // namespace shaderfit::search_detail
