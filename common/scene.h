#pragma once
// The scene model: only what the effects need (brief: "model no more than a scene needs").
// Triangles with per-vertex normals, a base colour per mesh (its factor, times its base-colour
// texture where it has one), alpha cutouts (which are visibility), one directional light, and
// cameras. Everything is in world space once loaded;
// node transforms are baked in.
#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "common/camera.h"

namespace mrr {

// How a texture coordinate outside [0, 1) finds its texel (glTF sampler wrapS / wrapT).
enum class Wrap { Repeat, Clamp, Mirror };

// An alpha cutout (glTF alphaMode MASK): visibility, not colour. Which texels of the base-colour
// texture are opaque, alpha = the factor's alpha × the texel's alpha ≥ alphaCutoff, decided once
// on the host so both paths read the same bits. Sampled nearest (docs/spec.md §1.1).
struct Cutout {
  int width = 0, height = 0;
  std::vector<uint8_t> opaque;  // width × height, 1 = opaque; row 0 is the image's first row (v = 0)
  Wrap wrapS = Wrap::Repeat, wrapT = Wrap::Repeat;

  bool opaqueAt(float s, float t) const;  // the texel cutoutTexel addresses
};

// The texel index along one axis of n texels for texture coordinate t, nearest (docs/spec.md
// §1.1): i = floor(t·n), then wrapped. gpu/shaders/cutout.glsl is the same function.
int cutoutTexel(float t, int n, Wrap wrap);

// sRGB-encoded byte → linear float32 (the sRGB transfer function, evaluated once in double and
// rounded): the one table both paths read (the port uploads it as a texture).
const float* srgbToLinearTable();  // 256 entries

// A base-colour texture (glTF baseColorTexture, docs/spec.md §1.2): the image's RGB as stored
// (sRGB bytes), addressed like a cutout (cutoutTexel, nearest), decoded through
// srgbToLinearTable. Albedo = the material's factor × this, per channel, in float32.
struct ColorTexture {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width × height × 4 (alpha unused: 255); row 0 is the image's first row (v = 0)
  Wrap wrapS = Wrap::Repeat, wrapT = Wrap::Repeat;

  glm::vec3 linearAt(float s, float t) const;  // the texel cutoutTexel addresses, linear RGB
};

struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;  // world space
  std::vector<glm::vec3> normals;    // world space, unit length, one per position
  std::vector<uint32_t> indices;     // three per triangle, counter-clockwise seen from the front
  glm::vec3 baseColor{0.8f};         // linear RGB albedo in [0,1]
  int cutout = -1;                   // index into Scene::cutouts, or -1: opaque
  int texture = -1;                  // index into Scene::textures, or -1: the factor alone
  // One per position when cutout >= 0 or texture >= 0, else empty: the base-colour texture's
  // TEXCOORD_n with its KHR_texture_transform already applied (the cutout reads the same).
  std::vector<glm::vec2> texcoords;

  bool blend = false;  // glTF alphaMode BLEND (glass, light cones), drawn opaque: no say in the default framing

  glm::vec3 albedoAt(const std::vector<ColorTexture>& textures, glm::vec2 st) const;  // baseColor × texel
};

struct DirectionalLight {
  glm::vec3 direction{0.3f, -1.0f, -0.4f};  // the way the light travels (world), unit length
  glm::vec3 color{1.0f};                     // linear RGB radiance scale
};

struct Bounds {
  glm::vec3 lo{0.0f};
  glm::vec3 hi{0.0f};
  glm::vec3 center() const { return 0.5f * (lo + hi); }
  float diagonal() const { return glm::length(hi - lo); }
};

// What the file said beside the geometry, for `mrr info`; nothing renders from it.
struct SceneFacts {
  std::vector<std::string> extensionsRequired, extensionsUsed;
  int opaqueMaterials = 0, maskMaterials = 0, blendMaterials = 0;
};

// Where a scene's light came from, for `mrr info`: the file's or the built-in
// scene's own, --light-dir, or for a scene without one the candidate that lights the most of
// the default view's visible surface (scenes/default_light.h).
struct LightOrigin {
  std::string source = "built-in default";  // "the scene", "--light-dir", "built-in default", "chosen for the view"
  float litShare = -1.0f;         // the share of the view's visible surface it lights (-1: not measured)
  float builtinLitShare = -1.0f;  // the built-in default's share of the same view (-1: not measured)
  int candidate = -1;             // its index in defaultLightCandidates() (0: the built-in default), -1: none
};

struct Scene {
  std::string name;    // "builtin:plane", or the file's path
  std::string credit;  // attribution line to show wherever a rendering is published
  std::vector<Mesh> meshes;
  std::vector<Cutout> cutouts;  // shared by the meshes that use them
  std::vector<ColorTexture> textures;  // base-colour textures, shared by the meshes that use them
  DirectionalLight light;
  bool hasLight = false;        // false: `light` is the default
  LightOrigin lightOrigin;      // set by loadRequestedScene (scenes/catalog.cpp)
  std::vector<Camera> cameras;  // from the file or the built-in scene; may be empty
  SceneFacts facts;

  Bounds bounds() const;
  size_t triangleCount() const;
};

// Fills missing normals with area-weighted vertex normals (glTF 2.0 §3.7.2.1 says flat
// normals; smooth ones keep the normal-edge detector from firing inside every mesh).
void computeVertexNormals(Mesh& mesh);

// Checks what every later stage relies on: finite positions and normals, indices in
// range, at least one non-degenerate triangle. Throws MrrError naming `source`.
void validateScene(const Scene& scene, const std::string& source);

// A camera that frames the bounds: looks at the centre from the front-above diagonal, far
// enough that the bounds' sphere fits the vertical field of view.
Camera frameBounds(const Bounds& bounds, float yfovRadians);

// The default view of a scene that brings no camera. Only opaque and MASK
// surfaces decide it: BLEND ones (glass, light cones) close a room (a window is a wall) but
// are never its walls, never a view's end, and do not count in the bounds it frames.
// - an interior (the bounds' centre is enclosed: rays from it meet geometry in at least 24 of
//   26 directions, and the surfaces met face it) is seen from inside: the eye is inside the
//   bounds, at the place with the most room, looking along the level direction with the
//   farthest opaque surface;
// - an enclosure with one level side open (a Cornell box: most of a fan of rays through that
//   side escapes, not just the one through a window or a door) is seen from outside, looking in
//   through the opening: not "inside";
// - anything else from the front-above diagonal, as frameBounds, but at the distance where its
//   vertices just fit an image of this aspect (W/H) with a 5% margin, so it fills the frame.
struct Framing {
  Camera camera;
  bool interior = false;   // the eye is inside the bounds, in the room
  bool openSide = false;   // an enclosure seen through its open side, from outside
  int enclosedDirections = 0;  // of 26: the rays from the bounds' centre that meet a surface
  int facingDirections = 0;    // of those, the ones along which a surface faces the centre (a room's walls)
};
Framing frameScene(const Scene& scene, float yfovRadians, float aspect);

// Rotates the scene 180° about the X axis: for files authored with Y down (the arcade).
// A rotation, not a mirror, so winding and handedness are kept.
void flipUp(Scene& scene);

}  // namespace mrr
