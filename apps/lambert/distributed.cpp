#include "distributed.h"

#include <cstdio>
#include <string>

#include "lambert/core/warning.h"
#ifdef LAMBERT_HAS_MPI
#include "lambert/distributed/mpi_communicator.h"
#endif

namespace lambert::cli {

Result<std::shared_ptr<Communicator>> joinDistributedJob() {
#ifdef LAMBERT_HAS_MPI
  // For the life of the program: MPI_Finalize runs at exit, after every collective call.
  static MpiSession session(nullptr, nullptr);
  if (!session.ok()) return session.ok().error();
  std::shared_ptr<Communicator> world = session.world();
  if (world->rank() != 0) {
    setWarningSink([](const std::string&) {});
    if (!std::freopen("/dev/null", "w", stderr)) return Error{"rank " + std::to_string(world->rank()) + ": cannot quiet stderr"};
  }
  return world;
#else
  return Error{"--distributed: this lambert was built without MPI; install OpenMPI (scripts/install-deps.sh installs openmpi-bin and "
               "libopenmpi-dev) and build it again"};
#endif
}

}  // namespace lambert::cli
