// Tests of the scene model helpers: bounds, normals, validation, framing and flipping.
#include "common/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "common/camera.h"
#include "common/error.h"

namespace mrr {
namespace {

Mesh makeTriangle(const std::string& name, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  Mesh mesh;
  mesh.name = name;
  mesh.positions = {a, b, c};
  mesh.indices = {0, 1, 2};
  computeVertexNormals(mesh);
  return mesh;
}

Scene oneTriangleScene() {
  Scene scene;
  scene.name = "test";
  scene.meshes.push_back(makeTriangle("tri", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  return scene;
}

// Runs validateScene and returns the MrrError message ("" if none was thrown).
std::string validationError(const Scene& scene, const std::string& source = "my/scene.gltf") {
  try {
    validateScene(scene, source);
  } catch (const MrrError& e) {
    return e.what();
  }
  return "";
}

void expectOneLineNaming(const std::string& message, const std::string& source,
                         const std::string& fragment) {
  EXPECT_NE(message.find(source), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_NE(message.find(fragment), std::string::npos) << message;
}

TEST(SceneTest, BoundsAndTriangleCount) {
  Scene scene = oneTriangleScene();
  scene.meshes.push_back(makeTriangle("b", {-2, 0, 5}, {0, 3, 0}, {1, 1, -1}));
  scene.meshes.back().positions.push_back({0, 0, 0});  // an unused vertex still counts
  scene.meshes.back().normals.push_back({0, 1, 0});
  const Bounds b = scene.bounds();
  EXPECT_EQ(b.lo, glm::vec3(-2, 0, -1));
  EXPECT_EQ(b.hi, glm::vec3(1, 3, 5));
  EXPECT_EQ(b.center(), glm::vec3(-0.5f, 1.5f, 2.0f));
  EXPECT_FLOAT_EQ(b.diagonal(), std::sqrt(9.0f + 9.0f + 36.0f));
  EXPECT_EQ(scene.triangleCount(), 2u);
}

TEST(SceneTest, BoundsOfEmptySceneIsZeroSize) {
  Scene scene;
  const Bounds b = scene.bounds();
  EXPECT_EQ(b.lo, glm::vec3(0.0f));
  EXPECT_EQ(b.hi, glm::vec3(0.0f));
  EXPECT_EQ(scene.triangleCount(), 0u);
}

TEST(SceneTest, ComputeVertexNormalsFollowsCounterClockwiseWinding) {
  Mesh mesh = makeTriangle("t", {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  ASSERT_EQ(mesh.normals.size(), 3u);
  for (const glm::vec3& n : mesh.normals) EXPECT_NEAR(glm::distance(n, glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
  std::swap(mesh.indices[1], mesh.indices[2]);
  computeVertexNormals(mesh);
  for (const glm::vec3& n : mesh.normals) EXPECT_NEAR(glm::distance(n, glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
}

TEST(SceneTest, ComputeVertexNormalsIsAreaWeighted) {
  // Vertex 0 is shared by a big triangle facing +Z (area 8) and a small one facing +X (area 0.5).
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.indices = {0, 1, 2, 0, 3, 4};
  computeVertexNormals(mesh);
  const glm::vec3 expected = glm::normalize(glm::vec3(0.5f, 0.0f, 8.0f));
  EXPECT_NEAR(glm::distance(mesh.normals[0], expected), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(mesh.normals[1], glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(mesh.normals[3], glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
}

TEST(SceneTest, ComputeVertexNormalsStaysFiniteForUnusedAndDegenerateVertices) {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 5, 5}};  // collinear + unused
  mesh.indices = {0, 1, 2};
  computeVertexNormals(mesh);
  ASSERT_EQ(mesh.normals.size(), 4u);
  for (const glm::vec3& n : mesh.normals) {
    EXPECT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
  }
}

TEST(SceneTest, ComputeVertexNormalsReplacesWrongSizedNormals) {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  mesh.normals = {{1, 0, 0}};
  computeVertexNormals(mesh);
  ASSERT_EQ(mesh.normals.size(), 3u);
  EXPECT_NEAR(glm::distance(mesh.normals[0], glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
}

TEST(SceneTest, ValidateAcceptsAGoodScene) {
  EXPECT_EQ(validationError(oneTriangleScene()), "");
  // One good triangle is enough even when others are degenerate.
  Scene scene = oneTriangleScene();
  scene.meshes.push_back(makeTriangle("flat", {0, 0, 0}, {1, 1, 1}, {2, 2, 2}));
  EXPECT_EQ(validationError(scene), "");
}

TEST(SceneTest, ValidateRejectsNoMeshes) {
  Scene scene;
  expectOneLineNaming(validationError(scene), "my/scene.gltf", "no meshes");
}

TEST(SceneTest, ValidateRejectsNoTriangles) {
  Scene scene;
  scene.meshes.emplace_back();
  scene.meshes.back().name = "empty";
  expectOneLineNaming(validationError(scene), "my/scene.gltf", "no triangles");
}

TEST(SceneTest, ValidateRejectsIndexOutOfRange) {
  Scene scene = oneTriangleScene();
  scene.meshes[0].indices[2] = 17;
  const std::string message = validationError(scene);
  expectOneLineNaming(message, "my/scene.gltf", "17");
  EXPECT_NE(message.find("'tri'"), std::string::npos) << message;
  EXPECT_NE(message.find("out of range"), std::string::npos) << message;
}

TEST(SceneTest, ValidateRejectsNonFinitePositionsAndNormals) {
  Scene scene = oneTriangleScene();
  scene.meshes[0].positions[1].y = std::numeric_limits<float>::quiet_NaN();
  expectOneLineNaming(validationError(scene), "my/scene.gltf", "position");

  scene = oneTriangleScene();
  scene.meshes[0].positions[0].x = std::numeric_limits<float>::infinity();
  expectOneLineNaming(validationError(scene), "my/scene.gltf", "position");

  scene = oneTriangleScene();
  scene.meshes[0].normals[2].z = -std::numeric_limits<float>::infinity();
  expectOneLineNaming(validationError(scene), "my/scene.gltf", "normal");
}

TEST(SceneTest, ValidateRejectsMissingNormals) {
  Scene scene = oneTriangleScene();
  scene.meshes[0].normals.clear();
  expectOneLineNaming(validationError(scene), "my/scene.gltf", "normals");
}

TEST(SceneTest, ValidateRejectsAllDegenerateTriangles) {
  Scene scene;
  scene.meshes.push_back(makeTriangle("line", {0, 0, 0}, {1, 1, 1}, {2, 2, 2}));
  scene.meshes.push_back(makeTriangle("point", {3, 3, 3}, {3, 3, 3}, {3, 3, 3}));
  expectOneLineNaming(validationError(scene), "my/scene.gltf", "degenerate");
}

TEST(SceneTest, FrameBoundsLooksAtTheCentreFromFrontAbove) {
  const Bounds bounds{{-1, 0, -2}, {3, 2, 4}};
  const float yfov = 0.8f;
  const Camera camera = frameBounds(bounds, yfov);
  EXPECT_EQ(camera.target, bounds.center());
  EXPECT_EQ(camera.up, glm::vec3(0, 1, 0));
  EXPECT_FLOAT_EQ(camera.yfov, yfov);
  const glm::vec3 offset = camera.eye - camera.target;
  EXPECT_GT(offset.y, 0.0f);  // above
  EXPECT_GT(offset.z, 0.0f);  // in front (+Z)
  const float radius = 0.5f * bounds.diagonal();
  EXPECT_GE(glm::length(offset), radius / std::sin(0.5f * yfov));  // the whole sphere fits
  EXPECT_LT(glm::length(offset), 2.0f * radius / std::sin(0.5f * yfov));  // not lost in the distance
}

TEST(SceneTest, FrameBoundsProjectsEveryCornerIntoTheImage) {
  const Bounds bounds{{100, -5, 20}, {160, 15, 21}};
  // Square and landscape images: the vertical field is the narrow one.
  for (const auto& [w, h] : {std::pair{64, 64}, std::pair{160, 90}}) {
    const Camera camera = frameBounds(bounds, 0.9f);
    const View view = makeView(camera, w, h, w, h);
    const glm::vec2 centre = view.project(view.toView(bounds.center()));
    EXPECT_NEAR(centre.x, 0.5f * float(w), 1e-3f * float(w));
    EXPECT_NEAR(centre.y, 0.5f * float(h), 1e-3f * float(h));
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p{corner & 1 ? bounds.hi.x : bounds.lo.x, corner & 2 ? bounds.hi.y : bounds.lo.y,
                        corner & 4 ? bounds.hi.z : bounds.lo.z};
      const glm::vec3 v = view.toView(p);
      ASSERT_LT(v.z, 0.0f);  // in front of the camera
      const glm::vec2 pixel = view.project(v);
      EXPECT_GE(pixel.x, 0.0f);
      EXPECT_LE(pixel.x, float(w));
      EXPECT_GE(pixel.y, 0.0f);
      EXPECT_LE(pixel.y, float(h));
    }
  }
}

TEST(SceneTest, FrameBoundsHandlesZeroSizeBounds) {
  for (const glm::vec3& at : {glm::vec3(0.0f), glm::vec3(1000.0f, -2000.0f, 5e4f)}) {
    const Camera camera = frameBounds(Bounds{at, at}, 0.9f);
    for (int i = 0; i < 3; ++i) {
      EXPECT_TRUE(std::isfinite(camera.eye[i]));
      EXPECT_TRUE(std::isfinite(camera.target[i]));
    }
    EXPECT_GT(glm::length(camera.eye - camera.target), 0.0f);
    EXPECT_NO_THROW(makeView(camera, 32, 32, 32, 32));
  }
}

TEST(SceneTest, FlipUpRotatesEverythingAboutX) {
  Scene scene;
  scene.meshes.push_back(makeTriangle("t", {1, 2, 3}, {2, 2, 3}, {1, 3, 4}));
  scene.light.direction = glm::normalize(glm::vec3(0.2f, -1.0f, 0.3f));
  scene.hasLight = true;
  Camera camera;
  camera.eye = {1, 2, 3};
  camera.target = {4, 5, 6};
  camera.up = {0, 1, 0};
  scene.cameras.push_back(camera);
  const Scene before = scene;

  flipUp(scene);
  auto flipped = [](glm::vec3 v) { return glm::vec3(v.x, -v.y, -v.z); };
  for (size_t v = 0; v < 3; ++v) {
    EXPECT_EQ(scene.meshes[0].positions[v], flipped(before.meshes[0].positions[v]));
    EXPECT_EQ(scene.meshes[0].normals[v], flipped(before.meshes[0].normals[v]));
  }
  EXPECT_EQ(scene.meshes[0].indices, before.meshes[0].indices);
  EXPECT_EQ(scene.light.direction, flipped(before.light.direction));
  EXPECT_EQ(scene.cameras[0].eye, glm::vec3(1, -2, -3));
  EXPECT_EQ(scene.cameras[0].target, glm::vec3(4, -5, -6));
  EXPECT_EQ(scene.cameras[0].up, glm::vec3(0, -1, 0));

  // A rotation keeps fronts in front: the winding still agrees with the normals.
  const Mesh& mesh = scene.meshes[0];
  const glm::vec3 geometric = glm::cross(mesh.positions[1] - mesh.positions[0], mesh.positions[2] - mesh.positions[0]);
  EXPECT_GT(glm::dot(geometric, mesh.normals[0]), 0.0f);

  // Twice is the identity.
  flipUp(scene);
  EXPECT_EQ(scene.meshes[0].positions, before.meshes[0].positions);
}

TEST(SceneTest, FlipUpKeepsTheDefaultLight) {
  Scene scene = oneTriangleScene();
  const glm::vec3 direction = scene.light.direction;
  flipUp(scene);
  EXPECT_EQ(scene.light.direction, direction);  // already meant for Y-up
}

}  // namespace
}  // namespace mrr

namespace mrr {
namespace {

// A box of six quads facing in (a room), or five (open on +z: a Cornell box), from lo to hi.
Scene roomScene(const glm::vec3& lo, const glm::vec3& hi, bool openFront) {
  Scene scene;
  auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    // counter-clockwise seen from inside (the quads below are listed clockwise from inside)
    scene.meshes.push_back(makeTriangle("q", a, c, b));
    scene.meshes.push_back(makeTriangle("q", a, d, c));
  };
  const glm::vec3 l = lo, h = hi;
  quad({l.x, l.y, l.z}, {h.x, l.y, l.z}, {h.x, l.y, h.z}, {l.x, l.y, h.z});  // floor
  quad({l.x, h.y, l.z}, {l.x, h.y, h.z}, {h.x, h.y, h.z}, {h.x, h.y, l.z});  // ceiling
  quad({l.x, l.y, l.z}, {l.x, h.y, l.z}, {h.x, h.y, l.z}, {h.x, l.y, l.z});  // back
  quad({l.x, l.y, l.z}, {l.x, l.y, h.z}, {l.x, h.y, h.z}, {l.x, h.y, l.z});  // left
  quad({h.x, l.y, l.z}, {h.x, h.y, l.z}, {h.x, h.y, h.z}, {h.x, l.y, h.z});  // right
  if (!openFront) quad({l.x, l.y, h.z}, {h.x, l.y, h.z}, {h.x, h.y, h.z}, {l.x, h.y, h.z});
  return scene;
}

TEST(SceneTest, DefaultFramingFillsTheFrameWithAnObject) {
  // A long thin object: the bounds' sphere would leave most of a 16:9 frame empty.
  Scene scene;
  scene.meshes.push_back(makeTriangle("a", {-4, 0, 0}, {4, 0, 0}, {4, 0.5f, 0.2f}));
  scene.meshes.push_back(makeTriangle("b", {-4, 0, 0}, {4, 0.5f, 0.2f}, {-4, 0.5f, 0.2f}));
  const Framing framing = frameScene(scene, 0.9f, 16.0f / 9.0f);
  EXPECT_FALSE(framing.interior);
  const View view = makeView(framing.camera, 160, 90, 160, 90);
  float widest = 0.0f, tallest = 0.0f;
  for (const Mesh& mesh : scene.meshes)
    for (const glm::vec3& p : mesh.positions) {
      const glm::vec2 pixel = view.project(view.toView(p));
      ASSERT_GE(pixel.x, 0.0f);
      ASSERT_LE(pixel.x, 160.0f);
      ASSERT_GE(pixel.y, 0.0f);
      ASSERT_LE(pixel.y, 90.0f);
      widest = std::max(widest, std::fabs(pixel.x - 80.0f) / 80.0f);
      tallest = std::max(tallest, std::fabs(pixel.y - 45.0f) / 45.0f);
    }
  EXPECT_GT(std::max(widest, tallest), 0.9f);  // it reaches within 10% of the frame's border
  // The sphere-fitted framing is farther: the same object covers much less of the frame.
  const Camera sphere = frameBounds(scene.bounds(), 0.9f);
  EXPECT_GT(glm::length(sphere.eye - sphere.target), 1.3f * glm::length(framing.camera.eye - framing.camera.target));
}

TEST(SceneTest, DefaultFramingOfAClosedRoomIsFromInside) {
  const Scene scene = roomScene({0, 0, 0}, {10, 3, 6}, false);
  const Framing framing = frameScene(scene, glm::radians(60.0f), 16.0f / 9.0f);
  EXPECT_TRUE(framing.interior);
  EXPECT_EQ(framing.enclosedDirections, 26);
  const Bounds b = scene.bounds();
  for (int a = 0; a < 3; ++a) {
    EXPECT_GT(framing.camera.eye[a], b.lo[a]);
    EXPECT_LT(framing.camera.eye[a], b.hi[a]);
  }
  const glm::vec3 d = glm::normalize(framing.camera.target - framing.camera.eye);
  EXPECT_FLOAT_EQ(d.y, 0.0f);
  EXPECT_GT(std::fabs(d.x), 0.7f);  // along the room's long side
}

TEST(SceneTest, DefaultFramingOfAClosedObjectIsFromOutside) {
  // The same closed box with its faces turned out (a crate, a helmet's shell): rays from its
  // centre meet it in every direction, but only its backs, so it is an object, not a room.
  Scene crate = roomScene({0, 0, 0}, {10, 3, 6}, false);
  for (Mesh& mesh : crate.meshes) {
    std::swap(mesh.indices[1], mesh.indices[2]);
    computeVertexNormals(mesh);
  }
  const Framing framing = frameScene(crate, glm::radians(60.0f), 16.0f / 9.0f);
  EXPECT_EQ(framing.enclosedDirections, 26);
  EXPECT_EQ(framing.facingDirections, 0);
  EXPECT_FALSE(framing.interior);
  const Bounds b = crate.bounds();
  bool outside = false;
  for (int a = 0; a < 3; ++a) outside |= framing.camera.eye[a] < b.lo[a] || framing.camera.eye[a] > b.hi[a];
  EXPECT_TRUE(outside) << "the eye is outside the crate";
  // Faces turned in, the room's framing: every direction meets a wall that faces the centre.
  const Framing room = frameScene(roomScene({0, 0, 0}, {10, 3, 6}, false), glm::radians(60.0f), 16.0f / 9.0f);
  EXPECT_EQ(room.facingDirections, 26);
  EXPECT_TRUE(room.interior);
}

TEST(SceneTest, DefaultFramingOfAnOpenBoxLooksInThroughTheOpening) {
  const Scene scene = roomScene({-1, 0, -1}, {1, 2, 1}, true);
  const Framing framing = frameScene(scene, glm::radians(60.0f), 16.0f / 9.0f);
  EXPECT_FALSE(framing.interior);  // "inside" would mean the eye is inside the bounds
  EXPECT_TRUE(framing.openSide);
  EXPECT_GT(framing.camera.eye.z, 1.0f);  // outside, before the open +z side
  EXPECT_LT(std::fabs(framing.camera.eye.x), 1e-4f);
}

}  // namespace
}  // namespace mrr
