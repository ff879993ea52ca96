#pragma once
// Adaptive quad-tree meshing (quad-tree subdivision at light, shadow and radiosity edges). Each quad surface is cut into a grid of level-0 cells no
// longer than a base edge length; any cell can be split into four children, down to a deepest
// level, and four sibling leaves merged back into their parent. Every node ever created keeps a
// unique id for the life of the mesh, so what is computed for a node (its form factors, in the
// master table) is found again when the node becomes active again. Ids follow the order cells were
// created in, so they differ between runs that refine differently; a node's address (surface,
// level, i, j) does not, and is what names it outside one run (the master table's file).
//
// All positions lie on each surface's finest grid (2^maxLevel × the base grid), so rendering can
// always use that finest level, with values interpolated from the active level: no T-junction
// cracks, and no steps where a coarse cell meets refined ones (where a plain quad-tree leaves T-junctions).
#include <array>
#include <cstdint>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/rgb.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"
#include "lambert/method/flat_options.h"

namespace lambert {


struct QuadNode {
  std::uint32_t surface = 0;
  int level = 0;
  std::uint32_t i = 0, j = 0;    // the cell's column and row in its surface's grid at its level
  std::int32_t parent = -1;
  std::int32_t firstChild = -1;  // children are firstChild … firstChild + 3, once created
  bool active = false;
};

class AdaptiveMesh {
 public:
  // Every surface must be a quad (four vertices); anything else is an error naming the surface.
  static Result<AdaptiveMesh> build(const Scene& scene, const QuadtreeOptions& options);

  const QuadtreeOptions& options() const { return options_; }
  std::size_t numNodes() const { return nodes_.size(); }
  const QuadNode& node(std::uint32_t id) const { return nodes_[id]; }

  // A node's stable address: the same cell has the same address in every run of the same scene
  // and options, whatever order cells were refined in. Bits, most significant first:
  //   63–44  surface (20 bits)
  //   43–40  level   (4 bits)
  //   39–20  j, the row at that level    (20 bits)
  //   19–0   i, the column at that level (20 bits)
  // so addresses order cells by surface, then level, row and column. build() rejects scenes and
  // options whose cells would not fit.
  std::uint64_t address(std::uint32_t id) const;
  static constexpr int kAddressSurfaceBits = 20, kAddressLevelBits = 4, kAddressCellBits = 20;
  static std::uint64_t packAddress(std::uint32_t surface, int level, std::uint32_t i, std::uint32_t j);
  // Every node ever created, as a patch: patch id = node id. It grows as nodes are created.
  const Mesh& nodeMesh() const { return nodeMesh_; }

  // The active leaves, in ascending id order, and a mesh of them (patch k is activeNodes()[k]).
  const std::vector<std::uint32_t>& activeNodes() const { return active_; }
  Mesh activeMesh() const;

  // Replaces an active node by its four children, creating them on first use; false (nothing
  // done) at the deepest level.
  bool refine(std::uint32_t id);
  // The four children a refine would make, created if needed, without activating anything.
  std::uint32_t children(std::uint32_t id);
  // Replaces four active sibling leaves by their parent.
  void coarsen(std::uint32_t parent);

  // Radiosity at the four corners of each active node (same order as activeNodes(), corners
  // counter-clockwise): area-weighted averages of the active nodes meeting there, except where a
  // corner hangs on a coarser node's edge, where it follows that edge linearly.
  std::vector<std::array<Rgb, 4>> cornerRadiosity(const std::vector<Rgb>& activeRadiosity) const;

  // The finest level of every surface (quads), built once; and its per-vertex radiosity,
  // interpolated bilinearly inside each active node from that node's corner radiosity.
  const Mesh& fineMesh() const { return fineMesh_; }
  std::vector<Rgb> fineVertexRadiosity(const std::vector<Rgb>& activeRadiosity) const;

 private:
  struct SurfaceGrid {
    std::array<Vec3, 4> corners;
    std::uint32_t baseColumns = 1, baseRows = 1;  // level-0 cells along v0→v1 and v0→v3
    std::uint32_t fineColumns = 1, fineRows = 1;  // finest-level cells
    std::size_t firstFineVertex = 0;              // offset of this surface's grid in fineMesh_
    std::vector<std::int32_t> nodeVertex;         // grid point → nodeMesh_ vertex, −1 until used
    bool twinned = false;                         // the surface has a back-to-back twin
  };

  Vec3 gridPoint(const SurfaceGrid& grid, std::uint32_t a, std::uint32_t b) const;
  std::uint32_t nodeVertex(std::uint32_t surface, std::uint32_t a, std::uint32_t b);
  std::uint32_t span(int level) const { return 1u << (options_.maxLevel - level); }
  std::uint32_t createNode(std::uint32_t surface, int level, std::uint32_t i, std::uint32_t j, std::int32_t parent);
  void rebuildActiveList();

  QuadtreeOptions options_;
  std::vector<SurfaceGrid> grids_;
  std::vector<QuadNode> nodes_;
  Mesh nodeMesh_;
  Mesh fineMesh_;
  std::vector<std::uint32_t> active_;
};

}  // namespace lambert
