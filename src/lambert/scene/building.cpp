#include "lambert/scene/building.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/rng.h"

namespace lambert {
namespace {

constexpr double kRoomWidth = 4, kRoomDepth = 4, kHeight = 2.8, kWall = 0.2, kCorridor = 2;
constexpr double kDoorAt = 1.5, kDoorWidth = 1, kDoorHeight = 2.1, kWindowWidth = 2, kWindowSill = 0.9, kWindowTop = 2.1;
constexpr int kRoomsPerSide = 8;
constexpr double kStorey = kHeight + 0.3;  // floor to floor: a 0.3 m slab

enum MaterialId { kWallMaterial, kFloorMaterial, kCeilingMaterial, kLampMaterial, kWoodMaterial, kFabricMaterial };

class Builder {
 public:
  Builder(Scene& scene, double faceSize) : scene_(scene), faceSize_(faceSize) {}

  // A rectangle from corner `o` along `u` and `v`; its front is u × v. Split into a grid of faces.
  void rectangle(const std::string& name, int material, const Vec3& o, const Vec3& u, const Vec3& v) {
    const int nu = faceSize_ > 0 ? std::max(1, static_cast<int>(std::ceil(length(u) / faceSize_ - 1e-9))) : 1;
    const int nv = faceSize_ > 0 ? std::max(1, static_cast<int>(std::ceil(length(v) / faceSize_ - 1e-9))) : 1;
    Surface s;
    s.name = name;
    s.material = material;
    if (material == kLampMaterial) s.emittedRadiance = {40, 38, 34};
    for (int j = 0; j <= nv; ++j)
      for (int i = 0; i <= nu; ++i) s.vertices.push_back(o + u * (static_cast<double>(i) / nu) + v * (static_cast<double>(j) / nv));
    if (nu > 1 || nv > 1)
      for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
          auto at = [&](int a, int b) { return static_cast<std::uint32_t>(b * (nu + 1) + a); };
          s.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    else
      s.vertices = {o, o + u, o + u + v, o + v};
    scene_.surfaces.push_back(std::move(s));
  }

  // An axis-aligned box standing on y = lo.y, faces outward (its bottom is not drawn: it stands).
  void box(const std::string& name, int material, const Vec3& lo, const Vec3& hi) {
    const Vec3 d = hi - lo;
    rectangle(name + " top", material, {lo.x, hi.y, lo.z}, {0, 0, d.z}, {d.x, 0, 0});
    rectangle(name + " -x", material, lo, {0, 0, d.z}, {0, d.y, 0});
    rectangle(name + " +x", material, {hi.x, lo.y, lo.z}, {0, d.y, 0}, {0, 0, d.z});
    rectangle(name + " -z", material, lo, {0, d.y, 0}, {d.x, 0, 0});
    rectangle(name + " +z", material, {lo.x, lo.y, hi.z}, {d.x, 0, 0}, {0, d.y, 0});
  }

  // A wall in the plane through `o` spanning `along` (horizontal) and up to `height`, facing
  // `u × up`, with an opening [a0, a1] × [y0, y1] (a along the wall, y above o), lined by
  // reveals `depth` deep behind the wall (away from its front).
  void wallWithOpening(const std::string& name, const Vec3& o, const Vec3& along, double height, double a0, double a1, double y0,
                       double y1, double depth) {
    const Vec3 u = normalize(along), up{0, 1, 0};
    const double w = length(along);
    const Vec3 back = cross(up, u) * depth;  // front is u × up; reveals go the other way
    rectangle(name + " left", kWallMaterial, o, u * a0, up * height);
    rectangle(name + " right", kWallMaterial, o + u * a1, u * (w - a1), up * height);
    if (y0 > 0) rectangle(name + " below", kWallMaterial, o + u * a0, u * (a1 - a0), up * y0);
    rectangle(name + " above", kWallMaterial, o + u * a0 + up * y1, u * (a1 - a0), up * (height - y1));
    if (depth <= 0) return;  // the other side of the wall lines the opening
    // Reveals face into the opening: the left one along +u, the right one along −u, the head
    // down, the sill up.
    rectangle(name + " reveal left", kWallMaterial, o + u * a0 + up * y0, back, up * (y1 - y0));
    rectangle(name + " reveal right", kWallMaterial, o + u * a1 + up * y0, up * (y1 - y0), back);
    rectangle(name + " reveal top", kWallMaterial, o + u * a0 + up * y1, back, u * (a1 - a0));
    if (y0 > 0) rectangle(name + " sill", kWallMaterial, o + u * a0 + up * y0, u * (a1 - a0), back);
  }

 private:
  Scene& scene_;
  double faceSize_;
};

}  // namespace

Result<Scene> generateBuilding(const BuildingOptions& options) {
  if (options.rooms < 1 || options.rooms > 100000) return Error{"building: rooms must be between 1 and 100000"};
  if (!(options.faceSize >= 0) || (options.faceSize > 0 && options.faceSize < 0.01))
    return Error{"building: the face size must be 0 (whole rectangles) or at least 0.01 m"};
  Scene scene;
  scene.name = "building-" + std::to_string(options.rooms);
  scene.metresPerUnit = 1;
  scene.materials = {{"wall", Rgb::gray(0.7)},       {"floor", {0.45, 0.4, 0.35}}, {"ceiling", Rgb::gray(0.8)},
                     {"lamp", Rgb::gray(0.5)},       {"wood", {0.5, 0.32, 0.18}},  {"fabric", {0.25, 0.3, 0.5}}};
  Builder b(scene, options.faceSize);
  Pcg32 rng(options.seed, 0x6275696c64ULL);
  const int perStorey = 2 * kRoomsPerSide;
  const int storeys = (options.rooms + perStorey - 1) / perStorey;
  const double pitch = kRoomWidth + kWall;
  for (int storey = 0; storey < storeys; ++storey) {
    const double y = storey * kStorey;
    const int roomsHere = std::min(perStorey, options.rooms - storey * perStorey);
    const int alongCorridor = std::min(kRoomsPerSide, roomsHere);
    const double length = alongCorridor * pitch - kWall;
    // The corridor runs along x between z = 0 and z = kCorridor.
    const std::string c = "storey " + std::to_string(storey + 1) + " corridor";
    b.rectangle(c + " floor", kFloorMaterial, {0, y, 0}, {0, 0, kCorridor}, {length, 0, 0});
    b.rectangle(c + " ceiling", kCeilingMaterial, {0, y + kHeight, 0}, {length, 0, 0}, {0, 0, kCorridor});
    b.rectangle(c + " west end", kWallMaterial, {0, y, 0}, {0, kHeight, 0}, {0, 0, kCorridor});
    b.rectangle(c + " east end", kWallMaterial, {length, y, 0}, {0, 0, kCorridor}, {0, kHeight, 0});
    for (int k = 0; k < alongCorridor; ++k)
      b.rectangle(c + " lamp " + std::to_string(k + 1), kLampMaterial, {k * pitch + 1.7, y + kHeight - 0.01, 0.7}, {0.6, 0, 0},
                  {0, 0, 0.6});
    for (int side = 0; side < 2; ++side) {
      const int count = side == 0 ? alongCorridor : roomsHere - alongCorridor;
      // The corridor's wall on this side: one wall with a door per room (and blank beyond).
      for (int k = 0; k < alongCorridor; ++k) {
        const double x0 = k * pitch;
        const std::string w = c + (side ? " north" : " south") + " wall " + std::to_string(k + 1);
        const double span = k + 1 < alongCorridor ? pitch : kRoomWidth;
        const bool door = k < count;
        // Doors at x0 + [1.5, 2.5] on both sides; a wall faces along × up.
        if (side == 0) {  // z = 0, facing +z
          if (door) b.wallWithOpening(w, {x0, y, 0}, {span, 0, 0}, kHeight, kDoorAt, kDoorAt + kDoorWidth, 0, kDoorHeight, kWall);
          else b.rectangle(w, kWallMaterial, {x0, y, 0}, {span, 0, 0}, {0, kHeight, 0});
        } else {  // z = kCorridor, facing −z
          if (door)
            b.wallWithOpening(w, {x0 + span, y, kCorridor}, {-span, 0, 0}, kHeight, span - kDoorAt - kDoorWidth, span - kDoorAt, 0,
                              kDoorHeight, kWall);
          else b.rectangle(w, kWallMaterial, {x0, y, kCorridor}, {0, kHeight, 0}, {span, 0, 0});
        }
      }
      for (int k = 0; k < count; ++k) {
        // The room spans x in [x0, x0 + kRoomWidth], z away from the corridor by kWall.
        const double x0 = k * pitch;
        const double zNear = side ? kCorridor + kWall : -kWall, zFar = side ? zNear + kRoomDepth : zNear - kRoomDepth;
        const double sz = side ? 1 : -1;  // +z or −z away from the corridor
        const std::string r = "storey " + std::to_string(storey + 1) + (side ? " north" : " south") + " room " + std::to_string(k + 1);
        const double zLo = std::min(zNear, zFar), depth = kRoomDepth;
        b.rectangle(r + " floor", kFloorMaterial, {x0, y, zLo}, {0, 0, depth}, {kRoomWidth, 0, 0});
        b.rectangle(r + " ceiling", kCeilingMaterial, {x0, y + kHeight, zLo}, {kRoomWidth, 0, 0}, {0, 0, depth});
        b.rectangle(r + " west", kWallMaterial, {x0, y, zLo}, {0, kHeight, 0}, {0, 0, depth});
        b.rectangle(r + " east", kWallMaterial, {x0 + kRoomWidth, y, zLo}, {0, 0, depth}, {0, kHeight, 0});
        // The door wall (towards the corridor) and the window wall, each facing into the room.
        const double windowAt = (kRoomWidth - kWindowWidth) / 2;
        if (side == 0) {  // the door wall faces −z, the window wall +z
          b.wallWithOpening(r + " door wall", {x0 + kRoomWidth, y, zNear}, {-kRoomWidth, 0, 0}, kHeight, kRoomWidth - kDoorAt - kDoorWidth,
                            kRoomWidth - kDoorAt, 0, kDoorHeight, 0);
          b.wallWithOpening(r + " window wall", {x0, y, zFar}, {kRoomWidth, 0, 0}, kHeight, windowAt, windowAt + kWindowWidth, kWindowSill,
                            kWindowTop, kWall);
        } else {  // the door wall faces +z, the window wall −z
          b.wallWithOpening(r + " door wall", {x0, y, zNear}, {kRoomWidth, 0, 0}, kHeight, kDoorAt, kDoorAt + kDoorWidth, 0, kDoorHeight, 0);
          b.wallWithOpening(r + " window wall", {x0 + kRoomWidth, y, zFar}, {-kRoomWidth, 0, 0}, kHeight, windowAt, windowAt + kWindowWidth,
                            kWindowSill, kWindowTop, kWall);
        }
        b.rectangle(r + " lamp", kLampMaterial, {x0 + 1.7, y + kHeight - 0.01, zLo + 1.7}, {0.6, 0, 0}, {0, 0, 0.6});
        // Furniture: a desk and one or two cabinets, placed by the seed.
        auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * rng.nextDouble(); };
        // The desk stays between x0 + 0.8 and x0 + 3.4, the cabinets outside that, by the side walls.
        const double deskX = x0 + uniform(0.8, 2.0), deskZ = zNear + sz * uniform(1.2, 2.4);
        b.box(r + " desk", kWoodMaterial, {deskX, y, std::min(deskZ, deskZ + sz * 0.8)}, {deskX + 1.4, y + 0.75, std::max(deskZ, deskZ + sz * 0.8)});
        const int cabinets = 1 + static_cast<int>(rng.nextUint() % 2);
        for (int n = 0; n < cabinets; ++n) {
          const double cx = n == 0 ? x0 + 0.05 : x0 + kRoomWidth - 0.55, cz = zFar - sz * uniform(0.6, 1.4);
          b.box(r + " cabinet " + std::to_string(n + 1), kFabricMaterial, {cx, y, std::min(cz, cz - sz * 0.5)},
                {cx + 0.5, y + uniform(0.8, 1.8), std::max(cz, cz - sz * 0.5)});
        }
      }
    }
  }
  // The camera: in the first room, by its door, looking at its window.
  scene.camera.eye = {0.6, 1.6, -kWall - 0.4};  // the first room: south side, x in [0, 4]
  scene.camera.target = {2.4, 1.2, -kWall - kRoomDepth};
  scene.camera.verticalFovDegrees = 60;
  return scene;
}

}  // namespace lambert
