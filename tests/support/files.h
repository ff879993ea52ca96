#pragma once
// Scratch files for tests: a fresh directory per test under the build's test-output folder.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#ifndef LAMBERT_TEST_OUTPUT_DIR
#define LAMBERT_TEST_OUTPUT_DIR "/tmp/lambert-test-output"
#endif

namespace lambert::testing {

// <test output>/<group>/<name>-<pid>, emptied and created: tests never see another run's files.
inline std::filesystem::path scratchDirectory(const std::string& group, const std::string& name) {
  std::filesystem::path dir = std::filesystem::path(LAMBERT_TEST_OUTPUT_DIR) / group / (name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::vector<char> readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void writeBytes(const std::filesystem::path& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

// Whether dir holds a temporary file of an atomic write (core/atomic_file.h names them *.tmp-*).
inline bool hasTemporaryFiles(const std::filesystem::path& dir) {
  if (!std::filesystem::is_directory(dir)) return false;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().filename().string().find(".tmp") != std::string::npos) return true;
  return false;
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace lambert::testing
