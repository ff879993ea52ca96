#include "fuzz_file.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "lambert/core/warning.h"

namespace lambert::fuzz {
namespace {

// The directory is made on first use and removed when the process exits normally (after a crash
// it stays, with the input that caused it, beside libFuzzer's own copy in the artifacts).
class PrivateDirectory {
 public:
  PrivateDirectory() : path_(std::filesystem::temp_directory_path() / ("lambert-fuzz-" + std::to_string(getpid()))) {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);  // a directory left by an earlier process with this pid
    std::filesystem::create_directories(path_, ec);
    if (ec) {
      std::fprintf(stderr, "fuzz: cannot create %s: %s\n", path_.c_str(), ec.message().c_str());
      std::abort();
    }
  }
  ~PrivateDirectory() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace

std::string writeInput(const std::string& name, const std::uint8_t* data, std::size_t size) {
  static const PrivateDirectory directory;
  const std::filesystem::path path = directory.path() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path.string();
}

bool verbose() {
  static const bool on = std::getenv("LAMBERT_FUZZ_VERBOSE") != nullptr;
  return on;
}

void silenceWarnings() {
  static const bool silenced = [] {
    setWarningSink([](const std::string&) {});
    return true;
  }();
  (void)silenced;
}

}  // namespace lambert::fuzz
