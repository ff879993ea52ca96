#pragma once
// Small text helpers shared by the loaders and the CLI.
#include <cctype>
#include <filesystem>
#include <string>

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

}  // namespace lambert
