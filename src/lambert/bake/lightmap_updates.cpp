#include "lambert/bake/lightmap_updates.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "lambert/core/parallel.h"
#include "lambert/core/timer.h"
#include "lambert/method/point_gather.h"
#include "lambert/engine/solution_internals.h"
#include "lambert/light/sky.h"
#include "lambert/light/lights.h"

namespace lambert {
namespace {

constexpr std::uint32_t kNoTexel = std::numeric_limits<std::uint32_t>::max();
// Four lattice texels interpolate a texel between them where their faces' normals agree to this
// (one plane, or a gently curved surface).
constexpr double kSamePlaneCosine = 0.999;
// A texel is gathered itself where the lattice's interpolation of the bake's light from the
// surfaces misses the texel's own by more than this share (of it, or of a twentieth of the mean).
constexpr double kInterpolationTolerance = 0.05;
// An update reads a node's weights where its change × its largest weight exceeds this share of the
// mean texel irradiance (and a corner vertex's where its change does).
constexpr double kChangeTolerance = 1e-4;

// Whether the light can reach a point facing `normal` at all (before any shadow ray): in front of
// the surface, and for a spot inside its cone. Light::irradiance gives zero wherever this is false.
bool mayLight(const Light& light, const VertexSite& site) {
  switch (light.kind) {
    case LightKind::Directional:
      return dot(site.normal, light.direction) < 0;
    case LightKind::Point:
      return dot(site.normal, light.position - site.point) > 0;
    case LightKind::Luminaire:
      // An opening's sources lie off its centre, so only the far-field point is judged by it.
      return light.luminaireModel != LuminaireModel::FarField || dot(site.normal, light.position - site.point) > 0;
    case LightKind::Spot: {
      const Vec3 toPoint = site.point - light.position;
      const double distance = length(toPoint);
      if (!(distance > 0) || !(dot(site.normal, toPoint) < 0)) return false;
      return dot(toPoint / distance, normalize(light.direction)) >= std::cos(light.coneAngleDegrees * kPi / 180) - 1e-9;
    }
    case LightKind::Sky:  // every site but one facing straight down sees some of the sky (any, an environment)
      return light.sky != nullptr && (light.sky->isUniformEnvironment() || site.normal.y > -1 + 1e-12);
  }
  return true;
}

}  // namespace

Result<LightmapUpdater> LightmapUpdater::create(const SolutionView& view, const BakedLightmaps& baked, const LightmapUpdateOptions& options) {
  Timer timer;
  if (options.latticeStep < 1) return Error{"lightmap updates: latticeStep must be at least 1"};
  const Scene& scene = view.scene();
  LightmapUpdater u;
  u.uvs_ = baked.uvs;
  u.covered_ = baked.covered;
  u.paddingRings_ = baked.paddingRings;
  const LightmapTexels texels = lightmapTexels(scene, baked.uvs);
  if (texels.points.size() != baked.texelsBaked)
    return Error{"lightmap updates: the lightmaps were not baked over this scene's faces (" + std::to_string(baked.texelsBaked) +
                 " texels baked, " + std::to_string(texels.points.size()) + " here)"};
  const std::size_t n = texels.points.size();
  const int size = baked.uvs.size;
  const std::uint64_t perAtlas = static_cast<std::uint64_t>(size) * size;
  u.texel_.resize(n);
  u.baked_.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    u.texel_[t] = texels.atlas[t] * perAtlas + texels.texel[t];
    u.baked_[t] = baked.irradiance[texels.atlas[t]].pixels[texels.texel[t]];
  }
  Result<PointGather> sites = pointGather(view, texels.points, PointGatherRequest::Sites);
  if (!sites) return sites.error();
  u.site_ = std::move(sites->sites);
  u.rayEpsilon_ = sites->rayEpsilon;

  // The lights' direct light per texel, as the bake traced it, and per corner vertex.
  u.lights_ = view.lights();
  const double metresPerUnit = scene.metresPerUnit;
  const auto traceAll = [&](const std::vector<VertexSite>& sites, std::vector<std::vector<Rgb>>& direct, std::vector<Rgb>& total) {
    direct.assign(u.lights_.size(), std::vector<Rgb>(sites.size()));
    total.assign(sites.size(), Rgb{});
    parallelFor(0, sites.size(), [&](std::size_t t) {
      for (std::size_t l = 0; l < u.lights_.size(); ++l) {
        direct[l][t] = irradiance(u.lights_[l], sites[t].point, sites[t].normal, view.caster(), u.rayEpsilon_, metresPerUnit);
        total[t] += direct[l][t];
      }
    }, 256);
  };
  traceAll(u.site_, u.direct_, u.bakedDirect_);
  // The lattice: per atlas texel, the covered texel there (or none).
  std::vector<std::uint32_t> at(perAtlas * static_cast<std::uint64_t>(baked.uvs.numAtlases), kNoTexel);
  for (std::size_t t = 0; t < n; ++t) at[u.texel_[t]] = static_cast<std::uint32_t>(t);
  std::vector<std::uint32_t> gatherPointOf(n, kNoTexel);
  std::vector<SurfacePoint> gatherPoints;
  const auto gatherPoint = [&](std::uint32_t t) {
    if (gatherPointOf[t] == kNoTexel) {
      gatherPointOf[t] = static_cast<std::uint32_t>(gatherPoints.size());
      gatherPoints.push_back(texels.points[t]);
    }
    return gatherPointOf[t];
  };
  const int step = options.latticeStep;
  u.interpStart_.assign(1, 0);
  for (std::size_t t = 0; t < n; ++t) {
    const std::uint64_t atlasBase = u.texel_[t] - texels.texel[t];
    const int x = static_cast<int>(texels.texel[t] % size), y = static_cast<int>(texels.texel[t] / size);
    const int x0 = x - x % step, y0 = y - y % step;
    const double fx = static_cast<double>(x - x0) / step, fy = static_cast<double>(y - y0) / step;
    const int cx[4] = {x0, x0 + step, x0, x0 + step}, cy[4] = {y0, y0, y0 + step, y0 + step};
    const double w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    std::uint32_t corner[4];
    bool usable = true;
    for (int k = 0; k < 4 && usable; ++k) {
      corner[k] = kNoTexel;
      if (w[k] == 0) continue;
      if (cx[k] >= size || cy[k] >= size) {
        usable = false;
        break;
      }
      const std::uint32_t c = at[atlasBase + static_cast<std::uint64_t>(cy[k]) * size + cx[k]];
      usable = c != kNoTexel && texels.points[c].surface == texels.points[t].surface &&
               dot(texels.points[c].normal, texels.points[t].normal) >= kSamePlaneCosine;
      corner[k] = c;
    }
    if (!usable) {
      u.interpPoint_.push_back(gatherPoint(static_cast<std::uint32_t>(t)));
      u.interpWeight_.push_back(1);
    } else {
      for (int k = 0; k < 4; ++k)
        if (w[k] != 0) {
          u.interpPoint_.push_back(gatherPoint(corner[k]));
          u.interpWeight_.push_back(static_cast<float>(w[k]));
        }
    }
    u.interpStart_.push_back(static_cast<std::uint32_t>(u.interpPoint_.size()));
  }
  std::vector<std::uint32_t>().swap(at);

  // The weights at the gather points, and the solution they were recorded against.
  Result<PointGather> gathered = pointGather(view, gatherPoints, PointGatherRequest::Weights);
  if (!gathered) return gathered.error();
  u.nodeWeights_ = std::move(gathered->nodes);
  u.cornerWeights_ = std::move(gathered->near);
  std::vector<Rgb>().swap(u.cornerWeights_.meanPart);
  // Where a lattice texel sees another surface from close by (a room's corner line, a block's
  // foot), the light's change varies over less than a lattice cell: the texels interpolated from
  // it are gathered themselves (without this, the Cornell box's updated floor and walls along
  // their corner lines were up to 60–130% of the mean off a fresh bake; with it, as every texel).
  const std::size_t latticePoints = gatherPoints.size();
  // And where the bake's own light from the surfaces is not what the lattice interpolates (a
  // block's foot, a shadow's edge, a lattice texel under a block): the change will not be either.
  const auto surfacesAt = [&](std::uint32_t t) { return u.baked_[t] - u.bakedDirect_[t]; };
  std::vector<std::uint32_t> latticeTexel(latticePoints);
  for (std::size_t t = 0; t < n; ++t)
    if (gatherPointOf[t] != kNoTexel) latticeTexel[gatherPointOf[t]] = static_cast<std::uint32_t>(t);
  double meanSurfaces = 0;
  for (std::size_t t = 0; t < n; ++t) meanSurfaces += surfacesAt(static_cast<std::uint32_t>(t)).maxComponent() / static_cast<double>(n);
  const double floor = 0.05 * meanSurfaces;
  for (std::size_t t = 0; t < n; ++t) {
    const std::uint32_t first = u.interpStart_[t], last = u.interpStart_[t + 1];
    if (last - first < 2) continue;
    bool close = false;
    Rgb predicted;  // the baked surfaces' light interpolated as the change would be
    for (std::uint32_t k = first; k < last; ++k) {
      const std::uint32_t g = u.interpPoint_[k];
      close = close || u.cornerWeights_.start[g + 1] > u.cornerWeights_.start[g];
      predicted += surfacesAt(latticeTexel[g]) * u.interpWeight_[k];
    }
    const Rgb actual = surfacesAt(static_cast<std::uint32_t>(t));
    const double miss = std::fmax((predicted - actual).maxComponent(), (actual - predicted).maxComponent());
    if (!close && !(miss > kInterpolationTolerance * std::fmax(actual.maxComponent(), floor))) continue;
    // The texel's own gather point (a lattice texel's is already there), its weight 1 and the
    // rest 0: the lists keep their places.
    const std::uint32_t own = gatherPoint(static_cast<std::uint32_t>(t));
    u.interpPoint_[first] = own;
    u.interpWeight_[first] = 1;
    for (std::uint32_t k = first + 1; k < last; ++k) u.interpWeight_[k] = 0;
  }
  if (gatherPoints.size() > latticePoints) {
    const std::vector<SurfacePoint> refined(gatherPoints.begin() + static_cast<std::ptrdiff_t>(latticePoints), gatherPoints.end());
    Result<PointGather> more = pointGather(view, refined, PointGatherRequest::Weights);
    if (!more) return more.error();
    // Appended to the lattice points' lists.
    const auto append = [](std::vector<std::uint32_t>& start, const std::vector<std::uint32_t>& moreStart) {
      const std::uint32_t base = start.back();
      for (std::size_t i = 1; i < moreStart.size(); ++i) start.push_back(base + moreStart[i]);
    };
    append(u.nodeWeights_.start, more->nodes.start);
    u.nodeWeights_.node.insert(u.nodeWeights_.node.end(), more->nodes.node.begin(), more->nodes.node.end());
    u.nodeWeights_.weight.insert(u.nodeWeights_.weight.end(), more->nodes.weight.begin(), more->nodes.weight.end());
    append(u.cornerWeights_.start, more->near.start);
    u.cornerWeights_.corner.insert(u.cornerWeights_.corner.end(), more->near.corner.begin(), more->near.corner.end());
    u.cornerWeights_.weight.insert(u.cornerWeights_.weight.end(), more->near.weight.begin(), more->near.weight.end());
  }
  // The corner vertices those weights read, renumbered among themselves, and their own gather.
  u.cornerVertex_ = u.cornerWeights_.corner;
  std::sort(u.cornerVertex_.begin(), u.cornerVertex_.end());
  u.cornerVertex_.erase(std::unique(u.cornerVertex_.begin(), u.cornerVertex_.end()), u.cornerVertex_.end());
  const auto subsetIndex = [&](std::uint32_t vertex) {
    const auto it = std::lower_bound(u.cornerVertex_.begin(), u.cornerVertex_.end(), vertex);
    return it != u.cornerVertex_.end() && *it == vertex ? static_cast<std::uint32_t>(it - u.cornerVertex_.begin()) : kNoTexel;
  };
  for (std::uint32_t& c : u.cornerWeights_.corner) c = subsetIndex(c);
  Result<PointGather> corners = vertexGather(view, u.cornerVertex_, PointGatherRequest::Weights);
  if (!corners) return corners.error();
  u.vertexNodeWeights_ = std::move(corners->nodes);
  u.vertexNearWeights_ = std::move(corners->near);
  std::vector<Rgb>().swap(u.vertexNearWeights_.meanPart);
  u.nearInSubset_.resize(u.vertexNearWeights_.corner.size());
  for (std::size_t k = 0; k < u.nearInSubset_.size(); ++k) u.nearInSubset_[k] = subsetIndex(u.vertexNearWeights_.corner[k]);
  u.vertexSite_ = std::move(corners->sites);
  u.vertexAlbedo_.assign(u.cornerVertex_.size(), Rgb{});
  for (std::size_t i = 0; i < u.cornerVertex_.size(); ++i)
    if (corners->leaf[i] != PointGather::kNoLeaf) u.vertexAlbedo_[i] = view.albedo()[corners->leaf[i]];
  Result<std::vector<Rgb>> mean = nodeMeanRadiosity(view);
  if (!mean) return mean.error();
  u.bakedNodeMean_ = std::move(*mean);
  u.bakedLeafRadiosity_ = view.radiosity();

  traceAll(u.vertexSite_, u.vertexDirect_, u.bakedVertexDirect_);
  // The inverted indices: per node the gather points and corner vertices its weights reach, per
  // corner vertex the gather points.
  const auto invert = [](const std::vector<std::uint32_t>& start, const std::vector<std::uint32_t>& target, std::size_t targets,
                         std::vector<std::uint32_t>& outStart, std::vector<std::uint32_t>& out) {
    outStart.assign(targets + 1, 0);
    for (std::uint32_t t : target) ++outStart[t + 1];
    for (std::size_t i = 0; i < targets; ++i) outStart[i + 1] += outStart[i];
    out.resize(target.size());
    std::vector<std::uint32_t> next(outStart.begin(), outStart.end() - 1);
    for (std::size_t row = 0; row + 1 < start.size(); ++row)
      for (std::uint32_t k = start[row]; k < start[row + 1]; ++k) out[next[target[k]]++] = static_cast<std::uint32_t>(row);
  };
  const std::size_t numNodes = u.bakedNodeMean_.size();
  invert(u.nodeWeights_.start, u.nodeWeights_.node, numNodes, u.pointsOfNodeStart_, u.pointsOfNode_);
  invert(u.vertexNodeWeights_.start, u.vertexNodeWeights_.node, numNodes, u.cornersOfNodeStart_, u.cornersOfNode_);
  invert(u.cornerWeights_.start, u.cornerWeights_.corner, u.cornerVertex_.size(), u.pointsOfCornerStart_, u.pointsOfCorner_);
  u.nodeLargestWeight_.assign(numNodes, 0.0f);
  for (std::size_t k = 0; k < u.nodeWeights_.size(); ++k)
    u.nodeLargestWeight_[u.nodeWeights_.node[k]] = std::fmax(u.nodeLargestWeight_[u.nodeWeights_.node[k]], std::fabs(u.nodeWeights_.weight[k]));
  for (std::size_t k = 0; k < u.vertexNodeWeights_.size(); ++k)
    u.nodeLargestWeight_[u.vertexNodeWeights_.node[k]] =
        std::fmax(u.nodeLargestWeight_[u.vertexNodeWeights_.node[k]], std::fabs(u.vertexNodeWeights_.weight[k]));
  double meanIrradiance = 0;
  for (const Rgb& e : u.baked_) meanIrradiance += e.maxComponent() / static_cast<double>(n);
  u.changeFloor_ = kChangeTolerance * meanIrradiance;
  u.fill_ = LightmapFill::plan(scene, u.uvs_, u.covered_, u.paddingRings_);
  u.texelChanged_.assign(n, 1);  // the first update writes every texel
  u.seamTexel_.assign(n, 0);
  for (std::size_t t = 0; t < n; ++t)
    u.seamTexel_[t] = std::binary_search(u.fill_.seamTexels().begin(), u.fill_.seamTexels().end(), u.texel_[t]);
  u.lightmaps_.assign(static_cast<std::size_t>(baked.uvs.numAtlases), Image{size, size, std::vector<Rgb>(perAtlas)});

  u.stats_.texels = n;
  u.stats_.gatherPoints = gatherPoints.size();
  u.stats_.weights = u.nodeWeights_.size() + u.cornerWeights_.size();
  u.stats_.bytes = u.nodeWeights_.bytes() + u.cornerWeights_.start.size() * 4 + u.cornerWeights_.size() * 8 +
                   n * (sizeof(std::uint64_t) + sizeof(VertexSite) + 2 * sizeof(Rgb) + u.lights_.size() * sizeof(Rgb)) +
                   u.interpPoint_.size() * 8 + u.interpStart_.size() * 4 +
                   (u.bakedNodeMean_.size() + u.bakedLeafRadiosity_.size()) * sizeof(Rgb);
  u.stats_.createSeconds = timer.seconds();
  return u;
}

Status LightmapUpdater::update(const SolutionView& view) {
  Timer timer;
  const std::size_t n = texel_.size();
  Result<std::vector<Rgb>> mean = nodeMeanRadiosity(view);
  if (!mean) return mean.error();
  if (mean->size() != bakedNodeMean_.size() || view.radiosity().size() != bakedLeafRadiosity_.size())
    return Error{"lightmap updates: the solution is not the one the updater was created from (its hierarchy differs)"};
  std::vector<Rgb>& meanChange = *mean;
  parallelFor(0, meanChange.size(), [&](std::size_t i) { meanChange[i] -= bakedNodeMean_[i]; }, 4096);
  std::vector<Rgb> leafChange(view.radiosity());
  parallelFor(0, leafChange.size(), [&](std::size_t i) { leafChange[i] -= bakedLeafRadiosity_[i]; }, 4096);
  const std::vector<Rgb> interpolatedChange = view.vertexValues(leafChange);

  // The lights' direct light, traced again where a changed light can reach, at the texels and
  // at the corner vertices.
  const std::vector<Light>& lights = view.lights();
  const double metresPerUnit = view.scene().metresPerUnit;
  const bool sameLights = lights.size() == lights_.size();
  const auto retrace = [&](const std::vector<VertexSite>& sites, std::vector<std::vector<Rgb>>& perLight, std::vector<std::uint8_t>& any) {
    any.assign(sites.size(), sameLights ? 0 : 1);
    if (!sameLights) perLight.assign(lights.size(), std::vector<Rgb>(sites.size()));
    std::size_t traced = 0;
    for (std::size_t l = 0; l < lights.size(); ++l) {
      if (sameLights && lights[l] == lights_[l]) continue;
      std::vector<Rgb>& direct = perLight[l];
      std::vector<std::uint8_t> retraced(sites.size(), 0);
      parallelFor(0, sites.size(), [&](std::size_t t) {
        const bool wasLit = direct[t].r != 0 || direct[t].g != 0 || direct[t].b != 0;
        if (!wasLit && sameLights && !mayLight(lights[l], sites[t])) return;
        direct[t] = irradiance(lights[l], sites[t].point, sites[t].normal, view.caster(), rayEpsilon_, metresPerUnit);
        retraced[t] = 1;
      }, 256);
      for (std::size_t t = 0; t < sites.size(); ++t) {
        traced += retraced[t];
        any[t] |= retraced[t];
      }
    }
    return traced;
  };
  std::vector<std::uint8_t> texelRetraced, cornerRetraced;
  const std::size_t traced = retrace(site_, direct_, texelRetraced);
  retrace(vertexSite_, vertexDirect_, cornerRetraced);
  lights_ = lights;

  // The nodes whose change matters, and the corner vertices and gather points they reach.
  const auto magnitude = [](const Rgb& e) { return std::fmax(std::fabs(e.r), std::fmax(std::fabs(e.g), std::fabs(e.b))); };
  const std::size_t numCorners = cornerVertex_.size(), points = nodeWeights_.start.size() - 1;
  std::vector<std::uint8_t> cornerTouched(numCorners, 0), pointTouched(points, 0);
  parallelFor(0, meanChange.size(), [&](std::size_t node) {
    if (!(magnitude(meanChange[node]) * nodeLargestWeight_[node] > changeFloor_)) return;
    for (std::uint32_t k = cornersOfNodeStart_[node]; k < cornersOfNodeStart_[node + 1]; ++k) cornerTouched[cornersOfNode_[k]] = 1;
    for (std::uint32_t k = pointsOfNodeStart_[node]; k < pointsOfNodeStart_[node + 1]; ++k) pointTouched[pointsOfNode_[k]] = 1;
  }, 1024);
  // And those whose direct light or close leaves changed.
  parallelFor(0, numCorners, [&](std::size_t i) {
    if (cornerTouched[i]) return;
    Rgb d;
    for (const std::vector<Rgb>& direct : vertexDirect_) d += direct[i];
    bool changed = magnitude(d - bakedVertexDirect_[i]) > changeFloor_;
    for (std::uint32_t k = vertexNearWeights_.start[i]; k < vertexNearWeights_.start[i + 1] && !changed; ++k)
      changed = magnitude(interpolatedChange[vertexNearWeights_.corner[k]]) * vertexNearWeights_.weight[k] > changeFloor_;
    if (changed) cornerTouched[i] = 1;
  }, 1024);

  // The corner vertices' change of radiosity, their close sources' corners first from the leaves'
  // change interpolated, then once more from this step's own values where it has them.
  std::vector<Rgb> farChange(numCorners), cornerChange(numCorners), next(numCorners);
  parallelFor(0, numCorners, [&](std::size_t i) {
    if (!cornerTouched[i]) return;
    Rgb e;
    for (std::uint32_t k = vertexNodeWeights_.start[i]; k < vertexNodeWeights_.start[i + 1]; ++k)
      e += meanChange[vertexNodeWeights_.node[k]] * vertexNodeWeights_.weight[k];
    for (const std::vector<Rgb>& direct : vertexDirect_) e += direct[i];
    farChange[i] = e - bakedVertexDirect_[i];
    Rgb near;
    for (std::uint32_t k = vertexNearWeights_.start[i]; k < vertexNearWeights_.start[i + 1]; ++k)
      near += interpolatedChange[vertexNearWeights_.corner[k]] * vertexNearWeights_.weight[k];
    cornerChange[i] = vertexAlbedo_[i] * (farChange[i] + near);
  }, 256);
  parallelFor(0, numCorners, [&](std::size_t i) {
    if (!cornerTouched[i]) return;
    Rgb near;
    for (std::uint32_t k = vertexNearWeights_.start[i]; k < vertexNearWeights_.start[i + 1]; ++k)
      near += (nearInSubset_[k] != kNoTexel ? cornerChange[nearInSubset_[k]] : interpolatedChange[vertexNearWeights_.corner[k]]) *
              vertexNearWeights_.weight[k];
    next[i] = vertexAlbedo_[i] * (farChange[i] + near);
  }, 256);
  cornerChange.swap(next);
  parallelFor(0, numCorners, [&](std::size_t i) {
    if (!(magnitude(cornerChange[i]) > changeFloor_)) return;
    for (std::uint32_t k = pointsOfCornerStart_[i]; k < pointsOfCornerStart_[i + 1]; ++k) pointTouched[pointsOfCorner_[k]] = 1;
  }, 1024);

  // The surfaces' change at the gather points it reaches: one sparse product.
  std::vector<Rgb> change(points);
  parallelFor(0, points, [&](std::size_t g) {
    if (!pointTouched[g]) return;
    Rgb e;
    for (std::uint32_t k = nodeWeights_.start[g]; k < nodeWeights_.start[g + 1]; ++k) e += meanChange[nodeWeights_.node[k]] * nodeWeights_.weight[k];
    for (std::uint32_t k = cornerWeights_.start[g]; k < cornerWeights_.start[g + 1]; ++k)
      e += cornerChange[cornerWeights_.corner[k]] * cornerWeights_.weight[k];
    change[g] = e;
  }, 256);
  std::size_t touched = 0;
  for (std::uint8_t t : pointTouched) touched += t;
  stats_.gatherPointsUpdated = touched;

  const std::uint64_t perAtlas = static_cast<std::uint64_t>(uvs_.size) * uvs_.size;
  // Only the texels this update changes, and those the last one changed (back to their bake).
  parallelFor(0, n, [&](std::size_t t) {
    bool changed = texelRetraced[t] != 0 || seamTexel_[t] != 0;  // a seam's texels are stitched from their own values every time
    for (std::uint32_t k = interpStart_[t]; k < interpStart_[t + 1] && !changed; ++k) changed = pointTouched[interpPoint_[k]] != 0;
    const bool wasChanged = texelChanged_[t] != 0;
    texelChanged_[t] = changed;
    if (!changed && !wasChanged) return;
    Rgb e = baked_[t] - bakedDirect_[t];
    for (std::uint32_t k = interpStart_[t]; k < interpStart_[t + 1]; ++k) e += change[interpPoint_[k]] * interpWeight_[k];
    for (const std::vector<Rgb>& direct : direct_) e += direct[t];
    lightmaps_[texel_[t] / perAtlas].pixels[texel_[t] % perAtlas] = nonNegative(e);
  }, 1024);
  fill_.apply(lightmaps_);
  ++stats_.updates;
  stats_.directTexelsTraced = traced;
  stats_.lastUpdateSeconds = timer.seconds();
  return Ok{};
}

}  // namespace lambert
