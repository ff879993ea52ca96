#pragma once
// MGF's input, for the reader (load/mgf.cpp): a file as logical lines of words ('\' line
// continuations joined, the newline counting as a space; comments and blank lines dropped), each
// with the physical line it starts on; and the file an include (i) names, resolved relative to
// the including file, confined to a root folder where one is given, refusing cycles and nesting
// deeper than kMaxIncludeDepth. Internal to load/.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "lambert/core/error.h"

namespace lambert::mgf {

constexpr int kMaxIncludeDepth = 32;

// Input: logical lines (continuations joined) as words, with the physical line they start on.

struct Line {
  std::vector<std::string> words;
  int number = 0;
};

struct SourceFile {
  std::string path;  // as named in messages
  std::filesystem::path directory;
  std::vector<Line> lines;
};

// The file at `path` as logical lines, named `shownPath` in messages; nullopt where it cannot be
// opened.
std::optional<SourceFile> loadSource(const std::filesystem::path& path, const std::string& shownPath);

// The file `name`, included from `from`, while the files `active` (canonical paths, the include
// chain) are being read; `canonical` is set to its canonical path. Inside includeRoot (symbolic
// links resolved) unless that is empty. The error says what is wrong and how to proceed.
Result<SourceFile> openInclude(const SourceFile& from, const std::string& name, const std::string& includeRoot,
                               const std::vector<std::filesystem::path>& active, std::filesystem::path& canonical);

}  // namespace lambert::mgf
