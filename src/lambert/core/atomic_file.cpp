#include "lambert/core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <system_error>

namespace lambert {
namespace {

// The temporaries being written now, for removeTemporaryFiles.
std::mutex temporariesMutex;
std::set<std::string>& temporaries() {
  static std::set<std::string> paths;
  return paths;
}

// Registers a temporary for as long as it may exist.
class TemporaryFile {
 public:
  explicit TemporaryFile(std::string path) : path_(std::move(path)) {
    std::lock_guard lock(temporariesMutex);
    temporaries().insert(path_);
  }
  ~TemporaryFile() {
    std::lock_guard lock(temporariesMutex);
    temporaries().erase(path_);
  }
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Writes all the parts to a new file (O_EXCL: never into one another writer has open); an empty
// string on success, else what failed.
std::string writeNewFile(const std::string& path, std::span<const std::span<const std::uint8_t>> parts) {
  int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) return "cannot create " + path + ": " + std::strerror(errno);
  for (std::span<const std::uint8_t> bytes : parts) {
    std::size_t written = 0;
    while (written < bytes.size()) {
      ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        std::string why = n < 0 ? std::strerror(errno) : "nothing written";
        ::close(fd);
        return "cannot write " + path + ": " + why;
      }
      written += static_cast<std::size_t>(n);
    }
  }
  // close is where some file systems (NFS) report a failed write.
  if (::close(fd) != 0) return "cannot write " + path + ": " + std::strerror(errno);
  return {};
}

}  // namespace

Status writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes) {
  return writeFileAtomically(path, {bytes});
}

Status writeFileAtomically(const std::string& path, std::initializer_list<std::span<const std::uint8_t>> parts) {
  return writeFileAtomically(path, std::span<const std::span<const std::uint8_t>>(parts.begin(), parts.size()));
}

Status writeFileAtomically(const std::string& path, std::span<const std::span<const std::uint8_t>> parts) {
  namespace fs = std::filesystem;
  if (path.empty()) return Error{"cannot write a file with an empty path"};
  std::error_code ec;
  fs::path parent = fs::path(path).parent_path();
  if (!parent.empty()) {
    fs::create_directories(parent, ec);
    if (ec) return Error{path + ": cannot create directory " + parent.string() + ": " + ec.message()};
  }
  // Unique per process and call, so concurrent writers of one path never share a temporary.
  static std::atomic<std::uint64_t> counter{0};
  const TemporaryFile registered(path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  const std::string& temp = registered.path();
  // No fsync: callers whose files matter check them when reading (sizes, checksums); a torn file
  // after a crash is then rejected rather than trusted.
  if (std::string why = writeNewFile(temp, parts); !why.empty()) {
    fs::remove(temp, ec);
    return Error{path + ": " + why};
  }
  fs::rename(temp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    return Error{path + ": cannot rename " + temp + " over it: " + ec.message()};
  }
  return Ok{};
}

void removeTemporaryFiles() {
  std::lock_guard lock(temporariesMutex);
  for (const std::string& path : temporaries()) ::unlink(path.c_str());
}

}  // namespace lambert
