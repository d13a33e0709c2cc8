// shaderfit's Communicator (shaderfit/search/communicator.hpp) over MPI. Waits poll with short
// sleeps instead of MPI's busy wait, so that a rank waiting for the others leaves its core to
// the search threads of ranks that share the machine.
#pragma once

#include <mpi.h>

#include "shaderfit/search/communicator.hpp"

namespace shaderfit::mpi {

class MpiCommunicator final : public Communicator {
 public:
  explicit MpiCommunicator(MPI_Comm comm);

  [[nodiscard]] int rank() const override { return rank_; }
  [[nodiscard]] int size() const override { return size_; }
  std::vector<std::string> all_gather(std::string_view mine) override;
  std::string broadcast(std::string_view bytes, int root) override;
  std::vector<std::string> exchange(const std::vector<std::pair<int, std::string>>& sends,
                                    const std::vector<int>& from) override;

 private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
};

}  // namespace shaderfit::mpi
