// The bad-input corpus: every file under tests/bad/ is one case of input that lambert must refuse
// clearly (or, where the format says so, accept with a warning). tests/bad/cases.json lists each
// case's command line, exit status, the messages it must print and the files it may write; each
// case is a test of its own, so that CTest names the one that fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <regex>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/files.h"
#include "tests/support/process.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(LAMBERT_SOURCE_DIR) / "tests" / "bad";

struct BadInputCase {
  std::string name;                   // the test's name: the file's name with '-' and '.' as '_'
  std::string file;                   // the input, relative to tests/bad/
  std::vector<std::string> uses;      // files the input refers to (an MTL, an include), also under tests/bad/
  std::string arguments;              // {file}: the input's path; {out}: the case's empty scratch folder
  int exitCode = 2;
  std::vector<std::string> expect;    // regular expressions the output must match, each somewhere
  std::vector<std::string> writes;    // the files {out} must hold afterwards, and no others
  std::string manifestError;          // set when cases.json itself is wrong: the case fails with it
};

// What gtest (and so CTest's list) shows for a case: its file, not the struct's bytes.
void PrintTo(const BadInputCase& c, std::ostream* out) { *out << (c.file.empty() ? c.name : c.file); }

std::string testName(const std::string& file) {
  std::string name = file;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

std::vector<std::string> strings(const nlohmann::json& value) {
  std::vector<std::string> out;
  for (const auto& s : value) out.push_back(s.get<std::string>());
  return out;
}

// Every case of the manifest; a manifest that cannot be read is one failing case saying why
// (rather than no cases at all, which would pass unnoticed).
std::vector<BadInputCase> loadCases() {
  std::vector<BadInputCase> cases;
  try {
    std::ifstream in(kCorpus / "cases.json");
    const nlohmann::json manifest = nlohmann::json::parse(in);
    const nlohmann::json& defaults = manifest.at("defaults");
    std::set<std::string> names;
    for (const nlohmann::json& entry : manifest.at("cases")) {
      BadInputCase c;
      c.file = entry.at("file").get<std::string>();
      c.name = testName(c.file);
      if (!names.insert(c.name).second) throw std::runtime_error("two cases named " + c.name);
      c.uses = strings(entry.value("uses", nlohmann::json::array()));
      c.arguments = entry.value("args", defaults.at("args").get<std::string>());
      c.exitCode = entry.value("exit", defaults.at("exit").get<int>());
      c.expect = strings(entry.at("expect"));
      c.writes = strings(entry.value("writes", nlohmann::json::array()));
      // A misspelt field would silently fall back to a default: refuse it, as lambert does.
      for (const auto& item : entry.items()) {
        const std::string& key = item.key();
        if (key != "file" && key != "uses" && key != "args" && key != "exit" && key != "expect" && key != "writes" && key != "why")
          throw std::runtime_error(c.file + ": unknown field \"" + key + "\"");
      }
      cases.push_back(std::move(c));
    }
  } catch (const std::exception& e) {
    BadInputCase broken;
    broken.name = "manifest";
    broken.manifestError = (kCorpus / "cases.json").string() + ": " + e.what();
    cases = {broken};
  }
  return cases;
}

const std::vector<BadInputCase>& allCases() {
  static const std::vector<BadInputCase> cases = loadCases();
  return cases;
}

std::string replaceAll(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) text.replace(at, from.size(), to);
  return text;
}

std::vector<std::string> filesIn(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) names.push_back(fs::relative(entry.path(), dir).string());
  std::sort(names.begin(), names.end());
  return names;
}

class BadInputTest : public ::testing::TestWithParam<BadInputCase> {};

TEST_P(BadInputTest, FailsClearlyAndWritesNothing) {
  const BadInputCase& c = GetParam();
  ASSERT_TRUE(c.manifestError.empty()) << c.manifestError;
  const fs::path input = kCorpus / c.file;
  ASSERT_TRUE(fs::exists(input)) << input;
  for (const std::string& used : c.uses) ASSERT_TRUE(fs::exists(kCorpus / used)) << used;
  const fs::path out = testing::scratchDirectory("bad-input", c.name);
  const std::string arguments =
      replaceAll(replaceAll(replaceAll(c.arguments, "{file}", "'" + input.string() + "'"), "{out}", out.string()), "{dir}", "'" + kCorpus.string() + "'");
  // A case that hangs fails (status 124) instead of stalling the suite.
  const testing::CommandResult r = testing::shell("timeout 120 " + std::string(LAMBERT_CLI_PATH) + " " + arguments);
  SCOPED_TRACE("lambert " + arguments + "\n" + r.output);

  EXPECT_EQ(r.exitCode, c.exitCode);
  // The message names the file, or the file it uses where the problem is (an OBJ's MTL, named
  // with its line: OBJs that share it report it alike); expectations say which.
  // A case that loads cleanly (exit 0, no warning) has no message to name it in.
  if (c.exitCode != 0 || r.output.find("warning") != std::string::npos) {
    bool named = r.output.find(input.filename().string()) != std::string::npos;
    for (const std::string& used : c.uses) named = named || r.output.find(fs::path(used).filename().string()) != std::string::npos;
    EXPECT_TRUE(named) << "the output names neither " << input.filename() << " nor a file it uses";
  }
  for (const std::string& pattern : c.expect)
    EXPECT_TRUE(std::regex_search(r.output, std::regex(pattern))) << "the output does not match /" << pattern << "/";
  // Nothing is left behind but what the case writes on purpose: no image, no temporary file.
  std::vector<std::string> expected = c.writes;
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(filesIn(out), expected);
  for (const std::string& written : c.writes) EXPECT_GT(fs::file_size(out / written), 0u) << written;
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadInputTest, ::testing::ValuesIn(allCases()),
                         [](const ::testing::TestParamInfo<BadInputCase>& info) { return info.param.name; });

// The corpus holds no file that no case reads: a file added without a case would test nothing.
TEST(BadInputCorpusTest, EveryFileBelongsToACase) {
  std::set<std::string> listed = {"cases.json", "README.md"};
  for (const BadInputCase& c : allCases()) {
    listed.insert(c.file);
    listed.insert(c.uses.begin(), c.uses.end());
  }
  for (const std::string& file : filesIn(kCorpus)) EXPECT_TRUE(listed.count(file)) << file << " is in tests/bad/ but in no case";
}

}  // namespace
}  // namespace lambert
