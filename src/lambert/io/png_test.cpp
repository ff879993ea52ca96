#include "lambert/io/png.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/files.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using testing::hasTemporaryFiles;

fs::path scratch(const std::string& name) { return testing::scratchDirectory("png", name); }

std::vector<std::uint8_t> pattern(int width, int height, int seed) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3);
  std::uint32_t state = 2463534242u + seed;
  for (auto& byte : rgb) {
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    byte = static_cast<std::uint8_t>(state);
  }
  return rgb;
}


TEST(PngTest, WriteThenReadRoundTripsExactly) {
  fs::path dir = scratch("roundtrip");
  const std::string path = (dir / "image.png").string();
  const int width = 37, height = 23;
  std::vector<std::uint8_t> rgb = pattern(width, height, 1);
  Status status = writePng(path, width, height, rgb);
  ASSERT_TRUE(status.ok()) << status.error().message;
  Result<PngImage> image = readPng(path);
  ASSERT_TRUE(image.ok()) << image.error().message;
  EXPECT_EQ(image->width, width);
  EXPECT_EQ(image->height, height);
  EXPECT_EQ(image->rgb8, rgb);
  EXPECT_FALSE(hasTemporaryFiles(dir));

  // Writing again replaces the file whole.
  std::vector<std::uint8_t> other = pattern(5, 3, 2);
  ASSERT_TRUE(writePng(path, 5, 3, other).ok());
  image = readPng(path);
  ASSERT_TRUE(image.ok()) << image.error().message;
  EXPECT_EQ(image->width, 5);
  EXPECT_EQ(image->height, 3);
  EXPECT_EQ(image->rgb8, other);
  EXPECT_FALSE(hasTemporaryFiles(dir));
}

TEST(PngTest, CreatesMissingNestedDirectories) {
  fs::path dir = scratch("nested");
  fs::path path = dir / "a" / "b" / "c" / "image.png";
  std::vector<std::uint8_t> rgb = pattern(4, 4, 3);
  Status status = writePng(path.string(), 4, 4, rgb);
  ASSERT_TRUE(status.ok()) << status.error().message;
  Result<PngImage> image = readPng(path.string());
  ASSERT_TRUE(image.ok()) << image.error().message;
  EXPECT_EQ(image->rgb8, rgb);
}

TEST(PngTest, PathUnderARegularFileFails) {
  fs::path dir = scratch("under-file");
  std::ofstream(dir / "blocker") << "not a directory";
  const std::string path = (dir / "blocker" / "image.png").string();
  Status status = writePng(path, 2, 2, pattern(2, 2, 4));
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().message.find(path), std::string::npos) << status.error().message;
  EXPECT_FALSE(hasTemporaryFiles(dir));
  // The blocker is untouched.
  EXPECT_TRUE(fs::is_regular_file(dir / "blocker"));
}

TEST(PngTest, TargetThatIsADirectoryFailsAndLeavesNoTemporary) {
  // The temporary is written (the directory is writable) and only the rename fails: this is the
  // path that must clean up after itself.
  fs::path dir = scratch("target-dir");
  fs::create_directories(dir / "image.png" / "inside");
  const std::string path = (dir / "image.png").string();
  Status status = writePng(path, 2, 2, pattern(2, 2, 5));
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().message.find(path), std::string::npos) << status.error().message;
  EXPECT_FALSE(hasTemporaryFiles(dir));
  EXPECT_TRUE(fs::is_directory(dir / "image.png" / "inside"));
}

TEST(PngTest, UnwritableLocationFails) {
  const std::string path = "/proc/lambert-png-test/image.png";
  Status status = writePng(path, 2, 2, pattern(2, 2, 6));
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().message.find(path), std::string::npos) << status.error().message;
  EXPECT_FALSE(fs::exists(path));
}

TEST(PngTest, FailedWriteKeepsTheOldFile) {
  fs::path dir = scratch("keeps-old");
  const std::string path = (dir / "image.png").string();
  std::vector<std::uint8_t> old = pattern(3, 3, 7);
  ASSERT_TRUE(writePng(path, 3, 3, old).ok());
  Status status = writePng(path, 3, 3, pattern(3, 2, 8));  // too few bytes for 3×3
  ASSERT_FALSE(status.ok());
  EXPECT_FALSE(hasTemporaryFiles(dir));
  Result<PngImage> image = readPng(path);
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image->rgb8, old);
}

TEST(PngTest, WrongBufferSizeIsAnError) {
  fs::path dir = scratch("bad-size");
  const std::string path = (dir / "image.png").string();
  Status status = writePng(path, 4, 4, pattern(4, 3, 9));
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().message.find(path), std::string::npos);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(writePng(path, 0, 0, {}).ok());
}

TEST(PngTest, ReadingAMissingOrBrokenFileIsAnError) {
  fs::path dir = scratch("read-errors");
  const std::string missing = (dir / "missing.png").string();
  Result<PngImage> image = readPng(missing);
  ASSERT_FALSE(image.ok());
  EXPECT_NE(image.error().message.find(missing), std::string::npos);

  const std::string broken = (dir / "broken.png").string();
  std::ofstream(broken) << "\x89PNG but not really";
  image = readPng(broken);
  ASSERT_FALSE(image.ok());
  EXPECT_NE(image.error().message.find(broken), std::string::npos);
}

}  // namespace
}  // namespace lambert
