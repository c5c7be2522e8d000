#include "scenes/default_light.h"

#include "common/parallel.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mrr {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Rasterises the triangle (x, y: pixel coordinates; w: a value interpolated linearly in them)
// over the pixel centres of a width × height grid, calling visit(x, y, w) for each covered one.
template <class Visit>
void rasterise(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, int width, int height, Visit visit) {
  const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (!(std::fabs(area) > 0.0f) || !std::isfinite(area)) return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}) - 0.5f)));
  const int x1 = std::min(width - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}) - 0.5f)));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}) - 0.5f)));
  const int y1 = std::min(height - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}) - 0.5f)));
  const float inv = 1.0f / area;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const float px = static_cast<float>(x) + 0.5f, py = static_cast<float>(y) + 0.5f;
      const float wa = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) * inv;
      const float wb = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) * inv;
      const float wc = 1.0f - wa - wb;
      if (wa < 0.0f || wb < 0.0f || wc < 0.0f) continue;
      visit(x, y, wa * a.z + wb * b.z + wc * c.z);
    }
}

struct Tri {
  glm::vec3 a, b, c;
};

// `skipBlend`: leave out alphaMode BLEND meshes (glass, light cones), as the default framing does.
std::vector<Tri> allTriangles(const Scene& scene, bool skipBlend = false) {
  std::vector<Tri> out;
  for (const Mesh& mesh : scene.meshes)
    if (!(skipBlend && mesh.blend))
      for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
      out.push_back({mesh.positions[mesh.indices[t]], mesh.positions[mesh.indices[t + 1]],
                     mesh.positions[mesh.indices[t + 2]]});
  return out;
}

// What the view sees at each pixel of a small G-buffer: the world position and the face normal
// turned to the camera.
struct Sample {
  glm::vec3 position, normal;
};

std::vector<Sample> viewSamples(const std::vector<Tri>& tris, const Camera& camera, int width, int height,
                                float sceneSize) {
  const View view = makeView(camera, width, height, width, height);
  const float nearZ = std::max(1e-5f * sceneSize, 1e-6f);
  std::vector<float> nearest(static_cast<size_t>(width) * static_cast<size_t>(height), 0.0f);  // 1/z, 0: nothing
  std::vector<int> id(nearest.size(), -1);
  for (size_t t = 0; t < tris.size(); ++t) {
    // 1. view space, clipped against the near plane z = −near (a polygon of up to 4 corners)
    const glm::vec3 in[3] = {view.toView(tris[t].a), view.toView(tris[t].b), view.toView(tris[t].c)};
    glm::vec3 poly[4];
    int n = 0;
    for (int i = 0; i < 3; ++i) {
      const glm::vec3 &p = in[i], &q = in[(i + 1) % 3];
      const bool pIn = p.z <= -nearZ, qIn = q.z <= -nearZ;
      if (pIn) poly[n++] = p;
      if (pIn != qIn) poly[n++] = p + (q - p) * ((-nearZ - p.z) / (q.z - p.z));
    }
    if (n < 3) continue;
    // 2. to pixels, with 1/z to interpolate (linear in screen space)
    glm::vec3 s[4];
    for (int i = 0; i < n; ++i) {
      const glm::vec2 px = view.project(poly[i]);
      s[i] = glm::vec3(px, 1.0f / -poly[i].z);
    }
    for (int k = 1; k + 1 < n; ++k)
      rasterise(s[0], s[k], s[k + 1], width, height, [&](int x, int y, float w) {
        const size_t i = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
        if (w > nearest[i]) {
          nearest[i] = w;
          id[i] = static_cast<int>(t);
        }
      });
  }
  // 3. each covered pixel's point: its ray meets its triangle's plane
  std::vector<Sample> out;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int t = id[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
      if (t < 0) continue;
      const Tri& tri = tris[static_cast<size_t>(t)];
      const glm::vec3 d = view.worldRay(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
      glm::vec3 normal = glm::cross(tri.b - tri.a, tri.c - tri.a);
      const float length = glm::length(normal), along = glm::dot(d, normal);
      if (!(length > 0.0f) || along == 0.0f) continue;
      normal /= length;
      const glm::vec3 p = view.eye + d * (glm::dot(tri.a - view.eye, normal * length) / along);
      if (glm::dot(normal, d) > 0.0f) normal = -normal;  // faces the camera
      out.push_back({p, normal});
    }
  return out;
}

}  // namespace

const std::vector<glm::vec3>& defaultLightCandidates() {
  static const std::vector<glm::vec3> candidates = [] {
    std::vector<glm::vec3> out = {glm::normalize(DirectionalLight{}.direction)};
    for (const float elevation : {30.0f, 60.0f})
      for (int k = 0; k < 8; ++k) {
        const float azimuth = glm::radians(45.0f * static_cast<float>(k)), e = glm::radians(elevation);
        const glm::vec3 toward(std::cos(e) * std::sin(azimuth), std::sin(e), std::cos(e) * std::cos(azimuth));
        out.push_back(-glm::normalize(toward));
      }
    return out;
  }();
  return candidates;
}

namespace {

LitShare shareOf(const std::vector<Tri>& tris, const std::vector<Sample>& samples, const Bounds& bounds,
                 const glm::vec3& direction, int size) {
  LitShare out;
  out.surface = static_cast<int>(samples.size());
  if (samples.empty()) return out;
  // The light's frame: depth along l, the map over (u, v), fitted to the bounds' corners.
  const glm::vec3 l = glm::normalize(direction);
  const glm::vec3 helper = std::fabs(l.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  const glm::vec3 u = glm::normalize(glm::cross(helper, l)), v = glm::cross(l, u);
  glm::vec2 lo(kInf), hi(-kInf);
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 c((i & 1) ? bounds.hi.x : bounds.lo.x, (i & 2) ? bounds.hi.y : bounds.lo.y,
                      (i & 4) ? bounds.hi.z : bounds.lo.z);
    const glm::vec2 q(glm::dot(c, u), glm::dot(c, v));
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  const float texel = std::max({hi.x - lo.x, hi.y - lo.y, 1e-20f}) / static_cast<float>(size);
  auto toMap = [&](const glm::vec3& p) {
    return glm::vec3((glm::dot(p, u) - lo.x) / texel, (glm::dot(p, v) - lo.y) / texel, glm::dot(p, l));
  };
  std::vector<float> map(static_cast<size_t>(size) * static_cast<size_t>(size), kInf);
  for (const Tri& t : tris)
    rasterise(toMap(t.a), toMap(t.b), toMap(t.c), size, size, [&](int x, int y, float depth) {
      float& m = map[static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)];
      m = std::min(m, depth);
    });
  // Each receiver: facing the light, and (pushed off its surface by a texel and a half) no
  // nearer than the map's nearest surface at its texel, within half a texel.
  int lit = 0;
  for (const Sample& s : samples) {
    if (!(glm::dot(s.normal, -l) > 0.0f)) continue;
    const glm::vec3 q = toMap(s.position + s.normal * (1.5f * texel));
    const int x = static_cast<int>(std::floor(q.x)), y = static_cast<int>(std::floor(q.y));
    const bool inMap = x >= 0 && y >= 0 && x < size && y < size;
    if (!inMap || q.z <= map[static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)] + 0.5f * texel)
      ++lit;
  }
  out.share = static_cast<float>(lit) / static_cast<float>(out.surface);
  return out;
}

}  // namespace

LitShare litShare(const Scene& scene, const Camera& camera, const glm::vec3& direction, int width, int height,
                  int size) {
  const std::vector<Tri> tris = allTriangles(scene);
  const Bounds bounds = scene.bounds();
  return shareOf(tris, viewSamples(tris, camera, width, height, bounds.diagonal()), bounds, direction, size);
}

namespace {
constexpr int kProbeHeight = 72;
// The probe G-buffer's width for an image of aspect W/H, kProbeHeight high.
int probeWidth(float aspect) {
  return std::clamp(static_cast<int>(std::lround(kProbeHeight * (std::isfinite(aspect) ? aspect : 1.0f))), 8, 512);
}
}  // namespace

DefaultLightChoice chooseDefaultLight(const Scene& scene, const Camera& camera, float aspect) {
  constexpr int kHeight = kProbeHeight;
  const int width = probeWidth(aspect);
  const std::vector<Tri> tris = allTriangles(scene);
  const Bounds bounds = scene.bounds();
  const std::vector<Sample> samples = viewSamples(tris, camera, width, kHeight, bounds.diagonal());
  DefaultLightChoice out;
  out.surface = static_cast<int>(samples.size());
  const std::vector<glm::vec3>& candidates = defaultLightCandidates();
  // Each candidate's share on its own (side by side: independent), then the choice in order.
  out.shares.assign(candidates.size(), 0.0f);
  parallelFor(size_t{0}, candidates.size(),
              [&](size_t i) { out.shares[i] = shareOf(tris, samples, bounds, candidates[i], 256).share; });
  for (size_t i = 0; i < candidates.size(); ++i)
    if (out.shares[i] > out.shares[static_cast<size_t>(out.chosen)]) out.chosen = static_cast<int>(i);
  out.direction = candidates[static_cast<size_t>(out.chosen)];
  return out;
}

FramedSize framedSize(const Scene& scene, const Camera& camera, float aspect) {
  FramedSize out;
  out.diagonal = scene.bounds().diagonal();
  const std::vector<Tri> tris = allTriangles(scene, /*skipBlend=*/true);
  const std::vector<Sample> samples = viewSamples(tris, camera, probeWidth(aspect), kProbeHeight, out.diagonal);
  out.surface = static_cast<int>(samples.size());
  if (samples.empty()) {
    out.size = out.diagonal;  // nothing in view: the old basis (no pixel is shaded anyway)
    return out;
  }
  // 1. each visible point's depth along the view direction
  const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
  std::vector<float> depths;
  depths.reserve(samples.size());
  for (const Sample& s : samples) depths.push_back(glm::dot(s.position - camera.eye, forward));
  // 2. the median (the lower of the middle two)
  const auto middle = depths.begin() + static_cast<std::ptrdiff_t>((depths.size() - 1) / 2);
  std::nth_element(depths.begin(), middle, depths.end());
  out.medianDepth = *middle;
  // 3. the height of the view at that depth
  out.size = 2.0f * out.medianDepth * std::tan(0.5f * camera.yfov);
  if (!(std::isfinite(out.size) && out.size > 0.0f)) out.size = out.diagonal;
  return out;
}

}  // namespace mrr
