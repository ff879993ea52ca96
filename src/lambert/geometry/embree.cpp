// The only file in lambert that includes Embree.
#include <embree3/rtcore.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

#include "lambert/geometry/ray_caster.h"

namespace lambert {
namespace {

void reportEmbreeError(void*, RTCError code, const char* message) {
  std::fprintf(stderr, "embree error %d: %s\n", static_cast<int>(code), message ? message : "");
}

// Per-patch data the intersection filter reads.
struct PatchSides {
  std::vector<Vec3> normals;   // per patch: the front side
  std::vector<char> twinned;   // per patch: Patch::twinned
};

// A ray that meets the back of a twinned patch passes through it: the twin lying on it, facing
// the ray, is the hit (the two are coincident, so which one Embree finds first is arbitrary).
// Occlusion needs no filter: a two-sided face blocks from both sides either way.
void skipTwinnedBacks(const RTCFilterFunctionNArguments* args) {
  const auto* sides = static_cast<const PatchSides*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned patch = RTCHitN_primID(args->hit, args->N, i);
    if (!sides->twinned[patch]) continue;
    const Vec3 direction{RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                         RTCRayN_dir_z(args->ray, args->N, i)};
    if (dot(direction, sides->normals[patch]) >= 0) args->valid[i] = 0;
  }
}

RTCRay toRtcRay(const Ray& ray) {
  RTCRay r;
  r.org_x = static_cast<float>(ray.origin.x);
  r.org_y = static_cast<float>(ray.origin.y);
  r.org_z = static_cast<float>(ray.origin.z);
  r.dir_x = static_cast<float>(ray.direction.x);
  r.dir_y = static_cast<float>(ray.direction.y);
  r.dir_z = static_cast<float>(ray.direction.z);
  r.tnear = static_cast<float>(ray.tMin);
  r.tfar = static_cast<float>(ray.tMax);
  r.time = 0;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
  return r;
}

class EmbreeRayCaster final : public RayCaster {
 public:
  // Embree copies the geometry into its own buffers; the caster keeps only the normals it needs to
  // tell a hit's side, so it holds no reference to a mesh that could move away.
  explicit EmbreeRayCaster(const Mesh& mesh) {
    sides_.normals.reserve(mesh.numPatches());
    sides_.twinned.reserve(mesh.numPatches());
    bool anyTwinned = false;
    for (const Patch& patch : mesh.patches) {
      sides_.normals.push_back(patch.normal);
      sides_.twinned.push_back(patch.twinned);
      anyTwinned |= patch.twinned;
    }
    device_ = rtcNewDevice(nullptr);
    if (!device_) {
      std::fprintf(stderr, "embree: cannot create a device (error %d)\n", static_cast<int>(rtcGetDeviceError(nullptr)));
      std::abort();
    }
    rtcSetDeviceErrorFunction(device_, reportEmbreeError, nullptr);
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    // Rays from one patch to another graze shared edges; robust mode keeps those watertight.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);

    // Quads, with triangles encoded as (v0, v1, v2, v2) as Embree allows, so primID is the patch.
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_QUAD);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.numVertices()));
    for (std::size_t i = 0; i < mesh.numVertices(); ++i) {
      vertices[3 * i + 0] = static_cast<float>(mesh.positions[i].x);
      vertices[3 * i + 1] = static_cast<float>(mesh.positions[i].y);
      vertices[3 * i + 2] = static_cast<float>(mesh.positions[i].z);
    }
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), mesh.numPatches()));
    for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
      const Patch& patch = mesh.patches[i];
      for (std::uint32_t k = 0; k < 4; ++k) indices[4 * i + k] = patch.vertices[std::min(k, patch.numCorners - 1)];
    }
    if (anyTwinned) {
      rtcSetGeometryUserData(geometry, &sides_);
      rtcSetGeometryIntersectFilterFunction(geometry, skipTwinnedBacks);
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
  }

  ~EmbreeRayCaster() override {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }

  bool occluded(const Ray& ray) const override {
    countRays(1);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r = toRtcRay(ray);
    rtcOccluded1(scene_, &context, &r);
    return r.tfar < 0;  // Embree marks an occluded ray by setting tfar to -inf
  }

  void occluded(std::span<const Ray> rays, std::span<bool> out) const override {
    countRays(rays.size());
    RTCIntersectContext context = incoherentContext();
    RTCRay chunk[kChunk];
    inChunks(rays.size(), [&](std::size_t begin, std::size_t n) {
      for (std::size_t i = 0; i < n; ++i) chunk[i] = toRtcRay(rays[begin + i]);
      rtcOccluded1M(scene_, &context, chunk, static_cast<unsigned>(n), sizeof(RTCRay));
      for (std::size_t i = 0; i < n; ++i) out[begin + i] = chunk[i].tfar < 0;
    });
  }

  std::optional<RayHit> intersect(const Ray& ray) const override {
    countRays(1);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rayHit = toRtcRayHit(ray);
    rtcIntersect1(scene_, &context, &rayHit);
    return hitOf(rayHit, ray);
  }

  void intersect(std::span<const Ray> rays, std::span<std::optional<RayHit>> out) const override {
    countRays(rays.size());
    RTCIntersectContext context = incoherentContext();
    RTCRayHit chunk[kChunk];
    inChunks(rays.size(), [&](std::size_t begin, std::size_t n) {
      for (std::size_t i = 0; i < n; ++i) chunk[i] = toRtcRayHit(rays[begin + i]);
      rtcIntersect1M(scene_, &context, chunk, static_cast<unsigned>(n), sizeof(RTCRayHit));
      for (std::size_t i = 0; i < n; ++i) out[begin + i] = hitOf(chunk[i], rays[begin + i]);
    });
  }

 private:
  // Batches go to Embree's stream calls in chunks of this many rays, marked incoherent.
  static constexpr std::size_t kChunk = 64;
  template <typename Body>
  static void inChunks(std::size_t count, Body&& body) {
    for (std::size_t begin = 0; begin < count; begin += kChunk) body(begin, std::min(kChunk, count - begin));
  }
  static RTCIntersectContext incoherentContext() {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    return context;
  }
  static RTCRayHit toRtcRayHit(const Ray& ray) {
    RTCRayHit rayHit;
    rayHit.ray = toRtcRay(ray);
    rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rayHit;
  }
  std::optional<RayHit> hitOf(const RTCRayHit& rayHit, const Ray& ray) const {
    if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    const std::uint32_t patch = rayHit.hit.primID;
    return RayHit{rayHit.ray.tfar, patch, dot(ray.direction, sides_.normals[patch]) < 0};
  }

  PatchSides sides_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace

std::unique_ptr<RayCaster> makeEmbreeRayCaster(const Mesh& mesh) { return std::make_unique<EmbreeRayCaster>(mesh); }

}  // namespace lambert
