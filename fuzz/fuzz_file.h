#pragma once
// What every fuzz target shares. The readers take paths, not bytes, so each input is written to a
// file in a directory private to this process (/tmp/lambert-fuzz-<pid>/, removed at a normal
// exit), under the name and extension that selects the reader's format.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "lambert/core/error.h"

namespace lambert::fuzz {

// Writes size bytes at data to <private directory>/<name>, replacing what an earlier input left
// there, and returns its path. Aborts if it cannot: a target that silently fuzzed nothing would
// report clean runs.
std::string writeInput(const std::string& name, const std::uint8_t* data, std::size_t size);
inline std::string writeInput(const std::string& name, std::string_view text) {
  return writeInput(name, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

// Sends the library's warnings nowhere: readers warn about much of what a fuzzer feeds them, and
// printing every warning would cost more than reading the input.
void silenceWarnings();

// Whether LAMBERT_FUZZ_VERBOSE is set: then report() prints each reader's verdict, to see why a
// seed or a reproducer is refused (run a target on one file: build-fuzz/bin/mgf_fuzz file.mgf).
bool verbose();
template <class T>
void report(const Result<T>& result) {
  if (verbose()) std::fprintf(stderr, "fuzz: %s\n", result ? "read" : result.error().message.c_str());
}

}  // namespace lambert::fuzz
