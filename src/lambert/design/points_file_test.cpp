#include "lambert/design/points_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "lambert/core/text.h"
#include "lambert/core/warning.h"

namespace lambert {
namespace {

std::string written(const std::string& name, const std::string& text) {
  const std::string path = (std::filesystem::temp_directory_path() / ("lambert-points-" + name)).string();
  std::ofstream(path) << text;
  return path;
}

TEST(PointsFileTest, ReadsHeadersInAnyOrderAndKeepsOtherColumns) {
  const std::string path = written("header.csv", "# desks\nname,Z,x,y,NX,ny,nz\n\"desk 1\",3,1,0.8,0,1,0\ndesk 2,3.5,2,0.8,0,2,0\n");
  Result<PointsTable> table = readPointsCsv(path, FileFrame{});
  ASSERT_TRUE(table.ok()) << table.error().message;
  ASSERT_EQ(table->points.size(), 2u);
  EXPECT_EQ(table->points[1].position.x, 2);
  EXPECT_EQ(table->points[1].position.z, 3.5);
  EXPECT_EQ(table->points[1].normal.y, 1);  // normalised
  EXPECT_EQ(table->rows[0][0], "desk 1");
  const std::string out = written("header-out.csv", "");
  const std::vector<PointIrradiance> e{{.direct = Rgb::gray(1), .sky = Rgb::gray(0.25), .sun = Rgb::gray(0.5), .indirect = Rgb::gray(0.5)},
                                       {.direct = Rgb::gray(2), .sky = {}, .sun = {}, .indirect = {}}};
  ASSERT_TRUE(writePointsCsv(out, *table, e).ok());
  Result<std::string> text = readWholeFile(out);
  ASSERT_TRUE(text.ok());
  // 683 lm/W × the luminance of grey 1 W/m² (Rec. 709 weights sum to 1): 683 lx.
  EXPECT_EQ(*text, "name,Z,x,y,NX,ny,nz,E_direct,E_sky,E_sun,E_indirect,E\ndesk 1,3,1,0.8,0,1,0,683,170.75,341.5,341.5,1024.5\n"
                   "desk 2,3.5,2,0.8,0,2,0,1366,0,0,0,1366\n");
}

TEST(PointsFileTest, ReadsRowsWithoutAHeaderInTheFilesFrame) {
  // An MGF-like frame: file z is scene y (file (x, y, z) → scene (x, z, −y)), millimetres kept.
  FileFrame frame;
  frame.axes[0] = {1, 0, 0};
  frame.axes[1] = {0, 0, -1};
  frame.axes[2] = {0, 1, 0};
  frame.up = {0, 0, 1};
  const std::string path = written("plain.csv", "1 2 3 0 0 1\r\n4;5;6;0;0;-1\n");
  Result<PointsTable> table = readPointsCsv(path, frame);
  ASSERT_TRUE(table.ok()) << table.error().message;
  ASSERT_EQ(table->points.size(), 2u);
  EXPECT_EQ(table->points[0].position.y, 3);
  EXPECT_EQ(table->points[0].position.z, -2);
  EXPECT_EQ(table->points[0].normal.y, 1);
  EXPECT_EQ(table->points[1].normal.y, -1);
  EXPECT_EQ(table->header.size(), 6u);
  // Without normal columns: facing the file's up, with a warning.
  WarningCapture warnings;
  table = readPointsCsv(written("no-normals.csv", "x,y,z\n1,2,3\n"), frame);
  ASSERT_TRUE(table.ok());
  EXPECT_EQ(table->points[0].normal.y, 1);
  EXPECT_EQ(warnings.count("no-normals.csv:1"), 1);
}

TEST(PointsFileTest, RefusesWhatItCannotReadNamingTheLine) {
  struct Case {
    std::string text, expected;
  };
  for (const Case& c : {Case{"x,y,z,nx,ny,nz\n1,2,3,0,1,0\n1,2,zz,0,1,0\n", ":3: field 3"}, Case{"1,2,3,0,0,0\n", ":1: the normal"},
                        Case{"1,2,3,0,1\n", ":1: 5 fields"}, Case{"a,b,c\n", ":1: the header names no column \"x\""},
                        Case{"# nothing\n\n", "no points"}, Case{"1,2,3,0,1,nan\n", ":1: field 6"}}) {
    Result<PointsTable> table = readPointsCsv(written("bad.csv", c.text), FileFrame{});
    ASSERT_FALSE(table.ok()) << c.text;
    EXPECT_NE(table.error().message.find(c.expected), std::string::npos) << table.error().message;
    EXPECT_NE(table.error().message.find("lambert-points-bad.csv"), std::string::npos) << table.error().message;
  }
  EXPECT_FALSE(readPointsCsv("/nonexistent/points.csv", FileFrame{}).ok());
}

}  // namespace
}  // namespace lambert
