#include "lambert/flat/quadtree.h"

#include <algorithm>
#include <cmath>

namespace lambert {
namespace {

Vec3 bilinear(const std::array<Vec3, 4>& q, double u, double v) {
  return q[0] * ((1 - u) * (1 - v)) + q[1] * (u * (1 - v)) + q[2] * (u * v) + q[3] * ((1 - u) * v);
}

}  // namespace

Result<AdaptiveMesh> AdaptiveMesh::build(const Scene& scene, const QuadtreeOptions& options) {
  if (!(options.baseEdgeLength > 0)) return Error{"quad-tree: base edge length must be positive"};
  if (options.maxLevel < 0 || options.maxLevel > 12) return Error{"quad-tree: deepest level must be between 0 and 12"};
  static_assert(12 < (1 << kAddressLevelBits), "every level must fit in an address");
  if (scene.surfaces.size() > (std::size_t{1} << kAddressSurfaceBits))
    return Error{"quad-tree: " + std::to_string(scene.surfaces.size()) + " surfaces; cell addresses hold at most " +
                 std::to_string(std::size_t{1} << kAddressSurfaceBits)};
  // Cells along an edge at the deepest level, as a double first: the count may not fit any integer.
  const double maxFineCells = static_cast<double>(std::uint32_t{1} << kAddressCellBits);
  AdaptiveMesh mesh;
  mesh.options_ = options;
  const std::uint32_t scale = 1u << options.maxLevel;
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    const bool oneQuad = surface.vertices.size() == 4 &&
                         (surface.faces.empty() || surface.faces == std::vector<std::vector<std::uint32_t>>{{0, 1, 2, 3}});
    if (!oneQuad)
      return Error{"quad-tree: surface '" + surface.name + "' has " + std::to_string(surface.vertices.size()) +
                   " vertices in " + std::to_string(surfaceFaces(surface).size()) + " faces; adaptive meshing needs quads"};
    SurfaceGrid grid;
    for (int k = 0; k < 4; ++k) grid.corners[k] = surface.vertices[k];
    grid.twinned = surface.twin >= 0;
    const auto& c = grid.corners;
    double alongU = std::fmax(length(c[1] - c[0]), length(c[2] - c[3]));
    double alongV = std::fmax(length(c[3] - c[0]), length(c[2] - c[1]));
    const double fineAlong =
        std::fmax(std::ceil(alongU / options.baseEdgeLength - 1e-9), std::ceil(alongV / options.baseEdgeLength - 1e-9)) * scale;
    if (!(fineAlong <= maxFineCells))
      return Error{"quad-tree: surface '" + surface.name + "' needs more than " +
                   std::to_string(static_cast<std::uint64_t>(maxFineCells)) +
                   " cells along an edge at the deepest level, the most a cell address holds; use a longer base edge or fewer levels"};
    grid.baseColumns = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(std::ceil(alongU / options.baseEdgeLength - 1e-9)));
    grid.baseRows = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(std::ceil(alongV / options.baseEdgeLength - 1e-9)));
    grid.fineColumns = grid.baseColumns * scale;
    grid.fineRows = grid.baseRows * scale;
    grid.nodeVertex.assign(static_cast<std::size_t>(grid.fineColumns + 1) * (grid.fineRows + 1), -1);
    grid.firstFineVertex = mesh.fineMesh_.positions.size();
    for (std::uint32_t b = 0; b <= grid.fineRows; ++b)
      for (std::uint32_t a = 0; a <= grid.fineColumns; ++a) {
        mesh.fineMesh_.positions.push_back(mesh.gridPoint(grid, a, b));
        mesh.fineMesh_.vertexSurface.push_back(s);
      }
    for (std::uint32_t b = 0; b < grid.fineRows; ++b)
      for (std::uint32_t a = 0; a < grid.fineColumns; ++a) {
        auto at = [&](std::uint32_t x, std::uint32_t y) {
          return static_cast<std::uint32_t>(grid.firstFineVertex + static_cast<std::size_t>(y) * (grid.fineColumns + 1) + x);
        };
        const std::uint32_t quad[4] = {at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)};
        mesh.fineMesh_.patches.push_back(makePatch(mesh.fineMesh_.positions, quad, s));
        mesh.fineMesh_.patches.back().twinned = grid.twinned;
      }
    mesh.grids_.push_back(std::move(grid));
  }
  for (std::uint32_t s = 0; s < mesh.grids_.size(); ++s)
    for (std::uint32_t j = 0; j < mesh.grids_[s].baseRows; ++j)
      for (std::uint32_t i = 0; i < mesh.grids_[s].baseColumns; ++i) mesh.nodes_[mesh.createNode(s, 0, i, j, -1)].active = true;
  mesh.rebuildActiveList();
  return mesh;
}

std::uint64_t AdaptiveMesh::packAddress(std::uint32_t surface, int level, std::uint32_t i, std::uint32_t j) {
  LAMBERT_CHECK(surface < (std::uint64_t{1} << kAddressSurfaceBits));
  LAMBERT_CHECK(level >= 0 && level < (1 << kAddressLevelBits));
  LAMBERT_CHECK(i < (std::uint64_t{1} << kAddressCellBits) && j < (std::uint64_t{1} << kAddressCellBits));
  return (static_cast<std::uint64_t>(surface) << (kAddressLevelBits + 2 * kAddressCellBits)) |
         (static_cast<std::uint64_t>(level) << (2 * kAddressCellBits)) | (static_cast<std::uint64_t>(j) << kAddressCellBits) | i;
}

std::uint64_t AdaptiveMesh::address(std::uint32_t id) const {
  const QuadNode& n = nodes_[id];
  return packAddress(n.surface, n.level, n.i, n.j);
}

Vec3 AdaptiveMesh::gridPoint(const SurfaceGrid& grid, std::uint32_t a, std::uint32_t b) const {
  return bilinear(grid.corners, static_cast<double>(a) / grid.fineColumns, static_cast<double>(b) / grid.fineRows);
}

std::uint32_t AdaptiveMesh::nodeVertex(std::uint32_t surface, std::uint32_t a, std::uint32_t b) {
  SurfaceGrid& grid = grids_[surface];
  std::int32_t& index = grid.nodeVertex[static_cast<std::size_t>(b) * (grid.fineColumns + 1) + a];
  if (index < 0) {
    index = static_cast<std::int32_t>(nodeMesh_.positions.size());
    nodeMesh_.positions.push_back(gridPoint(grid, a, b));
    nodeMesh_.vertexSurface.push_back(surface);
  }
  return static_cast<std::uint32_t>(index);
}

std::uint32_t AdaptiveMesh::createNode(std::uint32_t surface, int level, std::uint32_t i, std::uint32_t j, std::int32_t parent) {
  QuadNode node;
  node.surface = surface;
  node.level = level;
  node.i = i;
  node.j = j;
  node.parent = parent;
  const std::uint32_t s = span(level), a = i * s, b = j * s;
  const std::uint32_t quad[4] = {nodeVertex(surface, a, b), nodeVertex(surface, a + s, b), nodeVertex(surface, a + s, b + s),
                                 nodeVertex(surface, a, b + s)};
  nodeMesh_.patches.push_back(makePatch(nodeMesh_.positions, quad, surface));
  nodeMesh_.patches.back().twinned = grids_[surface].twinned;
  nodes_.push_back(node);
  return static_cast<std::uint32_t>(nodes_.size() - 1);
}

std::uint32_t AdaptiveMesh::children(std::uint32_t id) {
  LAMBERT_CHECK(nodes_[id].level < options_.maxLevel);
  if (nodes_[id].firstChild < 0) {
    const QuadNode parent = nodes_[id];
    std::uint32_t first = 0;
    for (std::uint32_t k = 0; k < 4; ++k) {
      std::uint32_t child = createNode(parent.surface, parent.level + 1, 2 * parent.i + (k == 1 || k == 2),
                                       2 * parent.j + (k >= 2), static_cast<std::int32_t>(id));
      if (k == 0) first = child;
    }
    nodes_[id].firstChild = static_cast<std::int32_t>(first);
  }
  return static_cast<std::uint32_t>(nodes_[id].firstChild);
}

bool AdaptiveMesh::refine(std::uint32_t id) {
  LAMBERT_CHECK(nodes_[id].active);
  if (nodes_[id].level >= options_.maxLevel) return false;
  std::uint32_t first = children(id);
  nodes_[id].active = false;
  for (std::uint32_t k = 0; k < 4; ++k) nodes_[first + k].active = true;
  rebuildActiveList();
  return true;
}

void AdaptiveMesh::coarsen(std::uint32_t parent) {
  LAMBERT_CHECK(nodes_[parent].firstChild >= 0);
  const auto first = static_cast<std::uint32_t>(nodes_[parent].firstChild);
  for (std::uint32_t k = 0; k < 4; ++k) LAMBERT_CHECK(nodes_[first + k].active);
  for (std::uint32_t k = 0; k < 4; ++k) nodes_[first + k].active = false;
  nodes_[parent].active = true;
  rebuildActiveList();
}

void AdaptiveMesh::rebuildActiveList() {
  active_.clear();
  for (std::uint32_t id = 0; id < nodes_.size(); ++id)
    if (nodes_[id].active) active_.push_back(id);
}

Mesh AdaptiveMesh::activeMesh() const {
  Mesh mesh;
  mesh.positions = nodeMesh_.positions;
  mesh.vertexSurface = nodeMesh_.vertexSurface;
  mesh.patches.reserve(active_.size());
  for (std::uint32_t id : active_) mesh.patches.push_back(nodeMesh_.patches[id]);
  return mesh;
}

std::vector<std::array<Rgb, 4>> AdaptiveMesh::cornerRadiosity(const std::vector<Rgb>& activeRadiosity) const {
  LAMBERT_CHECK(activeRadiosity.size() == active_.size());
  // Per surface grid point: area-weighted sum and weight, then the hanging-node constraint.
  std::vector<std::vector<Rgb>> value(grids_.size());
  std::vector<std::vector<double>> weight(grids_.size());
  for (std::size_t s = 0; s < grids_.size(); ++s) {
    value[s].assign(grids_[s].nodeVertex.size(), Rgb{});
    weight[s].assign(grids_[s].nodeVertex.size(), 0.0);
  }
  auto gridIndex = [&](const SurfaceGrid& grid, std::uint32_t a, std::uint32_t b) {
    return static_cast<std::size_t>(b) * (grid.fineColumns + 1) + a;
  };
  auto cornerPoints = [&](const QuadNode& n) {
    const std::uint32_t s = span(n.level), a = n.i * s, b = n.j * s;
    return std::array<std::array<std::uint32_t, 2>, 4>{{{a, b}, {a + s, b}, {a + s, b + s}, {a, b + s}}};
  };
  for (std::size_t k = 0; k < active_.size(); ++k) {
    const QuadNode& n = nodes_[active_[k]];
    const double area = nodeMesh_.patches[active_[k]].area;
    for (auto [a, b] : cornerPoints(n)) {
      std::size_t g = gridIndex(grids_[n.surface], a, b);
      value[n.surface][g] += activeRadiosity[k] * area;
      weight[n.surface][g] += area;
    }
  }
  for (std::size_t s = 0; s < grids_.size(); ++s)
    for (std::size_t g = 0; g < value[s].size(); ++g)
      if (weight[s][g] > 0) value[s][g] = value[s][g] / weight[s][g];

  // Corners hanging on a coarser node's edge take the value along that edge. Coarse nodes go
  // first, so an edge's ends are final before the points on it are set.
  std::vector<std::uint32_t> byLevel = active_;
  std::stable_sort(byLevel.begin(), byLevel.end(), [&](std::uint32_t x, std::uint32_t y) { return nodes_[x].level < nodes_[y].level; });
  for (std::uint32_t id : byLevel) {
    const QuadNode& n = nodes_[id];
    const std::uint32_t s = span(n.level);
    if (s == 1) continue;
    const SurfaceGrid& grid = grids_[n.surface];
    auto corners = cornerPoints(n);
    for (int e = 0; e < 4; ++e) {
      auto [a0, b0] = corners[e];
      auto [a1, b1] = corners[(e + 1) % 4];
      const Rgb start = value[n.surface][gridIndex(grid, a0, b0)], end = value[n.surface][gridIndex(grid, a1, b1)];
      for (std::uint32_t t = 1; t < s; ++t) {
        std::uint32_t a = a0 + (static_cast<std::int64_t>(a1) - a0) * static_cast<std::int64_t>(t) / static_cast<std::int64_t>(s);
        std::uint32_t b = b0 + (static_cast<std::int64_t>(b1) - b0) * static_cast<std::int64_t>(t) / static_cast<std::int64_t>(s);
        std::size_t g = gridIndex(grid, a, b);
        if (weight[n.surface][g] > 0) value[n.surface][g] = start + (end - start) * (static_cast<double>(t) / s);
      }
    }
  }

  std::vector<std::array<Rgb, 4>> result(active_.size());
  for (std::size_t k = 0; k < active_.size(); ++k) {
    const QuadNode& n = nodes_[active_[k]];
    auto corners = cornerPoints(n);
    for (int c = 0; c < 4; ++c) result[k][c] = value[n.surface][gridIndex(grids_[n.surface], corners[c][0], corners[c][1])];
  }
  return result;
}

std::vector<Rgb> AdaptiveMesh::fineVertexRadiosity(const std::vector<Rgb>& activeRadiosity) const {
  std::vector<std::array<Rgb, 4>> corners = cornerRadiosity(activeRadiosity);
  std::vector<Rgb> fine(fineMesh_.numVertices());
  for (std::size_t k = 0; k < active_.size(); ++k) {
    const QuadNode& n = nodes_[active_[k]];
    const SurfaceGrid& grid = grids_[n.surface];
    const std::uint32_t s = span(n.level), a0 = n.i * s, b0 = n.j * s;
    const auto& c = corners[k];
    for (std::uint32_t y = 0; y <= s; ++y)
      for (std::uint32_t x = 0; x <= s; ++x) {
        double u = static_cast<double>(x) / s, v = static_cast<double>(y) / s;
        fine[grid.firstFineVertex + static_cast<std::size_t>(b0 + y) * (grid.fineColumns + 1) + a0 + x] =
            c[0] * ((1 - u) * (1 - v)) + c[1] * (u * (1 - v)) + c[2] * (u * v) + c[3] * ((1 - u) * v);
      }
  }
  return fine;
}

}  // namespace lambert
