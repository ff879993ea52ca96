#include "lambert/io/png.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include <stb_image.h>
#include <stb_image_write.h>

namespace lambert {
namespace {

void appendBytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(context);
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

// Writes all of bytes to a new file at path; an empty string on success, else what failed.
std::string writeFile(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) return "cannot create " + path + ": " + std::strerror(errno);
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
  // close is where some file systems (NFS) report a failed write.
  if (::close(fd) != 0) return "cannot write " + path + ": " + std::strerror(errno);
  return {};
}

}  // namespace

Status writePng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb8) {
  namespace fs = std::filesystem;
  if (path.empty()) return Error{"writePng: empty path"};
  if (width <= 0 || height <= 0 || rgb8.size() != static_cast<std::size_t>(width) * height * 3)
    return Error{path + ": image is " + std::to_string(width) + "x" + std::to_string(height) +
                 " but has " + std::to_string(rgb8.size()) + " bytes of RGB"};

  std::vector<std::uint8_t> encoded;
  if (!stbi_write_png_to_func(appendBytes, &encoded, width, height, 3, rgb8.data(), width * 3))
    return Error{path + ": PNG encoding failed"};

  std::error_code ec;
  fs::path parent = fs::path(path).parent_path();
  if (!parent.empty()) {
    fs::create_directories(parent, ec);
    if (ec) return Error{path + ": cannot create directory " + parent.string() + ": " + ec.message()};
  }

  const std::string temp = path + ".tmp-" + std::to_string(::getpid());
  if (std::string why = writeFile(temp, encoded); !why.empty()) {
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

Result<PngImage> readPng(const std::string& path) {
  int width = 0, height = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &width, &height, &channels, 3);
  if (!data) {
    const char* why = stbi_failure_reason();
    return Error{path + ": cannot read PNG: " + (why ? why : "unknown error")};
  }
  PngImage image;
  image.width = width;
  image.height = height;
  image.rgb8.assign(data, data + static_cast<std::size_t>(width) * height * 3);
  stbi_image_free(data);
  return image;
}

}  // namespace lambert
