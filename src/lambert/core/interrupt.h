#pragma once
// Ctrl-C for a program that writes files. Every output and cache file is written to a temporary
// beside it and renamed over it (core/atomic_file.h), so stopping at any instant leaves either
// the old file or the whole new one; what is left to clean up is the temporary being written.
#include <csignal>

namespace lambert {

// Call first in main, before any thread starts: SIGINT and SIGTERM are blocked in this thread
// (and so in every thread started later, which inherit the mask) and a thread of their own waits
// for them. On one it removes the temporary files being written, prints "<program>: interrupted"
// on stderr and ends the process at once with 128 + the signal's number (130 for Ctrl-C, 143 for
// SIGTERM), whatever the other threads are doing. SIGXFSZ is ignored, so that a write past the
// file-size limit fails (EFBIG, an error naming the file) instead of killing the process.
void exitCleanlyOnInterrupt(const char* program);

}  // namespace lambert
