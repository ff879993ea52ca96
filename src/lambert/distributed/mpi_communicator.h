#pragma once
// The Communicator over MPI (OpenMPI from Debian): MPI_COMM_WORLD, initialised for a program whose
// threads (TBB's) never call MPI themselves (MPI_THREAD_FUNNELED). Built into lambert_mpi, a
// library of its own, where CMake finds MPI: liblambert itself never links MPI.
#include <memory>

#include "lambert/core/communicator.h"

namespace lambert {

// MPI for the life of the object: MPI_Init_thread on construction, MPI_Finalize on destruction.
// One per process, made before any Communicator. An error (MPI that cannot start, or too little
// thread support) is reported by ok().
class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  const Status& ok() const { return status_; }
  // Every process of the job, through MPI_COMM_WORLD.
  std::shared_ptr<Communicator> world() const;

 private:
  Status status_ = Ok{};
  bool initialised_ = false;
};

}  // namespace lambert
