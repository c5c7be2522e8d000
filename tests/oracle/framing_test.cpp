// The default framing of interiors: "inside" means the eye is inside the bounds, and
// BLEND surfaces (glass) do not decide the framing. Two small scenes made here reproduce what
// public files showed: a study with a window (a hole the bounds' centre sees out of, part of it
// glazed), framed from outside its bounds through the hole; and a hotel room with a door and a
// gable roof, framed from above its roof. Each must now be framed from inside its room, and the
// first picture's centre must show the room: an opaque surface, not the glass or the roof.
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <optional>

#include "common/camera.h"
#include "common/scene.h"
#include "cpu_ref/pipeline.h"
#include "scenes/catalog.h"

namespace mrr {
namespace {

const glm::vec3 kWall{0.7f}, kFloor{0.5f, 0.45f, 0.4f}, kTable{0.3f, 0.2f, 0.1f};
const glm::vec3 kGlass{0.1f, 0.9f, 0.9f}, kRoof{0.9f, 0.2f, 0.2f};

// Adds the quad a b c d (counter-clockwise seen from where its normal points) as a mesh.
void quad(Scene& s, const std::string& name, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 colour,
          bool blend = false) {
  Mesh m;
  m.name = name;
  m.positions = {a, b, c, d};
  m.indices = {0, 1, 2, 0, 2, 3};
  m.baseColor = colour;
  m.blend = blend;
  computeVertexNormals(m);
  s.meshes.push_back(std::move(m));
}

// An axis-aligned rectangle in the plane coordinate[axis] = at, over [lo, hi] in the other two
// axes (u = axis+1, v = axis+2), facing +axis (facing > 0) or −axis; with a hole [holeLo,
// holeHi] (in u, v) cut out as four rectangles around it.
void wall(Scene& s, const std::string& name, int axis, float at, glm::vec2 lo, glm::vec2 hi, int facing,
          glm::vec3 colour, std::optional<std::pair<glm::vec2, glm::vec2>> hole = std::nullopt, bool blend = false) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  auto point = [&](float a, float b) {
    glm::vec3 p;
    p[axis] = at;
    p[u] = a;
    p[v] = b;
    return p;
  };
  auto rect = [&](glm::vec2 l, glm::vec2 h) {
    if (!(l.x < h.x && l.y < h.y)) return;
    // (u × v) = +axis: counter-clockwise in (u, v) faces +axis
    if (facing > 0)
      quad(s, name, point(l.x, l.y), point(h.x, l.y), point(h.x, h.y), point(l.x, h.y), colour, blend);
    else
      quad(s, name, point(l.x, l.y), point(l.x, h.y), point(h.x, h.y), point(h.x, l.y), colour, blend);
  };
  if (!hole) {
    rect(lo, hi);
    return;
  }
  const auto [hl, hh] = *hole;
  rect(lo, {hi.x, hl.y});          // below the hole (in v)
  rect({lo.x, hh.y}, hi);          // above
  rect({lo.x, hl.y}, {hl.x, hh.y});  // beside, low u
  rect({hh.x, hl.y}, {hi.x, hh.y});  // beside, high u
}

// A box of six rectangles facing out (furniture).
void box(Scene& s, glm::vec3 lo, glm::vec3 hi, glm::vec3 colour) {
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    wall(s, "table", axis, lo[axis], {lo[u], lo[v]}, {hi[u], hi[v]}, -1, colour);
    wall(s, "table", axis, hi[axis], {lo[u], lo[v]}, {hi[u], hi[v]}, +1, colour);
  }
}

// The closed room lo…hi, its six sides facing in; `holes` per side index (0 −x, 1 +x, 2 −y,
// 3 +y, 4 −z, 5 +z) in that side's (u, v).
Scene room(glm::vec3 lo, glm::vec3 hi, const std::vector<std::pair<int, std::pair<glm::vec2, glm::vec2>>>& holes) {
  Scene s;
  for (int side = 0; side < 6; ++side) {
    const int axis = side / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
    const bool high = side % 2 == 1;
    std::optional<std::pair<glm::vec2, glm::vec2>> hole;
    for (const auto& [at, h] : holes)
      if (at == side) hole = h;
    wall(s, "room", axis, high ? hi[axis] : lo[axis], {lo[u], lo[v]}, {hi[u], hi[v]}, high ? -1 : +1,
         axis == 1 && !high ? kFloor : kWall, hole);
  }
  return s;
}

// The study of the issue: bounds x, z in [−2.6, 2.6] × [−2.6, 2], a window in the −z wall around
// the centre's height, glazed in its lower part only (BLEND), so the bounds' centre sees out
// through it; a table, and a glass vitrine pane standing in the room.
Scene study() {
  // −z wall (axis 2): u = x, v = y
  Scene s = room({-2.6f, 0.0f, -2.6f}, {2.6f, 2.6f, 2.0f}, {{4, {{-0.8f, 0.9f}, {0.8f, 2.0f}}}});
  wall(s, "window glass", 2, -2.6f, {-0.8f, 0.9f}, {0.8f, 1.2f}, +1, kGlass, std::nullopt, true);
  box(s, {-0.6f, 0.0f, -0.6f}, {0.6f, 0.75f, 0.4f}, kTable);
  // a glass pane across the room's −x end (axis 0: u = y, v = z)
  wall(s, "vitrine glass", 0, -1.9f, {0.0f, -2.5f}, {2.0f, 1.9f}, +1, kGlass, std::nullopt, true);
  return s;
}

// The hotel room of the issue: a room with a door in its +x wall (up to 2.2 of its 2.5 height)
// and a gable roof above its ceiling, up to 4: the bounds' centre (y = 2) sees out of the door.
Scene hotelRoom() {
  // +x wall (axis 0): u = y, v = z
  Scene s = room({-3.0f, 0.0f, -2.0f}, {3.0f, 2.5f, 2.0f}, {{1, {{0.0f, -0.5f}, {2.2f, 0.5f}}}});
  box(s, {-2.0f, 0.0f, -1.2f}, {0.0f, 0.6f, 1.2f}, kTable);  // a bed
  // the roof's two slopes, facing up and out, from the eaves (y 2.5, z ±2.3) to the ridge (y 4, z 0)
  quad(s, "roof", {-3.3f, 2.5f, 2.3f}, {3.3f, 2.5f, 2.3f}, {3.3f, 4.0f, 0.0f}, {-3.3f, 4.0f, 0.0f}, kRoof);
  quad(s, "roof", {3.3f, 2.5f, -2.3f}, {-3.3f, 2.5f, -2.3f}, {-3.3f, 4.0f, 0.0f}, {3.3f, 4.0f, 0.0f}, kRoof);
  return s;
}

bool inside(const glm::vec3& p, glm::vec3 lo, glm::vec3 hi) {
  return p.x > lo.x && p.x < hi.x && p.y > lo.y && p.y < hi.y && p.z > lo.z && p.z < hi.z;
}

// The default framing's first picture (oracle G-buffer, small): its centre pixel's albedo.
glm::vec3 centreAlbedo(const Scene& scene, const Camera& camera) {
  Settings s = defaultSettings(Effect::Ssao);
  s.width = 64;
  s.height = 36;
  s.ssao.samples = 4;
  s.mode = Mode::Full;
  s.neverSlower = false;
  const Renderer renderer(scene);
  const FrameResult f = renderer.render(camera, makeConstants(s, framedSize(scene, camera, 64.0f / 36.0f).size));
  const GBuffer& g = f.levels[0].gbuffer;
  EXPECT_TRUE(g.hit.at(32, 18));
  return {g.albedo.at(32, 18, 0), g.albedo.at(32, 18, 1), g.albedo.at(32, 18, 2)};
}

void expectSeesTheRoom(const Scene& scene, const Camera& camera, const char* what) {
  const glm::vec3 a = centreAlbedo(scene, camera);
  EXPECT_NE(a, kGlass) << what << ": the first picture's centre is the glass";
  EXPECT_NE(a, kRoof) << what << ": the first picture's centre is the roof";
}

TEST(Framing, AStudySeenOutOfItsWindowIsFramedFromInside) {
  Scene scene = study();
  validateScene(scene, "study");
  const Framing f = frameScene(scene, glm::radians(60.0f), 16.0f / 9.0f);
  EXPECT_TRUE(f.interior);
  EXPECT_FALSE(f.openSide) << "a window is not an open side";
  const Bounds b = scene.bounds();
  EXPECT_TRUE(inside(f.camera.eye, b.lo, b.hi)) << "eye " << f.camera.eye.x << ", " << f.camera.eye.y << ", "
                                                 << f.camera.eye.z;
  expectSeesTheRoom(scene, f.camera, "study");
}

TEST(Framing, AHotelRoomWithADoorAndARoofIsFramedFromInsideTheRoom) {
  Scene scene = hotelRoom();
  validateScene(scene, "hotel room");
  const Framing f = frameScene(scene, glm::radians(60.0f), 16.0f / 9.0f);
  EXPECT_TRUE(f.interior);
  EXPECT_FALSE(f.openSide) << "a door is not an open side";
  EXPECT_TRUE(inside(f.camera.eye, {-3.0f, 0.0f, -2.0f}, {3.0f, 2.5f, 2.0f}))
      << "eye " << f.camera.eye.x << ", " << f.camera.eye.y << ", " << f.camera.eye.z << " is not in the room";
  expectSeesTheRoom(scene, f.camera, "hotel room");
}

TEST(Framing, AGlassWallClosesARoomButDoesNotEndTheView) {
  // A room whose −z wall is all glass (BLEND): the glass closes the room (the enclosure counts
  // it: not an open side, not an object), but the view does not end on it.
  Scene scene = room({-2.6f, 0.0f, -2.6f}, {2.6f, 2.6f, 2.0f}, {});
  scene.meshes.erase(std::remove_if(scene.meshes.begin(), scene.meshes.end(),
                                    [](const Mesh& m) {
                                      for (const glm::vec3& p : m.positions)
                                        if (p.z != -2.6f) return false;
                                      return true;
                                    }),
                     scene.meshes.end());
  wall(scene, "glass front", 2, -2.6f, {-2.6f, 0.0f}, {2.6f, 2.6f}, +1, kGlass, std::nullopt, true);
  const Framing f = frameScene(scene, glm::radians(60.0f), 16.0f / 9.0f);
  EXPECT_TRUE(f.interior);
  EXPECT_FALSE(f.openSide);
  expectSeesTheRoom(scene, f.camera, "glass-fronted room");
}

}  // namespace
}  // namespace mrr
