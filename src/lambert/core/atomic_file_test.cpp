#include "lambert/core/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "lambert/core/stats.h"
#include "lambert/core/warning.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> bytesOf(const std::string& text) { return {text.begin(), text.end()}; }
std::string textOf(const fs::path& path) {
  std::vector<char> bytes = testing::readBytes(path);
  return {bytes.begin(), bytes.end()};
}
std::size_t entries(const fs::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(AtomicFileTest, WritesCreatesDirectoriesAndReplacesWhole) {
  fs::path dir = testing::scratchDirectory("core", "atomic");
  const fs::path file = dir / "a" / "b" / "out.txt";
  ASSERT_TRUE(writeFileAtomically(file.string(), bytesOf("first version, longer")).ok());
  EXPECT_EQ(textOf(file), "first version, longer");
  ASSERT_TRUE(writeFileAtomically(file.string(), bytesOf("second")).ok());
  EXPECT_EQ(textOf(file), "second");  // replaced, not overwritten in place
  EXPECT_EQ(entries(file.parent_path()), 1u);  // no temporary file left

  const std::vector<std::uint8_t> head = bytesOf("head|"), body = bytesOf("body|"), tail = bytesOf("tail");
  ASSERT_TRUE(writeFileAtomically(file.string(), {head, body, tail}).ok());
  EXPECT_EQ(textOf(file), "head|body|tail");
}

TEST(AtomicFileTest, AFailedWriteNamesThePathAndKeepsTheOldFile) {
  fs::path dir = testing::scratchDirectory("core", "atomic-fail");
  const fs::path file = dir / "keep.txt";
  ASSERT_TRUE(writeFileAtomically(file.string(), bytesOf("old")).ok());
  // A directory where the parent should be: nothing can be created there.
  fs::create_directories(dir / "blocked");
  testing::writeBytes(dir / "plain", {'x'});
  Status failed = writeFileAtomically((dir / "plain" / "child.txt").string(), bytesOf("new"));
  ASSERT_FALSE(failed.ok());
  EXPECT_NE(failed.error().message.find((dir / "plain").string()), std::string::npos) << failed.error().message;
  // A directory in the file's place: the rename fails, the directory stays, no temporary is left.
  Status renamed = writeFileAtomically((dir / "blocked").string(), bytesOf("new"));
  ASSERT_FALSE(renamed.ok());
  EXPECT_TRUE(fs::is_directory(dir / "blocked"));
  EXPECT_EQ(textOf(file), "old");
  EXPECT_EQ(entries(dir), 3u);  // keep.txt, blocked, plain
}

TEST(WarningTest, GoesToTheSinkWhenOneIsSet) {
  std::vector<std::string> seen;
  WarningSink previous = setWarningSink([&](const std::string& message) { seen.push_back(message); });
  warning("cache file damaged; recomputing");
  setWarningSink(previous);
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0], "cache file damaged; recomputing");
}

TEST(WarningTest, CaptureKeepsThemForwardsWhenAskedAndRestoresTheSink) {
  std::vector<std::string> outer;
  WarningSink previous = setWarningSink([&](const std::string& message) { outer.push_back(message); });
  {
    WarningCapture forwarding(WarningCapture::Forward::yes);
    {
      WarningCapture silent;
      warning("first");
      EXPECT_EQ(silent.messages(), std::vector<std::string>{"first"});
    }
    warning("second");
    warning("second again");
    EXPECT_EQ(forwarding.messages(), (std::vector<std::string>{"second", "second again"}));
    EXPECT_EQ(forwarding.count("second"), 2);
  }
  warning("third");  // both captures gone: the outer sink again
  setWarningSink(previous);
  EXPECT_EQ(outer, (std::vector<std::string>{"second", "second again", "third"}));
}

TEST(StatsTest, AppendKeepsOrderAndFindsByKey) {
  Stats a, b;
  a.add("patches", "patches", std::int64_t{10});
  b.add("solver", "solver", std::string("gs"));
  b.add("residual", "relative residual", 1e-9);
  a.append(b);
  ASSERT_EQ(a.entries().size(), 3u);
  EXPECT_EQ(a.entries()[1].key, "solver");
  ASSERT_NE(a.find("residual"), nullptr);
  EXPECT_EQ(std::get<double>(a.find("residual")->value), 1e-9);
  EXPECT_EQ(a.find("missing"), nullptr);
  EXPECT_EQ(a.json()["patches"], 10);
}

}  // namespace
}  // namespace lambert
