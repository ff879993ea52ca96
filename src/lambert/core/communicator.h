#pragma once
// What a distributed solve asks of the processes it runs on (docs/distributed.md): every rank
// runs the same program on the same scene, and they meet in collective calls, each made by every
// rank in the same order. MPI stands behind it (distributed/mpi_communicator.h, OpenMPI from
// Debian); the library sees only this interface, so that it builds and links without MPI. The
// library calls it from one thread at a time.
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "lambert/core/error.h"

namespace lambert {

// What this rank has communicated so far.
struct CommunicationStats {
  std::uint64_t bytesSent = 0;      // this rank's own values handed to the others
  std::uint64_t bytesReceived = 0;  // the others' values received
  std::uint64_t calls = 0;          // collective calls
  double seconds = 0;               // wall time inside the collective calls (waiting included)
};

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Every rank's records in rank order into `all`: counts[r] records of recordBytes each from
  // rank r, this rank's counts[rank()] from `mine` (all ranks pass the same counts and size).
  virtual void allGatherRecords(const void* mine, std::span<const int> counts, void* all, std::size_t recordBytes) = 0;
  // The same for values of a trivially copyable type: all.size() is the counts' sum.
  template <class T>
  void allGather(std::span<const T> mine, std::span<const int> counts, std::span<T> all) {
    static_assert(std::is_trivially_copyable_v<T>);
    LAMBERT_CHECK(static_cast<std::size_t>(counts[static_cast<std::size_t>(rank())]) == mine.size());
    allGatherRecords(mine.data(), counts, all.data(), sizeof(T));
  }
  // Every rank's values, however many each has, in rank order (their counts gathered first).
  template <class T>
  std::vector<T> allGatherVariable(std::span<const T> mine) {
    std::vector<int> ones(static_cast<std::size_t>(size()), 1), counts(static_cast<std::size_t>(size()));
    const int count = static_cast<int>(mine.size());
    allGather<int>(std::span<const int>(&count, 1), ones, counts);
    std::size_t total = 0;
    for (int n : counts) total += static_cast<std::size_t>(n);
    std::vector<T> all(total);
    allGather<T>(mine, counts, all);
    return all;
  }
  // values[i] ← the largest values[i] over the ranks, on every rank.
  virtual void maxAll(std::span<double> values) = 0;
  // Every rank passes what it found; every rank gets Ok where all passed Ok, else the error of
  // the lowest rank that failed, its message prefixed with "rank R: " (R its rank).
  virtual Status agree(const Status& mine) = 0;
  const CommunicationStats& stats() const { return stats_; }

 protected:
  CommunicationStats stats_;
};

}  // namespace lambert
