#include "common/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/error.h"

namespace mrr {

namespace {

bool isFinite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Rotation by 180° about X: (x, y, z) -> (x, -y, -z). Determinant +1, so no mirroring.
glm::vec3 rotateX180(const glm::vec3& v) { return {v.x, -v.y, -v.z}; }

std::string describe(const glm::vec3& v) {
  std::ostringstream out;
  out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return out.str();
}

}  // namespace

namespace {
// i mod n for n > 0, in [0, n), written as cutout.glsl must (GLSL's % is undefined for negatives).
int positiveModulo(int i, int n) {
  const int r = (i < 0 ? -i : i) % n;
  return i < 0 && r != 0 ? n - r : r;
}
}  // namespace

int cutoutTexel(float t, int n, Wrap wrap) {
  // 1. the texel holding t·n, as a whole number kept well inside int's range (NaN: texel 0)
  const float f = std::floor(t * static_cast<float>(n));
  const int i = f == f ? static_cast<int>(std::clamp(f, -16777216.0f, 16777216.0f)) : 0;
  // 2. wrapped into [0, n)
  switch (wrap) {
    case Wrap::Clamp: return std::clamp(i, 0, n - 1);
    case Wrap::Mirror: {
      const int k = positiveModulo(i, 2 * n);  // period 2n: forward, then backward
      return k < n ? k : 2 * n - 1 - k;
    }
    case Wrap::Repeat:
    default: return positiveModulo(i, n);
  }
}

bool Cutout::opaqueAt(float s, float t) const {
  const int x = cutoutTexel(s, width, wrapS), y = cutoutTexel(t, height, wrapT);
  return opaque[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] != 0;
}

Bounds Scene::bounds() const {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  glm::vec3 lo{kInf}, hi{-kInf};
  bool any = false;
  for (const Mesh& mesh : meshes) {
    for (const glm::vec3& p : mesh.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
      any = true;
    }
  }
  // An empty scene gets a zero-size box at the origin rather than an inverted infinite one.
  if (!any) return Bounds{};
  return Bounds{lo, hi};
}

size_t Scene::triangleCount() const {
  size_t count = 0;
  for (const Mesh& mesh : meshes) count += mesh.indices.size() / 3;
  return count;
}

void computeVertexNormals(Mesh& mesh) {
  const size_t vertexCount = mesh.positions.size();
  // Accumulate in double: large scenes in millimetres give big cross products, and the sum
  // over a fan of thin triangles should not lose the small ones.
  std::vector<glm::dvec3> sums(vertexCount, glm::dvec3(0.0));
  const size_t triangleCount = mesh.indices.size() / 3;
  for (size_t t = 0; t < triangleCount; ++t) {
    const uint32_t i0 = mesh.indices[3 * t], i1 = mesh.indices[3 * t + 1],
                   i2 = mesh.indices[3 * t + 2];
    if (i0 >= vertexCount || i1 >= vertexCount || i2 >= vertexCount) continue;  // validateScene reports these
    const glm::dvec3 a(mesh.positions[i0]), b(mesh.positions[i1]), c(mesh.positions[i2]);
    // The unnormalised cross product has length 2·area: this is the area weighting.
    const glm::dvec3 n = glm::cross(b - a, c - a);
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) continue;
    sums[i0] += n;
    sums[i1] += n;
    sums[i2] += n;
  }
  mesh.normals.resize(vertexCount);
  for (size_t v = 0; v < vertexCount; ++v) {
    const double length = glm::length(sums[v]);
    if (length > 0.0 && std::isfinite(length)) {
      mesh.normals[v] = glm::vec3(sums[v] / length);
    } else {
      // Unused vertex, or only degenerate/cancelling triangles: any unit vector will do.
      mesh.normals[v] = glm::vec3(0.0f, 1.0f, 0.0f);
    }
  }
}

void validateScene(const Scene& scene, const std::string& source) {
  require(!scene.meshes.empty(), source + ": no meshes to render");
  require(scene.triangleCount() > 0, source + ": no triangles to render (" +
                                         std::to_string(scene.meshes.size()) + " empty meshes)");
  size_t goodTriangles = 0;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const std::string what = source + ": mesh '" + mesh.name + "'";
    const size_t vertexCount = mesh.positions.size();
    require(mesh.indices.size() % 3 == 0,
            what + " has " + std::to_string(mesh.indices.size()) +
                " indices, not a multiple of 3");
    require(mesh.normals.size() == vertexCount,
            what + " has " + std::to_string(mesh.normals.size()) + " normals for " +
                std::to_string(vertexCount) + " positions");
    for (size_t v = 0; v < vertexCount; ++v) {
      require(isFinite(mesh.positions[v]), what + " vertex " + std::to_string(v) +
                                               " has a non-finite position " +
                                               describe(mesh.positions[v]));
      require(isFinite(mesh.normals[v]), what + " vertex " + std::to_string(v) +
                                             " has a non-finite normal " +
                                             describe(mesh.normals[v]));
    }
    require(isFinite(mesh.baseColor), what + " has a non-finite base colour");
    if (mesh.cutout >= 0) {
      require(static_cast<size_t>(mesh.cutout) < scene.cutouts.size(),
              what + " uses cutout " + std::to_string(mesh.cutout) + " of " + std::to_string(scene.cutouts.size()));
      const Cutout& c = scene.cutouts[static_cast<size_t>(mesh.cutout)];
      require(c.width > 0 && c.height > 0 &&
                  c.opaque.size() == static_cast<size_t>(c.width) * static_cast<size_t>(c.height),
              what + ": its cutout has " + std::to_string(c.opaque.size()) + " texels for " +
                  std::to_string(c.width) + "x" + std::to_string(c.height));
      require(mesh.texcoords.size() == vertexCount, what + " has " + std::to_string(mesh.texcoords.size()) +
                                                        " texture coordinates for " + std::to_string(vertexCount) +
                                                        " positions");
      for (size_t v = 0; v < vertexCount; ++v)
        require(std::isfinite(mesh.texcoords[v].x) && std::isfinite(mesh.texcoords[v].y),
                what + " vertex " + std::to_string(v) + " has a non-finite texture coordinate");
    }
    for (size_t i = 0; i < mesh.indices.size(); ++i) {
      require(mesh.indices[i] < vertexCount,
              what + " index " + std::to_string(mesh.indices[i]) + " (at " + std::to_string(i) +
                  ") is out of range: the mesh has " + std::to_string(vertexCount) +
                  " vertices");
    }
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const glm::vec3& a = mesh.positions[mesh.indices[t]];
      const glm::vec3& b = mesh.positions[mesh.indices[t + 1]];
      const glm::vec3& c = mesh.positions[mesh.indices[t + 2]];
      const float area2 = glm::length(glm::cross(b - a, c - a));
      if (area2 > 0.0f && std::isfinite(area2)) ++goodTriangles;
    }
  }
  require(goodTriangles > 0, source + ": all " + std::to_string(scene.triangleCount()) +
                                 " triangles are degenerate (zero area)");
}

Camera frameBounds(const Bounds& bounds, float yfovRadians) {
  constexpr float kMargin = 1.15f;  // keep the silhouette off the image border
  Camera camera;
  // A nonsensical field of view keeps the Camera default rather than producing NaNs.
  if (std::isfinite(yfovRadians) && yfovRadians > 0.01f && yfovRadians < 3.1f)
    camera.yfov = yfovRadians;
  glm::vec3 centre = bounds.center();
  if (!isFinite(centre)) centre = glm::vec3(0.0f);
  float radius = 0.5f * bounds.diagonal();
  // A point-sized (or broken) box still needs the eye away from the target, far enough that
  // the difference survives float rounding at the centre's magnitude.
  const float extent = std::max({std::fabs(centre.x), std::fabs(centre.y), std::fabs(centre.z), 1.0f});
  const float minRadius = 1e-3f * extent;
  if (!(radius >= minRadius) || !std::isfinite(radius)) radius = minRadius;
  // The bounding sphere fits a cone of half-angle θ at distance r / sin θ; the vertical field
  // is the narrow one for landscape images.
  const float distance = kMargin * radius / std::sin(0.5f * camera.yfov);
  const glm::vec3 direction = glm::normalize(glm::vec3(0.35f, 0.45f, 1.0f));
  camera.target = centre;
  camera.eye = centre + direction * distance;
  camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  return camera;
}

void flipUp(Scene& scene) {
  for (Mesh& mesh : scene.meshes) {
    for (glm::vec3& p : mesh.positions) p = rotateX180(p);
    for (glm::vec3& n : mesh.normals) n = rotateX180(n);
  }
  // The default light is already meant for a Y-up world, which is what flipping produces.
  if (scene.hasLight) scene.light.direction = rotateX180(scene.light.direction);
  for (Camera& camera : scene.cameras) {
    camera.eye = rotateX180(camera.eye);
    camera.target = rotateX180(camera.target);
    camera.up = rotateX180(camera.up);
  }
}

}  // namespace mrr
