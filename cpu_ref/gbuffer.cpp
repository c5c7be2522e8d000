#include "cpu_ref/gbuffer.h"


#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

#include "common/error.h"
#include "common/parallel.h"
#include "cpu_ref/rays.h"

namespace mrr {

// What a cutout mesh's filter function needs.
struct CutoutHits {
  const Scene* scene;
  const Mesh* mesh;
};

namespace {
void embreeError(void*, RTCError code, const char* str) {
  // Embree reports through this callback; we surface it on the next check.
  (void)code;
  (void)str;
}

// Embree's filter for a mesh with a cutout: a candidate hit on a transparent texel is refused,
// and the ray goes on to the next surface, as `discard` does in gbuffer.frag.
void refuseTransparentHits(const RTCFilterFunctionNArguments* args) {
  const auto* hits = static_cast<const CutoutHits*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    if (!opaqueHit(*hits->scene, *hits->mesh, RTCHitN_primID(args->hit, args->N, i), u, v)) args->valid[i] = 0;
  }
}
}  // namespace

glm::vec2 texcoordAt(const Mesh& mesh, unsigned primitive, float u, float v) {
  const size_t tri = 3 * static_cast<size_t>(primitive);
  const float w = 1.0f - u - v;
  return w * mesh.texcoords[mesh.indices[tri]] + u * mesh.texcoords[mesh.indices[tri + 1]] +
         v * mesh.texcoords[mesh.indices[tri + 2]];
}

bool opaqueHit(const Scene& scene, const Mesh& mesh, unsigned primitive, float u, float v) {
  if (mesh.cutout < 0) return true;
  const glm::vec2 t = texcoordAt(mesh, primitive, u, v);
  return scene.cutouts[static_cast<size_t>(mesh.cutout)].opaqueAt(t.x, t.y);
}

RayScene::RayScene(const Scene& scene) : scene_(scene) {
  device_ = rtcNewDevice(nullptr);
  require(device_ != nullptr, "embree: cannot create a device (error " +
                                  std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(device_, embreeError, nullptr);
  rtcScene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(rtcScene_, RTC_BUILD_QUALITY_MEDIUM);
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), mesh.positions.size()));
    std::memcpy(vb, mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
    auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(uint32_t), mesh.indices.size() / 3));
    std::memcpy(ib, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
    if (mesh.cutout >= 0) {
      cutoutHits_.push_back(std::make_unique<CutoutHits>(CutoutHits{&scene, &mesh}));
      rtcSetGeometryUserData(geom, cutoutHits_.back().get());
      rtcSetGeometryIntersectFilterFunction(geom, refuseTransparentHits);
      rtcSetGeometryOccludedFilterFunction(geom, refuseTransparentHits);
    }
    rtcCommitGeometry(geom);
    // geomID == mesh index: the G-buffer looks the mesh up by it.
    rtcAttachGeometryByID(rtcScene_, geom, static_cast<unsigned>(m));
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(rtcScene_);
  require(rtcGetDeviceError(device_) == RTC_ERROR_NONE, "embree: scene build failed");
}

RayScene::~RayScene() {
  if (rtcScene_) rtcReleaseScene(rtcScene_);
  if (device_) rtcReleaseDevice(device_);
}

GBuffer renderGBuffer(const RayScene& rays, const View& view, const LevelConstants& level) {
  GBuffer g = GBuffer::uninitialised(level.width, level.height);  // castGrid visits every pixel
  const Scene& scene = rays.scene();
  const float s = static_cast<float>(level.scale);
  castGrid(
      rays.handle(), g.width, g.height,
      [&](int x, int y, glm::vec3& origin, glm::vec3& direction) {
        // SPEC §0: level pixel (x, y) samples the full-res point ((x+½)s, (y+½)s).
        origin = view.eye;
        direction = view.worldRay((static_cast<float>(x) + 0.5f) * s, (static_cast<float>(y) + 0.5f) * s);
      },
      [&](int x, int y, const RayHit& hit) {
        // 0. alpha cutouts (docs/spec.md §1.1): refuseTransparentHits already passed the ray
        //    through transparent texels; 2. (gbuffer.frag's depth order) is the nearest hit here
        if (hit.geomID == RTC_INVALID_GEOMETRY_ID) {  // background: all zero
          g.hit.at(x, y) = 0;
          g.depth.at(x, y) = 0.0f;
          for (int c = 0; c < 3; ++c) g.position.at(x, y, c) = g.normal.at(x, y, c) = g.albedo.at(x, y, c) = 0.0f;
          return;
        }
        const Mesh& mesh = scene.meshes[hit.geomID];
        const size_t tri = 3 * static_cast<size_t>(hit.primID);
        const uint32_t i0 = mesh.indices[tri], i1 = mesh.indices[tri + 1], i2 = mesh.indices[tri + 2];
        const float w = 1.0f - hit.u - hit.v;
        // 1. position and shading normal by barycentric interpolation, as a rasteriser would;
        //    the normal normalised and flipped to face the camera
        const glm::vec3 pw = w * mesh.positions[i0] + hit.u * mesh.positions[i1] + hit.v * mesh.positions[i2];
        const glm::vec3 nw = w * mesh.normals[i0] + hit.u * mesh.normals[i1] + hit.v * mesh.normals[i2];
        const glm::vec3 p = view.toView(pw);
        glm::vec3 n = view.directionToView(nw);
        const float len = glm::length(n);
        n = len > 0.0f ? n / len : -glm::normalize(p);
        if (glm::dot(n, p) > 0.0f) n = -n;  // SPEC §1: flip to face the camera
        // 2. albedo: the factor, times the base-colour texture's texel at the hit's texture
        //    coordinate where the mesh has one (docs/spec.md §1.2)
        const glm::vec3 albedo =
            mesh.texture < 0 ? mesh.baseColor : mesh.albedoAt(scene.textures, texcoordAt(mesh, hit.primID, hit.u, hit.v));
        g.hit.at(x, y) = 1;
        g.depth.at(x, y) = -p.z;
        for (int c = 0; c < 3; ++c) {
          g.position.at(x, y, c) = p[c];
          g.normal.at(x, y, c) = n[c];
          g.albedo.at(x, y, c) = albedo[c];
        }
      });
  return g;
}

GBuffer subsampleGBuffer(const GBuffer& full, const LevelConstants& level) {
  GBuffer g = GBuffer::uninitialised(level.width, level.height);  // every pixel written below
  const int s = level.scale;
  parallelFor(0, g.height, [&](int y) {
    // 1. the full-res pixel this level pixel samples (SPEC §0), clamped to the grid
    const int fy = std::min(levelSamplePixel(y, s), full.height - 1);
    for (int x = 0; x < g.width; ++x) {
      const int fx = std::min(levelSamplePixel(x, s), full.width - 1);
      // 2. its every channel, copied
      g.hit.at(x, y) = full.hit.at(fx, fy);
      g.depth.at(x, y) = full.depth.at(fx, fy);
      for (int c = 0; c < 3; ++c) {
        g.position.at(x, y, c) = full.position.at(fx, fy, c);
        g.normal.at(x, y, c) = full.normal.at(fx, fy, c);
        g.albedo.at(x, y, c) = full.albedo.at(fx, fy, c);
      }
    }
  });
  return g;
}

}  // namespace mrr
