#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <tbb/global_control.h>
#include <xmmintrin.h>

#include "lambert/io/vertices.h"
#include "tests/support/files.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) { return testing::scratchDirectory("vertices", name); }

std::vector<VertexSample> someVertices() {
  Mesh mesh = subdivideScene(testing::perpendicularSquares(), 0.5);
  std::vector<Rgb> radiance;
  for (std::size_t v = 0; v < mesh.numVertices(); ++v) radiance.push_back({0.1 * v, 1.0 / (v + 1), 3.25e-7});
  return vertexSamples(mesh, radiance);
}

TEST(VerticesTest, NormalsComeFromTheirSurface) {
  Mesh mesh = subdivideScene(testing::perpendicularSquares(), 0.5);
  auto samples = vertexSamples(mesh, std::vector<Rgb>(mesh.numVertices()));
  for (std::size_t v = 0; v < samples.size(); ++v) {
    Vec3 expected = mesh.vertexSurface[v] == 0 ? Vec3{0, 0, 1} : Vec3{1, 0, 0};
    EXPECT_NEAR(dot(samples[v].normal, expected), 1, 1e-12);
  }
}

TEST(VerticesTest, CsvAndPlyRoundTrip) {
  fs::path dir = scratch("round-trip");
  std::vector<VertexSample> original = someVertices();
  for (const char* name : {"v.csv", "v.ply"}) {
    const std::string path = (dir / name).string();
    ASSERT_TRUE(writeVertices(path, original).ok()) << name;
    Result<std::vector<VertexSample>> read = readVertices(path);
    ASSERT_TRUE(read.ok()) << read.error().message;
    ASSERT_EQ(read->size(), original.size());
    for (std::size_t v = 0; v < original.size(); ++v) {
      EXPECT_NEAR(length((*read)[v].position - original[v].position), 0, 1e-7);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR((*read)[v].radiance[c], original[v].radiance[c], 1e-8 * std::fabs(original[v].radiance[c]) + 1e-300);
    }
  }
  std::ifstream csv(dir / "v.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "x,y,z,nx,ny,nz,r,g,b");
}

// The rows are printf's %.9g of every value, written in blocks (in parallel where threads are
// allowed) and joined in order: checked against snprintf itself over awkward values (subnormal, huge, infinite,
// negative zero, ties at the ninth digit) and more rows than one block holds, in the
// denormals-are-zero mode Embree leaves on its threads.
TEST(VerticesTest, RowsArePrintfsNineDigitsInOrder) {
  const double awkward[] = {0.1, -0.0, 5e-324, 2.2250738585072014e-308, 1.7976931348623157e308, 123456789.5, 1234567885.0,
                            -9.999999995e-5, 1.0 / 3.0, 1e21, 100, 0.5e-4};
  std::vector<VertexSample> vertices(10000);
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    auto value = [&](int k) { return awkward[(v + 5 * k) % std::size(awkward)] * (1 + 1e-3 * static_cast<double>(v % 7)); };
    vertices[v].position = {value(0), value(1), value(2)};
    vertices[v].normal = {value(3), value(4), value(5)};
    vertices[v].radiance = {value(6), value(7), static_cast<double>(v)};
  }
  const fs::path path = scratch("printf") / "v.csv";
  {
    // As threads that ran Embree's BVH builder are (denormals are zero, flush to zero), on one
    // thread, so that the writer runs in that mode whatever ran before.
    const tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
    const unsigned mode = _mm_getcsr();
    _mm_setcsr(mode | 0x8040u);
    const Status written = writeVertices(path.string(), vertices);
    _mm_setcsr(mode);
    ASSERT_TRUE(written.ok());
  }
  std::string expected = "x,y,z,nx,ny,nz,r,g,b\n";
  for (const VertexSample& v : vertices) {
    char line[400];
    std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", v.position.x, v.position.y, v.position.z,
                  v.normal.x, v.normal.y, v.normal.z, v.radiance.r, v.radiance.g, v.radiance.b);
    expected += line;
  }
  std::ifstream in(path, std::ios::binary);
  const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(written.size(), expected.size());
  std::size_t at = 0;
  while (at < std::min(written.size(), expected.size()) && written[at] == expected[at]) ++at;
  EXPECT_TRUE(written == expected) << "first difference at byte " << at << ": written '" << written.substr(at, 40) << "', printf '"
                                   << expected.substr(at, 40) << "'";
}

TEST(VerticesTest, BadFilesNameTheFileAndLine) {
  fs::path dir = scratch("bad");
  EXPECT_FALSE(writeVertices((dir / "v.txt").string(), someVertices()).ok());
  EXPECT_FALSE(fs::exists(dir / "v.txt"));
  {
    std::ofstream f(dir / "broken.csv");
    f << "x,y,z,nx,ny,nz,r,g,b\n1,2,3,0,0,1,0.5,0.5,0.5\n1,2,oops,0,0,1,0.5,0.5,0.5\n";
  }
  auto broken = readVertices((dir / "broken.csv").string());
  ASSERT_FALSE(broken.ok());
  EXPECT_NE(broken.error().message.find("broken.csv:3:"), std::string::npos) << broken.error().message;
  {
    std::ofstream f(dir / "noheader.csv");
    f << "1,2,3,0,0,1,0.5,0.5,0.5\n";
  }
  EXPECT_FALSE(readVertices((dir / "noheader.csv").string()).ok());
  EXPECT_FALSE(readVertices((dir / "missing.csv").string()).ok());
}

// Found by fuzz/vertices_fuzz.cpp: "element vertex +" made std::stoull throw out of the reader.
// Also hand-made neighbours of it: a negative, a trailing word, an empty count.
TEST(VerticesTest, FuzzedVertexCountIsAnErrorNotAnException) {
  const std::string reproducer = std::string(LAMBERT_SOURCE_DIR) + "/tests/corpus/vertices/regression-vertex-count-not-a-number.ply";
  Result<std::vector<VertexSample>> fuzzed = readVertices(reproducer);
  ASSERT_FALSE(fuzzed.ok());
  EXPECT_NE(fuzzed.error().message.find("regression-vertex-count-not-a-number.ply:4: the vertex count '+' is not a whole number"), std::string::npos)
      << fuzzed.error().message;
  fs::path dir = scratch("fuzzed-count");
  for (const char* count : {"-1", "3 vertices", "", "99999999999999999999999"}) {
    {
      std::ofstream f(dir / "count.ply");
      f << "ply\nformat ascii 1.0\nelement vertex " << count << "\nend_header\n";
    }
    Result<std::vector<VertexSample>> read = readVertices((dir / "count.ply").string());
    ASSERT_FALSE(read.ok()) << count;
    EXPECT_NE(read.error().message.find("is not a whole number"), std::string::npos) << read.error().message;
  }
}

}  // namespace
}  // namespace lambert
