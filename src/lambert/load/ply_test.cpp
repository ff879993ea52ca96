#include "lambert/load/ply.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>

#include "lambert/load/scene_file.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

const char* kHeader = "ply\nformat %s 1.0\ncomment a unit square of two triangles\nelement vertex 4\n"
                      "property float x\nproperty float y\nproperty double z\nproperty uchar red\n"
                      "element face 2\nproperty list uchar int vertex_indices\nend_header\n";

std::string header(const char* format) {
  char text[512];
  std::snprintf(text, sizeof text, kHeader, format);
  return text;
}

// The square as binary: float x, float y, double z, uchar red per vertex; two faces.
std::string binarySquare(bool bigEndian) {
  std::string bytes = header(bigEndian ? "binary_big_endian" : "binary_little_endian");
  auto put = [&](auto value) {
    char raw[sizeof value];
    std::memcpy(raw, &value, sizeof value);
    if (bigEndian) std::reverse(raw, raw + sizeof value);
    bytes.append(raw, sizeof value);
  };
  const float xy[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const auto& v : xy) {
    put(v[0]);
    put(v[1]);
    put(0.0);
    put(std::uint8_t{200});
  }
  const std::int32_t faces[2][3] = {{0, 1, 2}, {0, 2, 3}};
  for (const auto& face : faces) {
    put(std::uint8_t{3});
    for (std::int32_t index : face) put(index);
  }
  return bytes;
}

void expectSquare(const Result<Scene>& scene) {
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->surfaces.size(), 1u);  // two triangles of one plane: one smooth region
  EXPECT_EQ(scene->surfaces[0].vertices.size(), 4u);
  EXPECT_NEAR(surfaceArea(scene->surfaces[0]), 1, 1e-12);
  EXPECT_GT(surfaceNormal(scene->surfaces[0]).z, 0.999);
  EXPECT_EQ(scene->materials[0].albedo, Rgb::gray(0.5));
}

TEST(PlyTest, AsciiAndBothBinaryOrdersReadTheSameSquare) {
  const fs::path dir = testing::scratchDirectory("ply", "square");
  std::ofstream(dir / "ascii.ply") << header("ascii") << "0 0 0 200\n1 0 0 200\n1 1 0 200\n0 1 0 200\n3 0 1 2\n3 0 2 3\n";
  std::ofstream(dir / "little.ply", std::ios::binary) << binarySquare(false);
  std::ofstream(dir / "big.ply", std::ios::binary) << binarySquare(true);
  for (const char* name : {"ascii.ply", "little.ply", "big.ply"}) {
    SCOPED_TRACE(name);
    expectSquare(readPly((dir / name).string()));
  }
  Result<Scene> scaled = loadScene((dir / "ascii.ply").string(), LoadOptions{.metresPerUnit = 0.01, .creaseAngleDegrees = 20});
  ASSERT_TRUE(scaled.ok());
  EXPECT_EQ(scaled->metresPerUnit, 0.01);
}

TEST(PlyTest, HostileAndBrokenFilesAreErrors) {
  const fs::path dir = testing::scratchDirectory("ply", "bad");
  const std::pair<std::string, std::string> cases[] = {
      {"not a ply\n", "not a PLY file"},
      {"ply\nformat ascii 1.0\nelement vertex 10000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n",
       "the header declares 10000000 vertex elements, more than the file's"},
      {header("ascii") + "0 0 0 200\n1 0 0 200\n1 1 0 200\n0 1 0 200\n3 0 1\n", ": the file ends early, after line 16"},
      {header("ascii") + "0 0 0 200\n1 0 zero 200\n1 1 0 200\n0 1 0 200\n3 0 1 2\n3 0 2 3\n", ":13: expected a number"},
      {header("ascii") + "0 0 0 200\n1 0 0 200\n1 1 0 200\n0 1 0 200\n200 0 1 2\n3 0 2 3\n", "a list of 200 entries does not fit"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty quaternion x\nend_header\n", ":4: unknown type 'quaternion'"},
      {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
       "no faces"},
      {header("binary_little_endian") + std::string(10, '\0'), "more than the file's 10 bytes of data can hold"},
      {binarySquare(false).substr(0, binarySquare(false).size() - 9), ": byte 310: a list of 3 entries does not fit in the file"},
  };
  int k = 0;
  for (const auto& [text, message] : cases) {
    const fs::path file = dir / ("bad" + std::to_string(k++) + ".ply");
    std::ofstream(file, std::ios::binary) << text;
    Result<Scene> read = readPly(file.string());
    ASSERT_FALSE(read.ok()) << text;
    EXPECT_TRUE(testing::contains(read.error().message, file.string() + ":")) << read.error().message;
    EXPECT_TRUE(testing::contains(read.error().message, message)) << read.error().message << "\nwanted: " << message;
  }
  // Found by fuzz/ply_fuzz.cpp: a list whose count type is float, holding -1.6e29, was converted
  // to long long for the error message (undefined behaviour). The reproducer is in the corpus; a
  // fractional ascii count and a huge one are its ascii neighbours.
  const std::string reproducer = std::string(LAMBERT_SOURCE_DIR) + "/tests/corpus/ply/regression-float-list-count.ply";
  Result<Scene> fuzzed = readPly(reproducer);
  ASSERT_FALSE(fuzzed.ok());
  EXPECT_EQ(fuzzed.error().message, reproducer + ":8: a list's count type must be an integer type, not 'float'");
  const std::pair<std::string, std::string> counts[] = {
      {"2.5 0 1 2\n", "a list's count 2.5 is not a whole number"},
      {"1e300 0 1 2\n", "a list of 1e+300 entries does not fit in the file"},
      {"-1e30 0 1 2\n", "a list of -1e+30 entries does not fit in the file"},
  };
  for (const auto& [face, message] : counts) {
    const fs::path file = dir / "count.ply";
    std::ofstream(file, std::ios::binary) << header("ascii") << "0 0 0 200\n1 0 0 200\n1 1 0 200\n0 1 0 200\n" << face << "3 0 2 3\n";
    Result<Scene> read = readPly(file.string());
    ASSERT_FALSE(read.ok()) << face;
    EXPECT_TRUE(testing::contains(read.error().message, message)) << read.error().message << "\nwanted: " << message;
  }
  // Found by fuzz/ply_fuzz.cpp (a hang): a vertex element whose count overflowed long long, with no
  // properties (so no bytes per vertex for the file's size to bound), was read 2^63 times.
  const std::string hang = std::string(LAMBERT_SOURCE_DIR) + "/tests/corpus/ply/regression-huge-count-no-properties.ply";
  Result<Scene> hung = readPly(hang);
  ASSERT_FALSE(hung.ok());
  EXPECT_EQ(hung.error().message, hang + ":3: an element needs a count (a whole number below 2^63)");
  const fs::path empty = dir / "empty-element.ply";
  std::ofstream(empty) << "ply\nformat ascii 1.0\nelement vertex 4000000000\nend_header\n";
  Result<Scene> noProperties = readPly(empty.string());
  ASSERT_FALSE(noProperties.ok());
  EXPECT_TRUE(testing::contains(noProperties.error().message, "4000000000 vertex elements without any property"))
      << noProperties.error().message;
  // An index past the vertices drops that face only, with the count in a warning.
  const fs::path outOfRange = dir / "range.ply";
  std::ofstream(outOfRange) << header("ascii") << "0 0 0 200\n1 0 0 200\n1 1 0 200\n0 1 0 200\n3 0 1 2\n3 0 2 9\n";
  Result<Scene> partly = readPly(outOfRange.string());
  ASSERT_TRUE(partly.ok()) << partly.error().message;
  EXPECT_NEAR(surfaceArea(partly->surfaces[0]), 0.5, 1e-12);
}

}  // namespace
}  // namespace lambert
