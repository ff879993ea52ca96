#include "lambert/io/exr.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

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

// The pixel type (0 uint, 1 half, 2 float) of each channel, read from the EXR header's "channels"
// attribute as OpenEXR's file layout describes it: magic and version (8 bytes), then attributes
// (name, type name, int32 size, value) up to an empty name; a chlist value is per channel its
// name, int32 pixel type and 12 more bytes, ended by an empty name.
std::vector<int> channelPixelTypes(const std::vector<char>& file) {
  std::size_t at = 8;
  auto text = [&] {
    std::string s(&file.at(at));
    at += s.size() + 1;
    return s;
  };
  auto int32 = [&] {
    std::int32_t v;
    std::memcpy(&v, &file.at(at), 4);
    at += 4;
    return v;
  };
  for (std::string name = text(); !name.empty(); name = text()) {
    const std::string type = text();
    const std::size_t size = static_cast<std::size_t>(int32());
    if (name != "channels") {
      at += size;
      continue;
    }
    std::vector<int> types;
    for (std::string channel = text(); !channel.empty(); channel = text()) {
      types.push_back(int32());
      at += 12;
    }
    return types;
  }
  return {};
}

// Half float keeps 11 significant bits: each value comes back within 2^-11 of itself (rounded to
// nearest), below half's smallest normal 2^-14 within half a subnormal step 2^-25, and above its
// largest finite value as 65504. The file says half in its header.
TEST(ExrTest, HalfFloatKeepsElevenSignificantBits) {
  const std::filesystem::path dir = testing::scratchDirectory("exr", "half");
  Image image;
  image.width = 9;
  image.height = 8;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const double decade = std::pow(10.0, (y * image.width + x) / 9.0 - 6);  // 1e-6 .. 1e2
      image.pixels.push_back({decade * 3.14159, decade * 271.828, x == 0 ? 0.0 : 1e5 / x});
    }
  const std::string path = (dir / "lightmap.exr").string();
  ASSERT_TRUE(writeExr(path, image, ExrPixelType::Half).ok());
  EXPECT_EQ(channelPixelTypes(testing::readBytes(path)), (std::vector<int>{1, 1, 1}));
  ASSERT_TRUE(writeExr((dir / "float.exr").string(), image).ok());
  EXPECT_EQ(channelPixelTypes(testing::readBytes((dir / "float.exr").string())), (std::vector<int>{2, 2, 2}));
  Result<Image> read = readExr(path);
  ASSERT_TRUE(read.ok()) << read.error().message;
  std::size_t subnormal = 0, clamped = 0;
  for (std::size_t p = 0; p < image.pixels.size(); ++p)
    for (int c = 0; c < 3; ++c) {
      const double x = image.pixels[p][c], back = read->pixels[p][c];
      if (x > 65504) {
        ++clamped;
        EXPECT_EQ(back, 65504) << p;
      } else if (x < std::ldexp(1.0, -14)) {
        ++subnormal;
        EXPECT_NEAR(back, x, std::ldexp(1.0, -25)) << p;
      } else {
        EXPECT_NEAR(back, x, std::ldexp(x, -11)) << p << " " << c;
      }
    }
  EXPECT_GT(subnormal, 3u);
  EXPECT_GT(clamped, 0u);
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
