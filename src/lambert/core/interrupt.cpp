#include "lambert/core/interrupt.h"

#include <pthread.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <thread>

#include "lambert/core/atomic_file.h"

namespace lambert {

void exitCleanlyOnInterrupt(const char* program) {
  std::signal(SIGXFSZ, SIG_IGN);
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  // A thread, not a handler: sigwait returns in ordinary code, so the cleanup may take locks and
  // free memory, which a signal handler may not.
  std::thread([signals, name = std::string(program)] {
    int signal = 0;
    while (sigwait(&signals, &signal) != 0) {
    }
    removeTemporaryFiles();
    std::fprintf(stderr, "\n%s: interrupted\n", name.c_str());
    std::fflush(stderr);
    ::_exit(128 + signal);
  }).detach();
}

}  // namespace lambert
