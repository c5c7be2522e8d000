#include "scenes/builtin.h"

#include <glm/gtc/constants.hpp>

#include <cmath>

#include "common/error.h"
#include "common/hash.h"

namespace mrr {

namespace {

constexpr float kPi = glm::pi<float>();

// A mesh builder: faces are given counter-clockwise as seen from their front side.
struct MeshBuilder {
  Mesh mesh;
  MeshBuilder(std::string name, glm::vec3 color) {
    mesh.name = std::move(name);
    mesh.baseColor = color;
  }
  uint32_t vertex(glm::vec3 p, glm::vec3 n) {
    mesh.positions.push_back(p);
    mesh.normals.push_back(glm::normalize(n));
    return static_cast<uint32_t>(mesh.positions.size() - 1);
  }
  // Flat quad p0 p1 p2 p3 (counter-clockwise from the front).
  void quad(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3) {
    const glm::vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    const uint32_t a = vertex(p0, n), b = vertex(p1, n), c = vertex(p2, n), d = vertex(p3, n);
    mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
  }
  // Axis-aligned box (optionally turned about Y by `yaw`), outward faces.
  void box(glm::vec3 center, glm::vec3 half, float yaw = 0.0f) {
    const float c = std::cos(yaw), s = std::sin(yaw);
    auto at = [&](float x, float y, float z) {
      const glm::vec3 l(x * half.x, y * half.y, z * half.z);
      return center + glm::vec3(c * l.x + s * l.z, l.y, -s * l.x + c * l.z);
    };
    quad(at(-1, -1, 1), at(1, -1, 1), at(1, 1, 1), at(-1, 1, 1));      // +z
    quad(at(1, -1, -1), at(-1, -1, -1), at(-1, 1, -1), at(1, 1, -1));  // −z
    quad(at(1, -1, 1), at(1, -1, -1), at(1, 1, -1), at(1, 1, 1));      // +x
    quad(at(-1, -1, -1), at(-1, -1, 1), at(-1, 1, 1), at(-1, 1, -1));  // −x
    quad(at(-1, 1, 1), at(1, 1, 1), at(1, 1, -1), at(-1, 1, -1));      // +y
    quad(at(-1, -1, -1), at(1, -1, -1), at(1, -1, 1), at(-1, -1, 1));  // −y
  }
  // UV sphere with smooth normals: curved, so it tests that smooth shading makes no edges.
  void sphere(glm::vec3 center, float radius, int rings, int segments) {
    const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
    for (int i = 0; i <= rings; ++i) {
      const float theta = kPi * static_cast<float>(i) / static_cast<float>(rings);
      for (int j = 0; j <= segments; ++j) {
        const float phi = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
        const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                          std::sin(theta) * std::sin(phi));
        vertex(center + radius * n, n);
      }
    }
    const uint32_t row = static_cast<uint32_t>(segments + 1);
    for (uint32_t i = 0; i < static_cast<uint32_t>(rings); ++i)
      for (uint32_t j = 0; j < static_cast<uint32_t>(segments); ++j) {
        const uint32_t a = base + i * row + j, b = a + row;
        mesh.indices.insert(mesh.indices.end(), {a, a + 1, b + 1, a, b + 1, b});
      }
  }
};

Scene finish(std::string name, std::vector<MeshBuilder> parts, Camera camera) {
  Scene s;
  s.name = "builtin:" + name;
  s.credit = "built-in scene '" + name + "' (mrr)";
  for (auto& p : parts) s.meshes.push_back(std::move(p.mesh));
  s.light.direction = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.55f));
  s.hasLight = true;
  s.cameras.push_back(camera);
  return s;
}

// A fronto-parallel square filling the view: no edges, AO 1 everywhere (SPEC §2, §6).
Scene plane() {
  MeshBuilder m("plane", glm::vec3(0.8f));
  m.quad({-4, -4, 0}, {4, -4, 0}, {4, 4, 0}, {-4, 4, 0});
  return finish("plane", {m}, lookAt({0, 0, 5}, {0, 0, 0}, 60.0f));
}

// A plane slanted 60° away from the viewer, filling the view: 1/z is affine on it, so it
// has no depth edge whatever its slant (SPEC §2).
Scene slanted() {
  MeshBuilder m("slanted", glm::vec3(0.8f));
  m.quad({-20, -3, 10}, {20, -3, 10}, {20, 3, -40}, {-20, 3, -40});
  return finish("slanted", {m}, lookAt({0, 2, 6}, {0, 0.4f, -2}, 50.0f));
}

// Floor and two walls meeting in a corner: the three creases are normal edges.
Scene corner() {
  MeshBuilder floor("floor", glm::vec3(0.8f)), left("left wall", glm::vec3(0.8f, 0.3f, 0.3f)),
      back("back wall", glm::vec3(0.3f, 0.8f, 0.3f));
  floor.quad({0, 0, 0}, {0, 0, 6}, {6, 0, 6}, {6, 0, 0});
  left.quad({0, 0, 0}, {0, 6, 0}, {0, 6, 6}, {0, 0, 6});
  back.quad({0, 0, 0}, {6, 0, 0}, {6, 6, 0}, {0, 6, 0});
  return finish("corner", {floor, left, back}, lookAt({5, 4, 5}, {0.5f, 0.5f, 0.5f}, 60.0f));
}

// A staircase: parallel treads at different depths (depth edges) joined by risers (creases).
Scene steps() {
  MeshBuilder m("steps", glm::vec3(0.75f, 0.7f, 0.6f));
  const float w = 4.0f, rise = 0.4f, run = 0.8f;
  for (int i = 0; i < 6; ++i) {
    const float y = static_cast<float>(i) * rise, z = -static_cast<float>(i) * run;
    m.quad({-w, y, z}, {w, y, z}, {w, y + rise, z}, {-w, y + rise, z});                    // riser
    m.quad({-w, y + rise, z}, {w, y + rise, z}, {w, y + rise, z - run}, {-w, y + rise, z - run});  // tread
  }
  m.quad({-w, 0, 4}, {w, 0, 4}, {w, 0, 0}, {-w, 0, 0});  // landing
  return finish("steps", {m}, lookAt({2.5f, 3.5f, 5}, {0, 1.0f, -2}, 55.0f));
}

// Boxes standing in a room: contact shadows for AO, silhouettes for depth edges.
Scene boxes() {
  MeshBuilder room("room", glm::vec3(0.8f)), box("boxes", glm::vec3(0.7f, 0.6f, 0.4f));
  room.quad({-5, 0, -5}, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5});    // floor
  room.quad({-5, 0, -5}, {5, 0, -5}, {5, 5, -5}, {-5, 5, -5});  // back wall
  room.quad({-5, 0, 5}, {-5, 0, -5}, {-5, 5, -5}, {-5, 5, 5});  // left wall
  box.box({-1.5f, 0.75f, -1.5f}, {0.75f, 0.75f, 0.75f}, 0.3f);
  box.box({1.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, -0.5f);
  return finish("boxes", {room, box}, lookAt({4, 3.5f, 6}, {0, 0.8f, -1}, 60.0f));
}

// The README's default: a room with boxes, a smooth sphere, columns and a staircase — large
// flat areas the coarse levels can take, creases and contacts for SSAO, and curved surfaces
// that must not raise edges.
Scene demo() {
  MeshBuilder room("room", glm::vec3(0.85f, 0.82f, 0.78f)), boxesPart("boxes", glm::vec3(0.75f, 0.55f, 0.35f)),
      ball("sphere", glm::vec3(0.6f, 0.65f, 0.8f)), cols("columns", glm::vec3(0.7f, 0.7f, 0.72f)),
      stair("stairs", glm::vec3(0.65f, 0.6f, 0.55f));
  room.quad({-6, 0, -6}, {-6, 0, 6}, {6, 0, 6}, {6, 0, -6});    // floor
  room.quad({-6, 0, -6}, {6, 0, -6}, {6, 6, -6}, {-6, 6, -6});  // back wall
  room.quad({-6, 0, 6}, {-6, 0, -6}, {-6, 6, -6}, {-6, 6, 6});  // left wall
  boxesPart.box({-3.2f, 0.8f, -3.0f}, {0.8f, 0.8f, 0.8f}, 0.35f);
  boxesPart.box({-3.0f, 2.0f, -3.1f}, {0.4f, 0.4f, 0.4f}, -0.2f);
  boxesPart.box({2.6f, 0.45f, 1.2f}, {0.9f, 0.45f, 0.6f}, -0.6f);
  ball.sphere({0.2f, 1.1f, -0.8f}, 1.1f, 48, 96);
  for (int i = 0; i < 3; ++i)
    cols.box({-5.2f + 2.0f * static_cast<float>(i), 2.5f, -5.4f}, {0.3f, 2.5f, 0.3f});
  for (int i = 0; i < 5; ++i) {
    const float y = 0.3f * static_cast<float>(i + 1), x0 = 2.0f + 0.6f * static_cast<float>(i);
    stair.box({x0 + 1.5f, y * 0.5f, -4.5f}, {0.3f, y * 0.5f, 1.2f});
  }
  return finish("demo", {room, boxesPart, ball, cols, stair},
                lookAt({4.8f, 4.2f, 7.5f}, {-0.4f, 1.0f, -1.8f}, 60.0f));
}

// Two thin slabs over a ground plane, one low and one high, under a near-vertical light:
// umbrae, fully lit ground, and penumbrae that widen with the blocker's height (SSM tests).
Scene shadows() {
  MeshBuilder ground("ground", glm::vec3(0.8f)), slabs("slabs", glm::vec3(0.6f, 0.6f, 0.7f));
  ground.quad({-12, 0, -12}, {-12, 0, 12}, {12, 0, 12}, {12, 0, -12});
  slabs.box({-3.0f, 0.5f, 0.0f}, {1.0f, 0.05f, 1.0f});
  slabs.box({3.0f, 2.5f, 0.0f}, {1.0f, 0.05f, 1.0f});
  Scene s = finish("shadows", {ground, slabs}, lookAt({0, 9, 7}, {0, 0, 0}, 55.0f));
  s.light.direction = glm::normalize(glm::vec3(0.15f, -1.0f, 0.1f));
  return s;
}

// A pure red wall standing on a white floor (SSGI tests: colour bleeding, red and never green).
Scene redwall() {
  MeshBuilder floor("floor", glm::vec3(1.0f)), wall("red wall", glm::vec3(1.0f, 0.0f, 0.0f));
  floor.quad({-6, 0, -6}, {-6, 0, 6}, {6, 0, 6}, {6, 0, -6});
  wall.quad({-6, 0, -2}, {6, 0, -2}, {6, 4, -2}, {-6, 4, -2});
  Scene s = finish("redwall", {floor, wall}, lookAt({0, 3.5f, 6}, {0, 0.5f, -1}, 55.0f));
  s.light.direction = glm::normalize(glm::vec3(0.2f, -0.6f, -1.0f));  // lights the wall's front
  return s;
}

// A lattice fence cut out of one quad by an alpha cutout (glTF alphaMode MASK, docs/spec.md
// §1.1), before a wall and over a ground, under a light from the front: the holes show the wall
// and let the light through, so the lattice's shadow falls on both. The cutout is 16×16 texels,
// a bar one texel wide every fourth texel in each direction, repeated 3 × 2 times across the
// quad (wrap: repeat), so the fence has 12 × 8 square holes.
Scene fence() {
  MeshBuilder ground("ground", glm::vec3(0.8f)), wall("wall", glm::vec3(0.75f, 0.7f, 0.6f)),
      lattice("lattice", glm::vec3(0.45f, 0.3f, 0.2f));
  ground.quad({-8, 0, -6}, {-8, 0, 8}, {8, 0, 8}, {8, 0, -6});
  wall.quad({-8, 0, -2.5f}, {8, 0, -2.5f}, {8, 4, -2.5f}, {-8, 4, -2.5f});
  lattice.quad({-3, 0, 0}, {3, 0, 0}, {3, 2, 0}, {-3, 2, 0});
  lattice.mesh.texcoords = {{0, 2}, {3, 2}, {3, 0}, {0, 0}};  // t = 0 at the top: the image's first row
  lattice.mesh.cutout = 0;
  Scene s = finish("fence", {ground, wall, lattice}, lookAt({2.5f, 2.2f, 5.5f}, {0, 0.9f, -0.5f}, 55.0f));
  Cutout cutout;
  cutout.width = cutout.height = 16;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) cutout.opaque.push_back(x % 4 == 0 || y % 4 == 0 ? 1 : 0);
  s.cutouts.push_back(std::move(cutout));
  s.light.direction = glm::normalize(glm::vec3(-0.3f, -0.45f, -0.85f));
  return s;
}

// Stress scenes (SPEC §10): each models one way the method can fail, and nothing more.

// A floor whose shading normals are perturbed facet by facet, as a normal map would: flat
// geometry, so AO barely changes, but neighbouring facets (~3 pixels at 1280×720) differ by
// ~25°, so normal edges explode (the paper's warning about bumpy surfaces).
Scene bumpy() {
  MeshBuilder floor("bumpy floor", glm::vec3(0.8f)), block("block", glm::vec3(0.7f, 0.6f, 0.5f));
  const int n = 160;
  const float extent = 8.0f, step = 2.0f * extent / static_cast<float>(n);
  auto corner = [&](int i, int j) {
    return glm::vec3(-extent + step * static_cast<float>(i), 0.0f, -extent + step * static_cast<float>(j));
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (uint32_t t = 0; t < 2; ++t) {
        // a deterministic jitter of the facet's normal: ±0.45 in x and z
        const uint32_t h = pixelHash(static_cast<uint32_t>(i), static_cast<uint32_t>(j), 0x6b756d70u + t);
        const glm::vec3 nrm(0.9f * (hashToUnit(h) - 0.5f), 1.0f, 0.9f * (hashToUnit(pcgHash(h ^ 0x9e3779b9u)) - 0.5f));
        const glm::vec3 p0 = corner(i, j), p1 = t ? corner(i + 1, j + 1) : corner(i, j + 1),
                        p2 = t ? corner(i + 1, j) : corner(i + 1, j + 1);
        const uint32_t v0 = floor.vertex(p0, nrm), v1 = floor.vertex(p1, nrm), v2 = floor.vertex(p2, nrm);
        floor.mesh.indices.insert(floor.mesh.indices.end(), {v0, v1, v2});
      }
  block.box({0.0f, 0.8f, -1.0f}, {1.2f, 0.8f, 0.8f}, 0.4f);
  return finish("bumpy", {floor, block}, lookAt({5, 4.5f, 7}, {0, 0.3f, -1}, 55.0f));
}

// Rails and wires thinner than a coarse pixel (a ⅛-level pixel is 8 full-res pixels wide):
// a coarse level alone misses them; only their edges bring full resolution to them.
Scene wires() {
  MeshBuilder floor("floor", glm::vec3(0.8f)), rails("rails", glm::vec3(0.5f, 0.5f, 0.55f));
  floor.quad({-8, 0, -8}, {-8, 0, 8}, {8, 0, 8}, {8, 0, -8});
  for (int i = 0; i < 5; ++i) {  // horizontal rails 1.5 cm thick, at different heights
    const float y = 0.3f + 0.35f * static_cast<float>(i), z = -1.0f - 0.4f * static_cast<float>(i);
    rails.box({0.0f, y, z}, {5.0f, 0.008f, 0.008f});
  }
  for (int i = 0; i < 7; ++i)  // posts
    rails.box({-4.5f + 1.5f * static_cast<float>(i), 1.0f, -1.0f}, {0.01f, 1.0f, 0.01f});
  return finish("wires", {floor, rails}, lookAt({1.5f, 2.5f, 6}, {0, 0.8f, -1.5f}, 55.0f));
}

// Small faceted pyramids tiling a wall that fills the view, ~5.5 full-res pixels each at
// 1280×720: every pixel is on or next to a crease, so E covers the image and nothing can be
// shaded coarsely. The never-slower rule's case.
Scene alledges() {
  MeshBuilder m("pyramids", glm::vec3(0.8f));
  const int nx = 233, ny = 131;  // not commensurate with common image sizes: no aliasing to one facet
  const float size = 8.0f / static_cast<float>(nx);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const float x0 = -4.0f + size * static_cast<float>(i), y0 = -2.25f + size * static_cast<float>(j);
      const glm::vec3 a(x0, y0, 0), b(x0 + size, y0, 0), c(x0 + size, y0 + size, 0), d(x0, y0 + size, 0);
      const glm::vec3 apex(x0 + 0.5f * size, y0 + 0.5f * size, 0.5f * size);
      for (auto [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, d}, std::pair{d, a}}) {
        const glm::vec3 nrm = glm::normalize(glm::cross(q - p, apex - p));
        const uint32_t v0 = m.vertex(p, nrm), v1 = m.vertex(q, nrm), v2 = m.vertex(apex, nrm);
        m.mesh.indices.insert(m.mesh.indices.end(), {v0, v1, v2});
      }
    }
  // 2 tan(fov/2) · 6.2 = 4.5 high: the wall fills the view
  return finish("alledges", {m}, lookAt({0, 0, 6.2f}, {0, 0, 0}, 40.0f));
}

struct Entry {
  const char* name;
  const char* description;
  Scene (*make)();
};

const Entry kEntries[] = {
    {"demo", "room with boxes, a sphere, columns and stairs: the default", demo},
    {"plane", "fronto-parallel plane filling the view: no edges, AO 1, ideal speedup 64", plane},
    {"slanted", "plane slanted 60 degrees: no depth edges (1/z is affine)", slanted},
    {"corner", "floor and two walls: creases are normal edges", corner},
    {"steps", "a staircase: depth edges and creases", steps},
    {"boxes", "two boxes in a room: silhouettes and contact occlusion", boxes},
    {"shadows", "two slabs at different heights over a ground: umbra, penumbra width (ssm)", shadows},
    {"redwall", "a red wall on a white floor: colour bleeding (ssgi)", redwall},
    {"fence", "a lattice fence cut out by an alpha mask before a wall: holes and their shadows", fence},
    {"bumpy", "stress: a floor with perturbed normals, so normal edges explode", bumpy},
    {"wires", "stress: rails and posts thinner than a coarse pixel", wires},
    {"alledges", "stress: tiny faceted pyramids, every pixel an edge (never-slower)", alledges},
};

}  // namespace

const std::vector<std::string>& builtinSceneNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const Entry& e : kEntries) n.emplace_back(e.name);
    return n;
  }();
  return names;
}

std::string builtinSceneDescription(const std::string& name) {
  for (const Entry& e : kEntries)
    if (name == e.name) return e.description;
  return {};
}

Scene makeBuiltinScene(const std::string& name) {
  for (const Entry& e : kEntries)
    if (name == e.name) return e.make();
  std::string list;
  for (const Entry& e : kEntries) list += (list.empty() ? "" : ", ") + std::string(e.name);
  throw MrrError("--scene builtin:" + name + ": unknown built-in scene (expected one of " + list + ")");
}

}  // namespace mrr
