#pragma once
// `lambert solve --distributed` (docs/distributed.md): joins the MPI job lambert was started in
// (mpirun, srun) and quiets every rank but rank 0, which alone prints and writes.
#include <memory>

#include "lambert/core/communicator.h"
#include "lambert/core/error.h"

namespace lambert::cli {

// The job's communicator (MPI starts here, and stops when the program exits). On ranks other
// than 0, stderr then goes nowhere and warnings are dropped: their errors reach rank 0 through
// Communicator::agree. An Error where this lambert was built without MPI or MPI cannot start.
Result<std::shared_ptr<Communicator>> joinDistributedJob();

}  // namespace lambert::cli
