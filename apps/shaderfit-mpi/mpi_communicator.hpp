// shaderfit's Communicator (shaderfit/search/communicator.hpp) over MPI. Waits poll with short
// sleeps instead of MPI's busy wait, so that a rank waiting for the others leaves its core to
// the search threads of ranks that share the machine.
#pragma once

#include <mpi.h>

#include <list>
#include <optional>
#include <string>
#include <utility>

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
  void send(int to, std::string_view bytes) override;
  std::optional<std::pair<int, std::string>> receive(double timeout_s) override;
  void forget(int rank) override;
  [[nodiscard]] bool lost() const override { return lost_; }

 private:
  // Completes the sends that have completed; a send to a dead rank stays pending.
  void reap_sends();

  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  struct PendingSend {
    std::string bytes;
    MPI_Request request = MPI_REQUEST_NULL;
  };
  std::list<PendingSend> sends_;  // stable addresses: MPI reads the bytes until it completes
  bool lost_ = false;
};

}  // namespace shaderfit::mpi
