#include "lambert/distributed/mpi_communicator.h"

#include <mpi.h>

#include <string>
#include <vector>

#include "lambert/core/timer.h"

namespace lambert {
namespace {

class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  void allGatherRecords(const void* mine, std::span<const int> counts, void* all, std::size_t recordBytes) override {
    const Timer timer;
    // Counted in records (an MPI type of recordBytes bytes), so that 2³¹ records fit, not 2³¹ bytes.
    MPI_Datatype record;
    MPI_Type_contiguous(static_cast<int>(recordBytes), MPI_BYTE, &record);
    MPI_Type_commit(&record);
    std::vector<int> offsets(counts.size(), 0);
    std::uint64_t total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) {
      offsets[r] = static_cast<int>(total);
      total += static_cast<std::uint64_t>(counts[r]);
    }
    const int own = counts[static_cast<std::size_t>(rank_)];
    MPI_Allgatherv(mine, own, record, all, counts.data(), offsets.data(), record, MPI_COMM_WORLD);
    MPI_Type_free(&record);
    count(static_cast<std::uint64_t>(own) * recordBytes, (total - static_cast<std::uint64_t>(own)) * recordBytes, timer);
  }

  void maxAll(std::span<double> values) override {
    const Timer timer;
    MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    count(values.size() * sizeof(double), values.size() * sizeof(double), timer);
  }

  Status agree(const Status& mine) override {
    const Timer timer;
    // The lowest failing rank (size_ where none failed), then its message from it.
    int failed = mine ? size_ : rank_;
    MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (failed == size_) {
      count(sizeof(int), sizeof(int), timer);
      return Ok{};
    }
    std::string message = failed == rank_ ? mine.error().message : std::string();
    int length = static_cast<int>(message.size());
    MPI_Bcast(&length, 1, MPI_INT, failed, MPI_COMM_WORLD);
    message.resize(static_cast<std::size_t>(length));
    MPI_Bcast(message.data(), length, MPI_CHAR, failed, MPI_COMM_WORLD);
    count(sizeof(int), sizeof(int) + static_cast<std::uint64_t>(length), timer);
    return Error{"rank " + std::to_string(failed) + ": " + message};
  }

 private:
  void count(std::uint64_t sent, std::uint64_t received, const Timer& timer) {
    stats_.bytesSent += sent;
    stats_.bytesReceived += received;
    ++stats_.calls;
    stats_.seconds += timer.seconds();
  }
  int rank_ = 0, size_ = 1;
};

}  // namespace

MpiSession::MpiSession(int* argc, char*** argv) {
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
    status_ = Error{"MPI did not start (MPI_Init_thread failed): run under mpirun or srun"};
    return;
  }
  initialised_ = true;
  if (provided < MPI_THREAD_FUNNELED)
    status_ = Error{"this MPI gives no thread support (MPI_THREAD_FUNNELED), which lambert's threads need"};
}

MpiSession::~MpiSession() {
  if (initialised_) MPI_Finalize();
}

std::shared_ptr<Communicator> MpiSession::world() const { return std::make_shared<MpiCommunicator>(); }

}  // namespace lambert
