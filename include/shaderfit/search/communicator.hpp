// What a search needs from a group of processes that run it together (docs/distributed.md): the
// library's view of MPI, implemented by shaderfit-mpi (apps/shaderfit-mpi/) over Open MPI, so
// that the library itself neither links nor knows MPI.
//
//   SearchOptions o;
//   o.communicator = &mpi;   // every rank runs run_search with the same data and options
//   run_search(o, problem, &summary);   // rank 0's summary holds the front; others' are empty
//
// Every call is collective or paired as documented: each rank makes the same calls in the same
// order. Messages are bytes; the search encodes them (CBOR) and counts what it sends.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace shaderfit {

class Communicator {
 public:
  virtual ~Communicator() = default;

  [[nodiscard]] virtual int rank() const = 0;  // 0 .. size() - 1
  [[nodiscard]] virtual int size() const = 0;

  // Every rank's `mine`, in rank order, on every rank (collective).
  virtual std::vector<std::string> all_gather(std::string_view mine) = 0;
  // `root`'s `bytes` on every rank (collective; the others' argument is ignored).
  virtual std::string broadcast(std::string_view bytes, int root) = 0;
  // Point to point (collective over the ranks that take part: every rank calls it): sends
  // `sends` (to rank, bytes) without waiting for their receipt, then receives one message from
  // each rank in `from`, returned in that order.
  virtual std::vector<std::string> exchange(const std::vector<std::pair<int, std::string>>& sends,
                                            const std::vector<int>& from) = 0;

  // Messages between any two ranks, for work handed out as ranks become free (a batch,
  // batch/batch.hpp), apart from the messages above: send returns at once (the bytes are copied)
  // and never waits for the receiver; receive returns the next message sent to this rank by any
  // rank, with its sender, waiting at most `timeout_s`, or nullopt when none came.
  virtual void send(int to, std::string_view bytes) = 0;
  virtual std::optional<std::pair<int, std::string>> receive(double timeout_s) = 0;
  // `rank` is taken for dead (it stopped answering; -1: one this rank did not talk to): no
  // collective call follows, and the process ends without waiting for it (lost() tells the
  // program to).
  virtual void forget(int rank) = 0;
  [[nodiscard]] virtual bool lost() const = 0;
};

}  // namespace shaderfit
