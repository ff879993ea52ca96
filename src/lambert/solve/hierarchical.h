#pragma once
// Gathering over the links of hierarchical radiosity (Hanrahan, Salzman & Aupperle 1991, §4):
// pull the leaves' radiosity up the hierarchy as area-weighted means, gather over every node's
// links, push what each node gathered down to the leaves under it. One gather costs
// O(nodes + links), against O(n²) for the dense matrix. formfactor/links.h makes the links.
#include <memory>
#include <span>
#include <vector>

#include "lambert/formfactor/links.h"
#include "lambert/mesh/element_hierarchy.h"
#include "lambert/solve/transport.h"

namespace lambert {

class HierarchicalTransport final : public Transport {
 public:
  // Copies what it needs of the hierarchy (which may be refined further afterwards).
  // leafOpenFraction: per leaf, the share not covered by other geometry (Patch::openFraction).
  HierarchicalTransport(const ElementHierarchy& hierarchy, std::shared_ptr<const Links> links,
                        std::span<const double> leafOpenFraction);

  std::size_t size() const override { return nodeOfLeaf_.size(); }
  void gather(const std::vector<Rgb>& radiosity, std::vector<Rgb>& irradiance) const override;
  // Jacobi: one gather from the previous iterate. Gauss–Seidel: nodes in order (parents first),
  // each gathering from the current means, and each new leaf value raising the means of its
  // ancestors at once, so later nodes gather it within the same sweep.
  SweepChange sweep(const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo, std::vector<Rgb>& radiosity,
                    bool inPlace) const override;

  const Links& links() const { return *links_; }
  // The radiosity every node shows to what its links reach, HSA'91's pull: the power of the
  // leaves under an element over their open area (where the floor runs under a block, the
  // covered part is dark, and the links' visibility rays already leave it out; a mean over the
  // whole area would count it out twice and dim everything the element lights); a cluster's
  // over all its area.
  void pull(const std::vector<Rgb>& radiosity, std::vector<Rgb>& mean) const;

 private:
  Rgb gatherNode(std::uint32_t node, const std::vector<Rgb>& mean) const;

  std::vector<std::uint32_t> parent_;
  std::vector<double> area_;
  std::vector<double> openArea_;  // of the leaves under each element; a cluster's whole area
  // A link's K is the irradiance of its receiver's open part (formfactor/links.h): a leaf takes
  // its open share f of what it and its ancestors gather, E = f·ΣK·B̄_s, a mean over its area.
  std::vector<double> leafOpenFraction_;
  std::vector<std::uint32_t> leafOfNode_;  // kNoNode for inner nodes
  std::vector<std::uint32_t> nodeOfLeaf_;
  std::shared_ptr<const Links> links_;
};

}  // namespace lambert
