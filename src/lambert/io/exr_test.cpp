#include "lambert/io/exr.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/files.h"

namespace lambert {
namespace {

TEST(ExrTest, RadianceRoundTripsToFloatPrecision) {
  const std::filesystem::path dir = testing::scratchDirectory("exr", "round-trip");
  Image image;
  image.width = 7;
  image.height = 5;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)  // values far outside [0, 1]: no tone mapping, no clamping
      image.pixels.push_back({0.001 * x + 1e-7, 123.456 * y, std::exp(0.5 * x - y)});
  const std::string path = (dir / "sub" / "radiance.exr").string();
  ASSERT_TRUE(writeExr(path, image).ok());
  EXPECT_FALSE(testing::hasTemporaryFiles(dir / "sub"));
  Result<Image> read = readExr(path);
  ASSERT_TRUE(read.ok()) << read.error().message;
  ASSERT_EQ(read->width, 7);
  ASSERT_EQ(read->height, 5);
  for (std::size_t p = 0; p < image.pixels.size(); ++p)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(read->pixels[p][c], static_cast<double>(static_cast<float>(image.pixels[p][c]))) << p;
}

TEST(ExrTest, ErrorsNameTheFile) {
  const std::filesystem::path dir = testing::scratchDirectory("exr", "errors");
  testing::writeBytes(dir / "not.exr", {'n', 'o', 't'});
  Result<Image> bad = readExr((dir / "not.exr").string());
  ASSERT_FALSE(bad.ok());
  EXPECT_TRUE(testing::contains(bad.error().message, (dir / "not.exr").string() + ": ")) << bad.error().message;
  EXPECT_FALSE(writeExr((dir / "empty.exr").string(), Image{}).ok());
  EXPECT_FALSE(std::filesystem::exists(dir / "empty.exr"));
}

}  // namespace
}  // namespace lambert
