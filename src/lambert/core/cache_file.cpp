#include "lambert/core/cache_file.h"

#include "lambert/core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <system_error>
#include <utility>

namespace lambert::cachefile {
namespace {

namespace fs = std::filesystem;

std::string errnoText(int error) { return std::generic_category().message(error); }

// Reads exactly size bytes unless the file ends first; returns the count read, or -1 with errno.
long long readFully(int fd, void* data, std::size_t size) {
  auto* p = static_cast<unsigned char*>(data);
  std::size_t done = 0;
  while (done < size) {
    ssize_t n = ::read(fd, p + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return -1;
    if (n == 0) break;
    done += static_cast<std::size_t>(n);
  }
  return static_cast<long long>(done);
}

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  int release() { return std::exchange(fd_, -1); }
  // close() is where some file systems (NFS) report a failed write, so a writer must see it.
  int close() {
    int rc = ::close(fd_);
    fd_ = -1;
    return rc;
  }

 private:
  int fd_;
};

}  // namespace

void Xxh64::update(const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  total_ += size;
  if (buffered_ > 0) {
    std::size_t take = std::min(size, kStripe - buffered_);
    std::memcpy(buffer_.data() + buffered_, p, take);
    buffered_ += take;
    p += take;
    size -= take;
    if (buffered_ < kStripe) return;
    consumeStripe(buffer_.data());
    buffered_ = 0;
  }
  for (; size >= kStripe; p += kStripe, size -= kStripe) consumeStripe(p);
  if (size > 0) std::memcpy(buffer_.data(), p, size);
  buffered_ = size;
}

std::uint64_t Xxh64::digest() const {
  std::uint64_t h;
  if (total_ >= kStripe) {
    h = std::rotl(acc_[0], 1) + std::rotl(acc_[1], 7) + std::rotl(acc_[2], 12) + std::rotl(acc_[3], 18);
    for (std::uint64_t a : acc_) h = mergeRound(h, a);
  } else {
    h = seed_ + kP5;
  }
  h += total_;
  const unsigned char* p = buffer_.data();
  std::size_t left = buffered_;
  for (; left >= 8; p += 8, left -= 8) {
    h ^= round(0, loadLe64(p));
    h = std::rotl(h, 27) * kP1 + kP4;
  }
  if (left >= 4) {
    h ^= static_cast<std::uint64_t>(loadLe32(p)) * kP1;
    h = std::rotl(h, 23) * kP2 + kP3;
    p += 4;
    left -= 4;
  }
  for (; left > 0; ++p, --left) {
    h ^= *p * kP5;
    h = std::rotl(h, 11) * kP1;
  }
  h ^= h >> 33;
  h *= kP2;
  h ^= h >> 29;
  h *= kP3;
  h ^= h >> 32;
  return h;
}

std::string hex(std::uint64_t v) {
  char text[19];
  std::snprintf(text, sizeof text, "0x%016" PRIx64, v);
  return text;
}

std::string keyedPath(const std::string& directory, const char* prefix, std::uint64_t key, const char* suffix) {
  char digits[17];
  std::snprintf(digits, sizeof digits, "%016" PRIx64, key);
  return (fs::path(directory) / (std::string(prefix) + digits + suffix)).string();
}

bool isMissing(const std::string& path) {
  std::error_code ec;
  return fs::symlink_status(path, ec).type() == fs::file_type::not_found;
}

Status writeFile(const std::string& path, const Format& format, std::uint64_t key, std::uint64_t count,
                 std::span<const unsigned char> payload) {
  if (path.empty()) return Error{"cache file: empty path"};
  unsigned char header[kHeaderBytes] = {};
  std::memcpy(header, format.magic.data(), format.magic.size());
  storeLe32(header + 8, format.version);
  storeLe32(header + 12, 0);
  storeLe64(header + 16, key);
  storeLe64(header + 24, count);
  Xxh64 checksum;
  checksum.update(header, sizeof header);
  if (!payload.empty()) checksum.update(payload.data(), payload.size());
  unsigned char trailer[kChecksumBytes];
  storeLe64(trailer, checksum.digest());

  return writeFileAtomically(path, {std::span<const std::uint8_t>(header, sizeof header), payload,
                                    std::span<const std::uint8_t>(trailer, sizeof trailer)});
}

Reader::Reader(Reader&& other) noexcept
    : path_(std::move(other.path_)),
      fd_(std::exchange(other.fd_, -1)),
      fileBytes_(other.fileBytes_),
      header_(other.header_),
      payloadBytes_(other.payloadBytes_),
      sized_(other.sized_) {}

Reader::~Reader() {
  if (fd_ >= 0) ::close(fd_);
}

Result<Reader> Reader::open(const std::string& path, const Format& format, std::uint64_t key) {
  FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) return Error{path + ": cannot open: " + errnoText(errno)};
  struct stat info {};
  if (::fstat(fd.get(), &info) != 0) return Error{path + ": cannot stat: " + errnoText(errno)};
  if (!S_ISREG(info.st_mode)) return Error{path + ": not a regular file"};
  Reader reader(path, -1, static_cast<std::uint64_t>(info.st_size));

  unsigned char* header = reader.header_.data();
  const std::size_t headerRead = static_cast<std::size_t>(std::min<std::uint64_t>(reader.fileBytes_, kHeaderBytes));
  long long got = readFully(fd.get(), header, headerRead);
  if (got < 0) return Error{path + ": cannot read: " + errnoText(errno)};
  const auto have = static_cast<std::size_t>(got);
  // What there is of the magic must match, so that some other short file is not called truncated.
  if (std::memcmp(header, format.magic.data(), std::min(have, format.magic.size())) != 0)
    return Error{path + ": not a " + format.name + " (bad magic)"};
  if (have < kHeaderBytes)
    return Error{path + ": truncated: " + std::to_string(have) + " bytes, shorter than the " +
                 std::to_string(kHeaderBytes) + "-byte header"};
  const std::uint32_t version = loadLe32(header + 8);
  if (version != format.version)
    return Error{path + ": format version " + std::to_string(version) + ", expected " + std::to_string(format.version)};
  const std::uint32_t reserved = loadLe32(header + 12);
  if (reserved != 0) return Error{path + ": reserved header field is " + std::to_string(reserved) + ", expected 0"};
  const std::uint64_t storedKey = loadLe64(header + 16);
  if (storedKey != key)
    return Error{path + ": key mismatch: file is for " + hex(storedKey) + ", expected " + hex(key) +
                 " (written for another mesh or options)"};
  reader.fd_ = fd.release();
  return reader;
}

Status Reader::checkSize(std::size_t payloadBytes, const std::string& counted) {
  const std::uint64_t expectedBytes = kHeaderBytes + static_cast<std::uint64_t>(payloadBytes) + kChecksumBytes;
  if (fileBytes_ < expectedBytes)
    return Error{path_ + ": truncated: " + std::to_string(fileBytes_) + " bytes, expected " +
                 std::to_string(expectedBytes) + " for " + counted};
  if (fileBytes_ > expectedBytes)
    return Error{path_ + ": " + std::to_string(fileBytes_ - expectedBytes) + " trailing bytes after the checksum (" +
                 std::to_string(fileBytes_) + " bytes, expected " + std::to_string(expectedBytes) + ")"};
  payloadBytes_ = payloadBytes;
  sized_ = true;
  return Ok{};
}

Status Reader::readPayload(void* data) {
  LAMBERT_CHECK(sized_ && fd_ >= 0);
  unsigned char trailer[kChecksumBytes];
  long long payloadRead = payloadBytes_ > 0 ? readFully(fd_, data, payloadBytes_) : 0;
  long long trailerRead =
      payloadRead == static_cast<long long>(payloadBytes_) ? readFully(fd_, trailer, sizeof trailer) : 0;
  if (payloadRead < 0 || trailerRead < 0) return Error{path_ + ": cannot read: " + errnoText(errno)};
  // The size was right a moment ago; a short read now means the file shrank while being read.
  if (payloadRead != static_cast<long long>(payloadBytes_) || trailerRead != static_cast<long long>(sizeof trailer))
    return Error{path_ + ": truncated while reading"};

  Xxh64 checksum;
  checksum.update(header_.data(), header_.size());
  if (payloadBytes_ > 0) checksum.update(data, payloadBytes_);
  const std::uint64_t computed = checksum.digest(), stored = loadLe64(trailer);
  if (computed != stored)
    return Error{path_ + ": checksum mismatch (stored " + hex(stored) + ", computed " + hex(computed) +
                 "): the file is damaged"};
  return Ok{};
}

}  // namespace lambert::cachefile
