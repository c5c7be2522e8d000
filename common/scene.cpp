#include "common/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/error.h"
#include "common/parallel.h"

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

const float* srgbToLinearTable() {
  static const auto table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = static_cast<double>(i) / 255.0;  // IEC 61966-2-1
      t[static_cast<size_t>(i)] = static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table.data();
}

glm::vec3 ColorTexture::linearAt(float s, float t) const {
  const int x = cutoutTexel(s, width, wrapS), y = cutoutTexel(t, height, wrapT);
  const uint8_t* texel = &rgba[4 * (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x))];
  const float* linear = srgbToLinearTable();
  return {linear[texel[0]], linear[texel[1]], linear[texel[2]]};
}

glm::vec3 Mesh::albedoAt(const std::vector<ColorTexture>& textures, glm::vec2 st) const {
  if (texture < 0) return baseColor;
  return baseColor * textures[static_cast<size_t>(texture)].linearAt(st.x, st.y);
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
    if (mesh.texture >= 0) {
      require(static_cast<size_t>(mesh.texture) < scene.textures.size(),
              what + " uses texture " + std::to_string(mesh.texture) + " of " + std::to_string(scene.textures.size()));
      const ColorTexture& t = scene.textures[static_cast<size_t>(mesh.texture)];
      require(t.width > 0 && t.height > 0 &&
                  t.rgba.size() == 4 * static_cast<size_t>(t.width) * static_cast<size_t>(t.height),
              what + ": its texture has " + std::to_string(t.rgba.size()) + " bytes for " + std::to_string(t.width) +
                  "x" + std::to_string(t.height) + " RGBA texels");
    }
    if (mesh.cutout >= 0 || mesh.texture >= 0) {
      require(mesh.texcoords.size() == vertexCount, what + " has " + std::to_string(mesh.texcoords.size()) +
                                                        " texture coordinates for " + std::to_string(vertexCount) +
                                                        " positions");
      for (size_t v = 0; v < vertexCount; ++v)
        require(std::isfinite(mesh.texcoords[v].x) && std::isfinite(mesh.texcoords[v].y),
                what + " vertex " + std::to_string(v) + " has a non-finite texture coordinate");
    }
    if (mesh.cutout >= 0) {
      require(static_cast<size_t>(mesh.cutout) < scene.cutouts.size(),
              what + " uses cutout " + std::to_string(mesh.cutout) + " of " + std::to_string(scene.cutouts.size()));
      const Cutout& c = scene.cutouts[static_cast<size_t>(mesh.cutout)];
      require(c.width > 0 && c.height > 0 &&
                  c.opaque.size() == static_cast<size_t>(c.width) * static_cast<size_t>(c.height),
              what + ": its cutout has " + std::to_string(c.opaque.size()) + " texels for " +
                  std::to_string(c.width) + "x" + std::to_string(c.height));
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

namespace {

// Whether the ray o + t·d (t > 0) meets triangle abc (Möller–Trumbore), and where.
bool rayMeetsTriangle(const glm::vec3& o, const glm::vec3& d, const glm::vec3& a, const glm::vec3& b,
                      const glm::vec3& c, float& t) {
  const glm::vec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
  const float det = glm::dot(e1, p);
  if (std::fabs(det) < 1e-20f) return false;
  const float inv = 1.0f / det;
  const glm::vec3 s = o - a;
  const float u = glm::dot(s, p) * inv;
  if (u < 0.0f || u > 1.0f) return false;
  const glm::vec3 q = glm::cross(s, e1);
  const float v = glm::dot(d, q) * inv;
  if (v < 0.0f || u + v > 1.0f) return false;
  t = glm::dot(e2, q) * inv;
  return t > 0.0f && std::isfinite(t);
}

// A triangle by its corners, and the way it faces: its vertex normals' sum where the mesh has
// normals (what shading calls the front; winding can be flipped by mirrored nodes), else the
// winding's normal.
struct Triangle {
  glm::vec3 a, b, c, n;
};

// Every triangle, or only the `largest` of them by area (walls and floors, not the furniture);
// BLEND meshes' only with `withBlend`.
std::vector<Triangle> triangles(const Scene& scene, size_t largest = SIZE_MAX, bool withBlend = false) {
  std::vector<std::pair<float, Triangle>> all;
  for (const Mesh& mesh : scene.meshes)
    for (size_t t = 0; t + 2 < mesh.indices.size() && (withBlend || !mesh.blend); t += 3) {
      const uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
      Triangle tri{mesh.positions[i0], mesh.positions[i1], mesh.positions[i2], glm::vec3(0.0f)};
      tri.n = mesh.normals.size() == mesh.positions.size() ? mesh.normals[i0] + mesh.normals[i1] + mesh.normals[i2]
                                                           : glm::cross(tri.b - tri.a, tri.c - tri.a);
      all.push_back({glm::length(glm::cross(tri.b - tri.a, tri.c - tri.a)), tri});
    }
  if (all.size() > largest) {
    std::nth_element(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(largest), all.end(),
                     [](const auto& x, const auto& y) { return x.first > y.first; });
    all.resize(largest);
  }
  std::vector<Triangle> out;
  out.reserve(all.size());
  for (const auto& [area, tri] : all) out.push_back(tri);
  return out;
}

// The nearest hit along each of `directions` from `origin` (infinity: none), and with `facing`
// whether any surface the ray meets faces the origin (its front towards it): a room's walls do,
// wherever the origin is among its furniture; a closed object's one-sided shell, seen from
// inside, shows only its back. Brute force over the triangles: a few hundred rays, once per run,
// where the oracle's BVH is not at hand.
std::vector<float> castFrom(const std::vector<Triangle>& tris, const glm::vec3& origin,
                            const std::vector<glm::vec3>& directions, std::vector<uint8_t>* facing = nullptr) {
  std::vector<float> nearest(directions.size(), std::numeric_limits<float>::infinity());
  if (facing) facing->assign(directions.size(), 0);
  parallelFor(size_t{0}, directions.size(), [&](size_t i) {  // one ray each: the same answer for any thread count
    for (const Triangle& tri : tris) {
      float hit = 0.0f;
      if (!rayMeetsTriangle(origin, directions[i], tri.a, tri.b, tri.c, hit)) continue;
      nearest[i] = std::min(nearest[i], hit);
      if (facing && glm::dot(tri.n, directions[i]) < 0.0f) (*facing)[i] = 1;
    }
  });
  return nearest;
}

}  // namespace

namespace {

// The eye on the ray centre + back·t at which every vertex is inside the frame: the camera
// looks at `centre` along −back, Y up, with the fields of view a 5% margin leaves.
glm::vec3 fittedEye(const Scene& scene, const glm::vec3& centre, const glm::vec3& back, const Camera& camera,
                    float aspect) {
  constexpr float kMargin = 1.05f;
  const glm::vec3 right = glm::normalize(glm::cross(camera.up, back)), up = glm::cross(back, right);
  const float tanV = std::tan(0.5f * camera.yfov) / kMargin;
  const float tanH = tanV * (std::isfinite(aspect) && aspect > 0.0f ? aspect : 16.0f / 9.0f);
  float distance = 0.0f;
  const bool anyOpaque = std::any_of(scene.meshes.begin(), scene.meshes.end(), [](const Mesh& m) { return !m.blend; });
  for (const Mesh& mesh : scene.meshes)
    for (size_t v = 0; v < mesh.positions.size() && !(anyOpaque && mesh.blend); ++v) {
      const glm::vec3& p = mesh.positions[v];
      const glm::vec3 d = p - centre;
      const float x = glm::dot(d, right), y = glm::dot(d, up), z = glm::dot(d, back);
      distance = std::max({distance, z + std::fabs(x) / tanH, z + std::fabs(y) / tanV});
    }
  const float sphere = glm::length(camera.eye - camera.target);  // frameBounds' distance
  return centre + back * (std::isfinite(distance) && distance > 1e-3f * sphere && distance < sphere ? distance : sphere);
}

// The 26 directions to the neighbours of a cell in a 3×3×3 block, unit length.
std::vector<glm::vec3> neighbourDirections() {
  std::vector<glm::vec3> out;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        if (x || y || z) out.push_back(glm::normalize(glm::vec3(x, y, z)));
  return out;
}

}  // namespace

namespace {

// The bounds the default framing frames: the opaque and MASK surfaces' (BLEND ones, a light
// cone reaching out of a window, do not count), or every surface's where all are BLEND.
Bounds framedBounds(const Scene& scene) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  glm::vec3 lo{kInf}, hi{-kInf};
  bool any = false;
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.blend) continue;
    for (const glm::vec3& p : mesh.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
      any = true;
    }
  }
  return any ? Bounds{lo, hi} : scene.bounds();
}

// Two unit vectors perpendicular to the axis direction d and to each other.
std::pair<glm::vec3, glm::vec3> across(const glm::vec3& d) {
  const glm::vec3 u = std::fabs(d.y) < 0.5f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  const glm::vec3 a = glm::normalize(glm::cross(d, u));
  return {a, glm::cross(d, a)};
}

}  // namespace

Framing frameScene(const Scene& scene, float yfovRadians, float aspect) {
  constexpr int kEnclosedAt = 24;  // of 26 directions
  constexpr int kOpenAt = 20;      // of the 25 rays of a side's fan that escape: the side is open
  Framing out;
  const Bounds b = framedBounds(scene);
  out.camera = frameBounds(b, yfovRadians);
  const glm::vec3 centre = out.camera.target;
  const std::vector<glm::vec3> directions = neighbourDirections();
  std::vector<glm::vec3> level;  // the 8 directions with y = 0
  for (const glm::vec3& d : directions)
    if (d.y == 0.0f) level.push_back(d);
  // 1. is the centre enclosed, by surfaces that face it? Inside a room the walls, floor and
  // ceiling turn their fronts to the centre (along a quarter of the directions at least: the
  // apartment's 15 of 26, the arcade's 26); inside a closed object (a helmet: 2 of 26) the centre
  // sees only the backs of its shell, and the object is framed from outside. A BLEND surface
  // (a window's glass) closes a direction but is never a wall that faces the centre.
  const std::vector<Triangle> opaque = triangles(scene);
  const std::vector<Triangle> all = triangles(scene, SIZE_MAX, true);
  std::vector<uint8_t> facing;  // an opaque surface along the ray faces the centre
  const std::vector<float> closed = castFrom(all, centre, directions);
  const std::vector<float> hits = castFrom(opaque, centre, directions, &facing);
  for (size_t i = 0; i < hits.size(); ++i) {
    out.enclosedDirections += std::isfinite(closed[i]);
    out.facingDirections += std::isfinite(hits[i]) && facing[i];
  }
  if (out.enclosedDirections < kEnclosedAt || 4 * out.facingDirections < out.enclosedDirections) {
    // 2. an object: from the front-above diagonal, fitted to the frame
    out.camera.eye = fittedEye(scene, centre, glm::normalize(out.camera.eye - centre), out.camera, aspect);
    return out;
  }
  // 3. an enclosure open on one level side (a Cornell box): look in through the opening, from
  // outside. Open means most of a fan of rays through that side escapes, not the one ray
  // through a window or a door (a study's window, a hotel room's door: those are rooms).
  for (size_t i = 0; i < level.size(); ++i) {
    if (level[i].x * level[i].z != 0.0f) continue;
    const auto [u, v] = across(level[i]);
    std::vector<glm::vec3> fan;
    for (int p = -2; p <= 2; ++p)
      for (int q = -2; q <= 2; ++q)
        fan.push_back(glm::normalize(level[i] + 0.3f * static_cast<float>(p) * u + 0.3f * static_cast<float>(q) * v));
    const std::vector<float> through = castFrom(all, centre, fan);
    if (std::count_if(through.begin(), through.end(), [](float h) { return !std::isfinite(h); }) >= kOpenAt) {
      const glm::vec3 back = glm::normalize(level[i] + glm::vec3(0.0f, 0.25f, 0.0f));
      out.camera.eye = fittedEye(scene, centre, back, out.camera, aspect);
      out.openSide = true;
      return out;
    }
  }
  out.interior = true;
  // 4. a closed interior: from the candidate eye with the most clearance among the large opaque
  // surfaces (a 6×6 grid over the bounds at about 0.4 of their height), along the level
  // direction with the farthest opaque surface whose view no BLEND surface covers (the glass of
  // a window, a light cone: drawn solid, they would hide the room), from near the surface
  // behind: the most of the room in view
  const std::vector<Triangle> large = triangles(scene, 4096), largeAll = triangles(scene, 4096, true);
  float clearance = -1.0f;
  glm::vec3 eye = centre;
  std::vector<float> view;
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 6; ++k) {
      // (odd fractions: an eye exactly in the plane of a wall or floor of a tidy or quantized
      // file would see it edge-on, where ray casting and rasterisation disagree)
      const glm::vec3 candidate(b.lo.x + (b.hi.x - b.lo.x) * (static_cast<float>(i) + 0.4871f) / 6.0f,
                                b.lo.y + 0.4129f * (b.hi.y - b.lo.y),
                                b.lo.z + (b.hi.z - b.lo.z) * (static_cast<float>(k) + 0.5133f) / 6.0f);
      const std::vector<float> reach = castFrom(largeAll, candidate, directions);
      if (std::count_if(reach.begin(), reach.end(), [](float h) { return std::isfinite(h); }) < kEnclosedAt)
        continue;  // outside, or in the open
      const std::vector<float> room = castFrom(large, candidate, level);
      const float nearest = *std::min_element(room.begin(), room.end());
      if (std::isfinite(nearest) && nearest > clearance) {
        clearance = nearest;
        eye = candidate;
        view = room;
      }
    }
  if (view.empty()) view = castFrom(large, eye, level);
  // a direction whose nearest surface, BLEND ones included, is nearer than its opaque one looks
  // at glass: taken only where every direction does
  const std::vector<float> first = castFrom(all, eye, level);
  auto clear = [&](size_t i) { return !(first[i] < view[i]); };
  size_t best = level.size();
  for (size_t i = 0; i < level.size(); ++i) {
    if (!std::isfinite(view[i])) continue;
    if (best == level.size() || (clear(i) && !clear(best)) || (clear(i) == clear(best) && view[i] > view[best])) best = i;
  }
  if (best == level.size()) best = 0;
  const glm::vec3 d = level[best];
  float behind = view[static_cast<size_t>(std::find(level.begin(), level.end(), -d) - level.begin())];
  if (!std::isfinite(behind)) behind = 0.0f;
  glm::vec3 placed = eye - d * (0.9f * behind);
  // 5. inside means inside: the eye is kept within the bounds (1% in from each face)
  const glm::vec3 margin = 0.01f * (b.hi - b.lo);
  placed = glm::clamp(placed, b.lo + margin, b.hi - margin);
  out.camera.eye = placed;
  out.camera.target = placed + d;
  return out;
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
