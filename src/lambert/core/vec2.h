#pragma once
// Small 2-vector for geometry in a plane: a chart's coordinates, a polygon in its own plane.
namespace lambert {

struct Vec2 {
  double x = 0, y = 0;
};

constexpr Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
// The z component of the 3-D cross product: twice the signed area of the triangle (0, a, b),
// positive where b lies counter-clockwise of a.
constexpr double cross2(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

}  // namespace lambert
