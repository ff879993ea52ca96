#include "lambert/load/mgf_source.h"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace lambert::mgf {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> splitWords(const std::string& text) {
  std::vector<std::string> words;
  std::istringstream in(text);
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

}  // namespace

std::optional<SourceFile> loadSource(const fs::path& path, const std::string& shownPath) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  SourceFile file;
  file.path = shownPath;
  file.directory = path.parent_path();
  std::string physical, logical;
  int number = 0, start = 0;
  while (std::getline(in, physical)) {
    ++number;
    if (!physical.empty() && physical.back() == '\r') physical.pop_back();
    if (logical.empty()) start = number;
    if (!physical.empty() && physical.back() == '\\') {
      physical.back() = ' ';  // an escaped newline counts as a space
      logical += physical;
      continue;
    }
    logical += physical;
    Line line{splitWords(logical), start};
    logical.clear();
    if (line.words.empty() || line.words[0][0] == '#') continue;
    file.lines.push_back(std::move(line));
  }
  if (!logical.empty()) {
    Line line{splitWords(logical), start};
    if (!line.words.empty() && line.words[0][0] != '#') file.lines.push_back(std::move(line));
  }
  return file;
}

Result<SourceFile> openInclude(const SourceFile& from, const std::string& name, const std::string& includeRoot,
                               const std::vector<fs::path>& active, fs::path& canonical) {
  const fs::path target = (from.directory / name).lexically_normal();
  canonical = fs::weakly_canonical(target);
  if (!includeRoot.empty()) {
    // Before looking at the file, so that nothing outside the root is even probed; both sides
    // with symbolic links resolved, so that no link leads out of it.
    const fs::path relative = canonical.lexically_relative(fs::weakly_canonical(includeRoot));
    if (relative.empty() || *relative.begin() == "..")
      return Error{"include '" + name + "' is " + canonical.string() + ", outside the folder includes are confined to (" +
                   includeRoot + "); move the file under it, or give a root that holds it"};
  }
  std::error_code ec;
  if (!fs::is_regular_file(target, ec))
    return Error{"cannot open include '" + name + "' (looked for " + fs::absolute(target).lexically_normal().string() +
                 ", relative to the including file; check the name, or put the file there)"};
  if (std::find(active.begin(), active.end(), canonical) != active.end())
    return Error{"include cycle: '" + name + "' is already being read (it would include itself forever); remove the include that closes the cycle"};
  if (static_cast<int>(active.size()) > kMaxIncludeDepth)
    return Error{"includes nested deeper than " + std::to_string(kMaxIncludeDepth) + " levels; include the innermost files from a shallower one"};
  std::optional<SourceFile> file = loadSource(target, target.string());
  if (!file) return Error{"cannot open include '" + name + "' (it is there but cannot be read; check its permissions)"};
  return std::move(*file);
}

}  // namespace lambert::mgf
