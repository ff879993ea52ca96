#pragma once
// Small text helpers shared by the loaders and the CLI.
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "lambert/core/error.h"

namespace lambert {

// A path's extension in lower case, with its dot: "Room.OBJ" → ".obj"; "" when it has none.
inline std::string lowercaseExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

// A library's multi-line message as one line of a lambert message: trailing newlines dropped,
// inner ones turned into "; ".
inline std::string singleLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  std::string out;
  for (char c : text) out += c == '\n' ? std::string("; ") : std::string(1, c);
  return out;
}

// A whole file's bytes, or "<path>: cannot be read".
inline Result<std::string> readWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot be read"};
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) return Error{path + ": cannot be read"};
  return bytes;
}

}  // namespace lambert
