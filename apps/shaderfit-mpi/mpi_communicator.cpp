#include "mpi_communicator.hpp"

#include <chrono>
#include <climits>
#include <stdexcept>
#include <thread>

namespace shaderfit::mpi {

namespace {

constexpr int kExchangeTag = 17;
constexpr int kMessageTag = 23;

// Waits for `request`, sleeping between tests: a waiting rank uses almost no CPU.
void wait(MPI_Request& request) {
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done != 0) return;
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
}

int byte_count(std::size_t n) {
  if (n > static_cast<std::size_t>(INT_MAX))
    throw std::length_error("an MPI message of more than 2 GiB");
  return static_cast<int>(n);
}

}  // namespace

MpiCommunicator::MpiCommunicator(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  // A rank that dies must not end the others' calls with an abort (batch: its entry is handed
  // out again; mpirun must be asked to keep the job, --mca orte_enable_recovery 1).
  MPI_Comm_set_errhandler(comm_, MPI_ERRORS_RETURN);
}

void MpiCommunicator::reap_sends() {
  for (auto it = sends_.begin(); it != sends_.end();) {
    int done = 0;
    MPI_Test(&it->request, &done, MPI_STATUS_IGNORE);
    it = done != 0 ? sends_.erase(it) : std::next(it);
  }
}

void MpiCommunicator::send(int to, std::string_view bytes) {
  reap_sends();
  PendingSend& p = sends_.emplace_back();
  p.bytes = std::string(bytes);
  MPI_Isend(p.bytes.data(), byte_count(p.bytes.size()), MPI_BYTE, to, kMessageTag, comm_,
            &p.request);
}

std::optional<std::pair<int, std::string>> MpiCommunicator::receive(double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    reap_sends();
    int ready = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kMessageTag, comm_, &ready, &status);
    if (ready != 0) {
      int n = 0;
      MPI_Get_count(&status, MPI_BYTE, &n);
      std::string message(static_cast<std::size_t>(n), '\0');
      MPI_Recv(message.data(), n, MPI_BYTE, status.MPI_SOURCE, kMessageTag, comm_,
               MPI_STATUS_IGNORE);
      return std::pair{status.MPI_SOURCE, std::move(message)};
    }
    if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

void MpiCommunicator::forget(int /*rank*/) { lost_ = true; }

std::vector<std::string> MpiCommunicator::all_gather(std::string_view mine) {
  int n = byte_count(mine.size());
  std::vector<int> sizes(static_cast<std::size_t>(size_));
  MPI_Request request;
  MPI_Iallgather(&n, 1, MPI_INT, sizes.data(), 1, MPI_INT, comm_, &request);
  wait(request);
  std::vector<int> offsets(sizes.size());
  std::size_t total = 0;
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    offsets[r] = byte_count(total);
    total += static_cast<std::size_t>(sizes[r]);
  }
  std::string all(total, '\0');
  MPI_Iallgatherv(mine.data(), n, MPI_BYTE, all.data(), sizes.data(), offsets.data(), MPI_BYTE,
                  comm_, &request);
  wait(request);
  std::vector<std::string> out;
  for (std::size_t r = 0; r < sizes.size(); ++r)
    out.emplace_back(
        all.substr(static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(sizes[r])));
  return out;
}

std::string MpiCommunicator::broadcast(std::string_view bytes, int root) {
  unsigned long long n = rank_ == root ? bytes.size() : 0;
  MPI_Request request;
  MPI_Ibcast(&n, 1, MPI_UNSIGNED_LONG_LONG, root, comm_, &request);
  wait(request);
  std::string out = rank_ == root ? std::string(bytes) : std::string(n, '\0');
  MPI_Ibcast(out.data(), byte_count(n), MPI_BYTE, root, comm_, &request);
  wait(request);
  return out;
}

std::vector<std::string> MpiCommunicator::exchange(
    const std::vector<std::pair<int, std::string>>& sends, const std::vector<int>& from) {
  std::vector<MPI_Request> sent(sends.size());
  for (std::size_t i = 0; i < sends.size(); ++i)
    MPI_Isend(sends[i].second.data(), byte_count(sends[i].second.size()), MPI_BYTE, sends[i].first,
              kExchangeTag, comm_, &sent[i]);
  std::vector<std::string> out;
  for (int source : from) {
    MPI_Status status;
    for (int ready = 0;;) {
      MPI_Iprobe(source, kExchangeTag, comm_, &ready, &status);
      if (ready != 0) break;
      std::this_thread::sleep_for(std::chrono::microseconds(50));
    }
    int n = 0;
    MPI_Get_count(&status, MPI_BYTE, &n);
    std::string message(static_cast<std::size_t>(n), '\0');
    MPI_Recv(message.data(), n, MPI_BYTE, source, kExchangeTag, comm_, MPI_STATUS_IGNORE);
    out.push_back(std::move(message));
  }
  for (MPI_Request& r : sent) wait(r);
  return out;
}

}  // namespace shaderfit::mpi
