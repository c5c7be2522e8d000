#include "common/shader_contract.h"

#include <cstdio>

// The table leaves `location` and `variant` out where they do not apply.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

#include "common/shader_constants.h"
#include "common/stages.h"
#include "common/tolerance.h"

namespace mrr {

namespace {
// Textures of the level G-buffer (gbuffer.frag's targets), as most stages read them.
constexpr ShaderVariable kPositionHit = {"positionHit", "sampler2D RGBA32F",
                                         "the level's G-buffer: view-space position (xyz), hit in w (1 geometry, 0 sky)"};
constexpr ShaderVariable kNormalDepth = {"normalDepth", "sampler2D RGBA32F",
                                         "the level's G-buffer: view-space unit normal (xyz), linear depth z = -p.z in w "
                                         "(0 on sky)"};
constexpr ShaderVariable kKernel = {"kernel", "sampler2D RGB32F, N x 1",
                                    "the host's hemisphere kernel in the tangent frame (common/kernels.h), one texel a sample"};
constexpr ShaderVariable kSamples = {"samples", "int", "N, the samples per pixel (--samples)"};
constexpr ShaderVariable kLevel = {"level", "int", "l, the level (0 = full res); seeds the per-pixel hash"};
constexpr ShaderVariable kSeed = {"seed", "uint",
                                  "the sampling seed (--seed; 0 = mrr's own): the rotation hashes (x, y, level + 4 seed); optional: a "
                                  "shader with its own noise may leave it out"};
constexpr ShaderVariable kInvScale = {"invScale", "float", "1 / s_l, s_l = 2^l the level's scale"};
constexpr ShaderVariable kCamera = {"camera", "vec3",
                                    "(focal length, cx, cy) of the full-res image, in full-res pixels"};
constexpr ShaderVariable kStencilMask = {"stencilMask", "sampler2D R8", "S_l, 1 where the level is shaded"};
}  // namespace

const std::vector<ShaderContract>& shaderContracts() {
  static const std::vector<ShaderContract> table = {
      {"albedo.glsl", "include", "gbuffer", "",
       {{"baseColor", "sampler2D RGBA8", "the mesh's base-colour texture: its sRGB bytes as stored (Scene::textures)"},
        {"srgbToLinear", "sampler2D R32F, 256 x 1", "the host's sRGB byte -> linear table (srgbToLinearTable)"}},
       {{"hasTexture", "int", "1: the mesh has a base-colour texture, 0: the factor alone"},
        {"textureWrap", "ivec2", "wrapS, wrapT: 0 repeat, 1 clamp, 2 mirror"}},
       {},
       "common/scene.cpp ColorTexture::linearAt and Mesh::albedoAt (docs/spec.md 1.2): the texel floor(t n), wrapped "
       "as a cutout's, its bytes through the sRGB table, times the factor."},
      {"bilateral.frag", "fragment", "bilateral", "",
       {{"image", "sampler2D R32F", "the raw sub-image c_raw of the level (channel r)"},
        kStencilMask, kPositionHit, kNormalDepth},
       {{"radius", "int", "r, the blur's half width in level pixels (at most 8)"},
        {"spatial", "float[289]", "(2r+1)^2 spatial Gaussian weights, row-major (Constants::Bilateral)"},
        {"sigmaDepth", "float", "the depth similarity's width, relative to the receiver's depth"},
        {"normalPower", "float", "p of the normal similarity max(N.N', 0)^p"}},
       {{"result", "vec4 -> R32F", "c_l, the blurred sub-image in r", 0}},
       "cpu_ref/bilateral.cpp bilateralBlur: taps weighted by spatial Gaussian x depth similarity x normal similarity "
       "x S(q), normalised over the valid taps; SSAO only. Drawn with the stencil test."},
      {"bilateral.glsl", "include", "bilateral, peers.uniform", "", {}, {}, {},
       "cpu_ref/bilateral.cpp normalSimilarity: max(N_p.N_q, 0)^p by repeated squaring when p is whole."},
      {"blend.frag", "fragment", "blend, blend.final.*, blend.reach.*",
       "FINAL_ONLY: one pass for every level (no per-level images); REACH: R(p) of mrr-effect's trim (docs/spec.md "
       "§12.5), from S and a alone; FINE_LEVELS: bit mask of the finer levels 0-2; COARSEST_LEVEL: C; COARSEST_SCALE: "
       "s_C; COARSEST_COVERED: S_C = 1 everywhere",
       {{"sub", "sampler2D R32F or RGBA32F", "c_l at level resolution (rgb; SSAO and SSM in r)", -1, "default"},
        {"stencilMask", "sampler2D R8", "S_l", -1, "default"},
        {"alphaMask", "sampler2D R32F", "a_l, the blurred mask", -1, "default"},
        {"coarser", "sampler2D R32F or RGBA32F", "c' of the next coarser enabled level, full res (unused at the coarsest)",
         -1, "default"},
        {"coarserLevel", "sampler2D R8", "its level map, l/255 (unused at the coarsest)", -1, "default"},
        {"subC", "sampler2D", "c_C of the coarsest enabled level C", -1, "FINAL_ONLY"},
        {"stencilC", "sampler2D R8", "S_C", -1, "FINAL_ONLY"},
        {"sub0", "sampler2D", "c_0", -1, "FINAL_ONLY"},
        {"sub1", "sampler2D", "c_1", -1, "FINAL_ONLY"},
        {"sub2", "sampler2D", "c_2", -1, "FINAL_ONLY"},
        {"stencil0", "sampler2D R8", "S_0", -1, "FINAL_ONLY or REACH"},
        {"stencil1", "sampler2D R8", "S_1", -1, "FINAL_ONLY or REACH"},
        {"stencil2", "sampler2D R8", "S_2", -1, "FINAL_ONLY or REACH"},
        {"alpha0", "sampler2D R32F", "a_0", -1, "FINAL_ONLY or REACH"},
        {"alpha1", "sampler2D R32F", "a_1", -1, "FINAL_ONLY or REACH"},
        {"alpha2", "sampler2D R32F", "a_2", -1, "FINAL_ONLY or REACH"}},
       {{"coarsest", "bool", "this level is the coarsest enabled one (alpha = 1 where covered)", -1, "default"},
        {"level", "int", "l", -1, "default"},
        {"scale", "int", "s_l = 2^l, full-res pixels per level pixel", -1, "default"},
        {"weight", "float", "w_l, the blend weight of the level (dimensionless)", -1, "default"},
        {"weights", "float[3]", "w_l of the finer levels 0-2", -1, "FINAL_ONLY or REACH"},
        {"frame", "ivec2", "W x H, full-res pixels (R = 0 outside)", -1, "REACH"}},
       {{"cHat", "vec4 -> R32F or RGBA32F", "c^_l, masked-bilinear upsampling at full res", 0, "default"},
        {"alphaOut", "vec4 -> R32F", "alpha_l = min(a^_l w_l, 1) in r", 1, "default"},
        {"composite", "vec4 -> R32F or RGBA32F", "c'_l = alpha c^_l + (1 - alpha) c'_coarser", 2, "default"},
        {"levelMap", "vec4 -> R8", "the finest level so far with alpha > 0, l/255", 3, "default"},
        {"finalOut", "vec4 -> R32F or RGBA32F", "the final effect buffer", 0, "FINAL_ONLY"},
        {"levelMap", "vec4 -> R8", "the finest level with alpha > 0, l/255", 1, "FINAL_ONLY"},
        {"reachOut", "vec4 -> R8", "R(p): the finest enabled level with alpha = 1, else C, l/255", 0, "REACH"}},
       "cpu_ref/blend.cpp: upsampleAt (bilinear over the four level texels with S = 1, renormalised) and blendStep "
       "with the erratum-corrected Eq. 1, c'_l = alpha_l c^_l + (1 - alpha_l) c'_(l+1), coarse to fine."},
      {"blocks.frag", "fragment", "blocks.*",
       "STEP: 1 dilate, 2 pool, 3 maps, 4 pack (a row's blocks as bits, for blocks.geom); DX, DY: the box's half sides in blocks (step 1); UNITE: OR another map "
       "(step 1); FACTOR_X, FACTOR_Y: the pooled blocks' sides (step 2); OUTPUTS: the maps (step 3, 1-8); SPEC_k: "
       "map k's (ax, ay, bx, by), -1 no term (step 3); REACH_A, REACH_B: the largest a and b; FINE: read `fine`",
       {{"source", "sampler2D R8", "a block map (1: the block may hold work)"},
        {"also", "sampler2D R8", "step 1 with UNITE: a map of the output's grid, OR-ed in", -1, "STEP == 1 && UNITE"},
        {"fine", "sampler2D R8", "step 3 with FINE: the map of the grid twice as fine", -1, "STEP == 3 && FINE"}},
       {},
       {{"result", "vec4 -> R8", "the block map: dilated (step 1), pooled (step 2), map 0 (step 3) in r", 0, "STEP != 4"},
        {"packedBits", "uvec4 -> RGBA32UI", "step 4: bit k of component c of texel (i, y) = block (128 i + 32 c + k, y) set", 0,
         "STEP == 4"},
        {"map1", "vec4 -> R8", "step 3: map 1", 1, "OUTPUTS > 1"},
        {"map2", "vec4 -> R8", "step 3: map 2", 2, "OUTPUTS > 2"},
        {"map3", "vec4 -> R8", "step 3: map 3", 3, "OUTPUTS > 3"},
        {"map4", "vec4 -> R8", "step 3: map 4", 4, "OUTPUTS > 4"},
        {"map5", "vec4 -> R8", "step 3: map 5", 5, "OUTPUTS > 5"},
        {"map6", "vec4 -> R8", "step 3: map 6", 6, "OUTPUTS > 6"},
        {"map7", "vec4 -> R8", "step 3: map 7", 7, "OUTPUTS > 7"}},
       "common/frame.cpp nearBlocks (a box max of ceil(r / blockSize) blocks) and gpu/masks.cpp blocksOf (a block is "
       "set where any under it is): the GPU-resident frame's block maps, which say where a pass has work; step 3: "
       "map k = nearBlocks(source, ax, ay) OR blocksOf(nearBlocks(fine, bx, by), 2)."},
      {"blocks.geom", "geometry", "every pass drawn over a block map (*.blocks)", "",
       {},
       {{"blockBits", "usampler2D RGBA32UI", "the block map whose runs are drawn, packed by blocks.frag step 4 (texture unit 15)"},
        {"blockGrid", "ivec2", "the map's size in blocks"},
        {"blockValue", "int", "the runs of blocks equal to it: 1 set, 0 clear"},
        {"blockSize", "int", "target pixels per block side"},
        {"targetSize", "vec2", "the target's size in pixels"}},
       {},
       "gpu/masks.cpp blockRects: each row's runs of matching blocks (cut every 32 blocks), a run the row above "
       "holds too drawn from there down to its last row, as rectangles clipped to the target; from the point "
       "blocks.vert gives (its segment and row, the flat varying segmentRow)."},
      {"blocks.vert", "vertex", "every pass drawn over a block map (*.blocks)", "",
       {},
       {{"segments", "int", "segments of 128 blocks per row of the map"}},
       {},
       "none: one point per (segment, row) of the block map, gl_VertexID = row x segments + segment, for blocks.geom."},
      {"common.glsl", "include", "ssao, ssgi, hash", "", {}, {}, {},
       "common/hash.h pixelHash (PCG, 32-bit wrap-around) and rotationHash, cpu_ref/hemisphere.h sampleFrame (the "
       "kernel rotated about N by an angle from the hash of (x, y, level + 4 seed)) and common/frame.h nearestLevelTexel (the texel whose "
       "sample is nearest a projected point)."},
      {"counts.frag", "fragment", "counts.reduce.*, counts.gather.*",
       "STEP: 1 reduce, 2 gather; FACTOR: the tile side summed per fragment (step 1); TARGETS: the inputs and outputs "
       "(step 1, 1-8, of one size); SOURCES: the inputs, one per output texel (step 2, 1-8)",
       {},
       {{"values0", "usampler2D RGBA32UI", "step 1: counts per block (rule.frag) or partial sums", -1, "STEP == 1"},
        {"values1", "usampler2D RGBA32UI", "step 1: target 1's", -1, "TARGETS > 1"},
        {"values2", "usampler2D RGBA32UI", "step 1: target 2's", -1, "TARGETS > 2"},
        {"values3", "usampler2D RGBA32UI", "step 1: target 3's", -1, "TARGETS > 3"},
        {"values4", "usampler2D RGBA32UI", "step 1: target 4's", -1, "TARGETS > 4"},
        {"values5", "usampler2D RGBA32UI", "step 1: target 5's", -1, "TARGETS > 5"},
        {"values6", "usampler2D RGBA32UI", "step 1: target 6's", -1, "TARGETS > 6"},
        {"values7", "usampler2D RGBA32UI", "step 1: target 7's", -1, "TARGETS > 7"},
        {"source0", "usampler2D RGBA32UI", "step 2: partial sums, at most 16 x 16 texels", -1, "STEP == 2"},
        {"source1", "usampler2D RGBA32UI", "step 2: input 1", -1, "SOURCES > 1"},
        {"source2", "usampler2D RGBA32UI", "step 2: input 2", -1, "SOURCES > 2"},
        {"source3", "usampler2D RGBA32UI", "step 2: input 3", -1, "SOURCES > 3"},
        {"source4", "usampler2D RGBA32UI", "step 2: input 4", -1, "SOURCES > 4"},
        {"source5", "usampler2D RGBA32UI", "step 2: input 5", -1, "SOURCES > 5"},
        {"source6", "usampler2D RGBA32UI", "step 2: input 6", -1, "SOURCES > 6"},
        {"source7", "usampler2D RGBA32UI", "step 2: input 7", -1, "SOURCES > 7"}},
       {{"sum0", "uvec4 -> RGBA32UI", "step 1: the sums of a FACTOR x FACTOR tile of values0", 0, "STEP == 1"},
        {"sum1", "uvec4 -> RGBA32UI", "step 1: of values1", 1, "TARGETS > 1"},
        {"sum2", "uvec4 -> RGBA32UI", "step 1: of values2", 2, "TARGETS > 2"},
        {"sum3", "uvec4 -> RGBA32UI", "step 1: of values3", 3, "TARGETS > 3"},
        {"sum4", "uvec4 -> RGBA32UI", "step 1: of values4", 4, "TARGETS > 4"},
        {"sum5", "uvec4 -> RGBA32UI", "step 1: of values5", 5, "TARGETS > 5"},
        {"sum6", "uvec4 -> RGBA32UI", "step 1: of values6", 6, "TARGETS > 6"},
        {"sum7", "uvec4 -> RGBA32UI", "step 1: of values7", 7, "TARGETS > 7"},
        {"sum", "uvec4 -> RGBA32UI", "step 2: texel k = the sum of all of source k", 0, "STEP == 2"}},
       "none: sums of the per-block counts of common/frame.cpp's rule counts (countHits, countEdgeSample, "
       "countForRule, countShadedPixels), so the host reads a few integers."},
      {"cutout.glsl", "include", "gbuffer, shadowmap", "",
       {{"cutout", "sampler2D R8", "the mesh's alpha cutout: 1 where the texel is opaque (Scene::cutouts)"}},
       {{"hasCutout", "int", "1: the mesh has a cutout, 0: opaque"},
        {"cutoutWrap", "ivec2", "wrapS, wrapT: 0 repeat, 1 clamp, 2 mirror"}},
       {},
       "common/scene.cpp cutoutTexel and Cutout::opaqueAt (docs/spec.md 1.1): the texel floor(t n), wrapped; the "
       "oracle refuses hits on transparent texels in an Embree filter function."},
      {"edge_test.glsl", "include", "edges, edgesample, rule.* (a pixel's hit, depth > 0; step 1 WITH_SAMPLE: the edge sample)", "",
       {{"normalDepth", "sampler2D RGBA32F", "the level-0 G-buffer: view normal, depth (0 on sky: a pixel is on geometry where it is > 0)"},
        {"shadowLit", "sampler2D R8", "the one-tap shadow test per pixel, 1 lit", -1, "SHADOW_EDGES"}},
       {{"normalThreshold", "float", "the normal-edge threshold on 1 - N.N' (Settings::edges, common/params.h)"},
        {"depthThreshold", "float", "the depth-edge threshold on |second difference of 1/z| / (1/z) (Settings::edges)"}},
       {},
       "cpu_ref/edges.cpp edgeAt: normal edges (1 - N.N' > the normal threshold over the 4-neighbourhood), depth edges "
       "(second difference of 1/z), background edges (hit next to sky) and SSM's shadow edges at one pixel (edgeAt), "
       "from its texel and its 4-neighbours'; anyKind: E."},
      {"edges.frag", "fragment", "edges, edges.shadow, edges.E, edgesample, edgesample.shadow",
       "SHADOW_EDGES: the shadow kind too (SSM); E_ONLY: E alone in r of an R8 target; EDGE_SAMPLE: the never-slower "
       "rule's edge sample: E at each 8x8 block's diagonal pixels, a block's eight side by side on a (W/8)*8 x H/8 "
       "target, ORed per block by the host (cpu_ref/edges.cpp edgeSample)",
       {},
       {},
       {{"edges", "vec4 -> RGBA8 (E_ONLY, EDGE_SAMPLE: R8)", "(normal, depth, background, E), 0 or 1 each; EDGE_SAMPLE: (E at a diagonal pixel, 0, 0, 1)", 0},
        {"shadowEdge", "vec4 -> RGBA8", "(shadow edge, 0, 0, 1)", 1, "SHADOW_EDGES without EDGE_SAMPLE"}},
       "cpu_ref/edges.cpp detectEdges: the edge test of edge_test.glsl (its inputs and uniforms) at every pixel, or "
       "at the edge sample's; E is the OR of the kinds."},
      {"fullscreen.vert", "vertex", "every image-space pass", "",
       {{"corner", "vec2", "useRects: a rectangle corner in target pixels", 0}},
       {{"useRects", "bool", "draw the given pixel rectangles instead of one full-screen triangle"},
        {"targetSize", "vec2", "the target's size in pixels"}},
       {}, "none: the passes run one fragment per target pixel at gl_FragCoord = pixel centre (x + 0.5, y + 0.5)."},
      {"gbuffer.frag", "fragment", "gbuffer, gbuffer.subsample",
       "SUBSAMPLE: level l >= 1, copied from level 0 (drawn with fullscreen.vert)",
       {{"viewPosition", "in vec3", "view-space position of the fragment (gbuffer.vert)", -1, "default"},
        {"viewNormal", "in vec3", "view-space vertex normal, interpolated (gbuffer.vert)", -1, "default"},
        {"surfaceTexcoord", "in vec2",
         "texture coordinate for the alpha cutout and the base-colour texture (gbuffer.vert; includes cutout.glsl, "
         "albedo.glsl)", -1, "default"},
        {"fullPositionHit", "sampler2D RGBA32F", "level 0's G-buffer: position, hit", -1, "SUBSAMPLE"},
        {"fullNormalDepth", "sampler2D RGBA32F", "level 0's G-buffer: normal, depth", -1, "SUBSAMPLE"},
        {"fullAlbedo", "sampler2D RGBA32F", "level 0's G-buffer: albedo", -1, "SUBSAMPLE"}},
       {{"albedo", "vec3", "the mesh's base-colour factor, linear RGB (times its texture: albedo.glsl)", -1, "default"},
        {"farDepth", "float", "the linear depth written as 1 to gl_FragDepth: surfaces are ordered by linear depth", -1,
         "default"},
        {"scale", "int", "s_l = 2^l: level pixel x copies full-res pixel x s + s/2", -1, "SUBSAMPLE"}},
       {{"outPositionHit", "vec4 -> RGBA32F", "view-space position, hit = 1 (0 on sky)", 0},
        {"outNormalDepth", "vec4 -> RGBA32F", "unit view normal facing the camera, linear depth z = -p.z", 1},
        {"outAlbedo", "vec4 -> RGBA32F", "base colour, 1", 2}},
       "cpu_ref/gbuffer.cpp: renderGBuffer, one ray per pixel centre (x + 0.5, y + 0.5) of the padded full-res grid "
       "(Embree); subsampleGBuffer, level l's pixel (x, y) a copy of full-res pixel (x s + s/2, y s + s/2)."},
      {"gbuffer.vert", "vertex", "gbuffer", "",
       {{"worldPosition", "vec3", "vertex position, world space", 0},
        {"worldNormal", "vec3", "vertex normal, world space", 1},
        {"texcoord", "vec2", "texture coordinate of a mesh with an alpha cutout or a base-colour texture (else (0, 0))",
         2}},
       {{"worldToView", "mat4", "the camera's world-to-view matrix"},
        {"projection", "vec4", "(2f/Wp, 2cx/Wp - 1, -2f/Hp, 2cy/Hp - 1): view point to clip x, y at full res"},
        {"depthMapping", "vec2", "(A, B): z_clip = A z + B, standard perspective depth for near/far"}},
       {{"viewPosition", "out vec3", "view-space position"}, {"viewNormal", "out vec3", "view-space normal"},
        {"surfaceTexcoord", "out vec2", "the texture coordinate, for the cutout and the base-colour texture"}},
       "common/camera.h: the pinhole View (px = cx + f x/(-z), py = cy - f y/(-z)); GL row 0 is image row 0."},
      {"hash.frag", "test", "hash (tests only)", "", {}, {kLevel},
       {{"halves", "vec4 -> RGBA32F", "pixelHash(x, y, level) as two exact 16-bit halves", 0}},
       "common/hash.h pixelHash, bit for bit."},
      {"limit.frag", "fragment", "limit", "",
       {kPositionHit},
       {{"gaze", "int", "1: --gaze given (steps 1-2)"},
        {"foveate", "int", "1: the eye limits (--foveate on); 0: the eccentricity is only measured"},
        {"motion", "int", "1: --prev-frame or --pan given (steps 3-4)"},
        {"gazePixel", "ivec2", "the gaze, a full-res pixel"},
        {"ppd", "float", "pixels per degree of visual angle (--ppd)"},
        {"radius2", "int[4]", "R_l: level l is allowed by the eye where d^2 >= R_l (whole full-res pixels squared)"},
        {"speed2", "float[4]", "level l is allowed by motion where |v|^2 >= speed2[l] (full-res pixels squared)"},
        {"motionCap", "int", "the coarsest level motion alone may ask for"},
        {"coarsest", "int", "C, the coarsest enabled level: the limit is at most C"},
        {"motionScale", "float", "multiplies the measured motion (1: as measured)"},
        {"viewEye", "vec3", "this frame's camera: eye, world space"},
        {"viewRight", "vec3", "this frame's camera: right axis"},
        {"viewUp", "vec3", "this frame's camera: up axis"},
        {"viewForward", "vec3", "this frame's camera: forward axis"},
        {"prevEye", "vec3", "the previous frame's camera: eye (--pan: this eye - pan * viewRight, made on the host)"},
        {"prevRight", "vec3", "the previous frame's camera: right axis"},
        {"prevUp", "vec3", "the previous frame's camera: up axis"},
        {"prevForward", "vec3", "the previous frame's camera: forward axis"},
        {"prevFocal", "float", "the previous View's focal length, pixels"},
        {"prevCx", "float", "the previous View's principal point x, pixels"},
        {"prevCy", "float", "the previous View's principal point y, pixels"}},
       {{"result", "vec4 -> RGBA32F", "eccentricity (degrees), |v| (pixels), fovea + 4 motion, l_min", 0}},
       "cpu_ref/foveation.cpp levelLimit (SPEC 13 steps 1-5): the eccentricity d/ppd and the eye's level (Guenter et "
       "al. 2012), the motion from the previous camera and its level, the limit min(C, max(both))."},
      {"masks.frag", "fragment", "masks.*",
       "STEP: 1 max-pool, 2 blur, 4 closure, 5 the level limit (M'_l); FACTOR: pool block side (step 5: s_l); RADIUS: "
       "blur half width; DIRECTION: ivec2 of the blur pass; SOURCE_CHANNEL: the source's channel; WITH_STENCIL: also "
       "write S_l (vertical blur); LEVEL: l (step 5)",
       {{"source", "sampler2D R8 or R32F", "the pass's input: E, M_(l-1), the horizontal blur, or S_l"},
        {"previous", "sampler2D R8", "step 4: the coarser level's own stencil"},
        {"limit", "sampler2D RGBA32F", "step 5: limit.frag's output, l_min in a (padded full res)", -1, "STEP == 5"}},
       {{"weights", "float[2 RADIUS + 1]", "the normalised Gaussian weights (common/kernels.h), step 2 only", -1,
         "STEP == 2"}},
       {{"result", "vec4 -> R8 or R32F", "M_l (step 1), a_l (step 2), S_next (step 4), M'_l (step 5) in r", 0},
        {"stencil", "vec4 -> R8", "S_l = [a_l > 0]", 1, "WITH_STENCIL"}},
       "cpu_ref/masks.cpp buildMasks: M_l max-pooled from E, a_l = G * M_l (separable, clamp to edge), S_l = [a_l > 0], "
       "then the coverage closure S_(l+1) |= max-pool(S_l)."},
      {"effect_masks.frag", "fragment", "effect_masks.*",
       "STEP: 1 the footprint F (full res), 2 each level's reach and the dilation along x, 3 the dilation along y, "
       "4 the effect-only arm's M'_l AND NOT M_l; EDGE_CHANNEL: E's channel (step 1); EFFECT_SSM: the one-tap "
       "penumbra bound as the reach (step 1); CAP: the widest reach, level pixels; MASK_CHANNEL: M_l's channel "
       "(steps 2, 4)",
       {{"positionHit", "sampler2D RGBA32F", "level 0's G-buffer: view position, hit", -1, "STEP == 1"},
        {"normalDepth", "sampler2D RGBA32F", "level 0's G-buffer: view normal, depth", -1, "STEP == 1"},
        {"edges", "sampler2D", "E in channel EDGE_CHANNEL", -1, "STEP == 1"},
        {"source", "sampler2D R8 or R32F", "step 2: M_l; step 3: H, the dilation along x; step 4: M'_l", -1,
         "STEP != 1"},
        {"footprint", "sampler2D R32F", "F_l, the max of F over each level pixel's block", -1, "STEP == 2"},
        {"geometry", "sampler2D", "M_l, the unwidened mask, in channel MASK_CHANNEL (level 0: E)", -1, "STEP == 4"}},
       {{"reach", "float", "R, world units (SSAO, SSGI)", -1, "STEP == 1"},
        {"tanHalfAngle", "float", "tan of half the light's angular diameter (SSM)", -1, "EFFECT_SSM"},
        {"focal", "float", "View::focal, full-res pixels", -1, "STEP == 1"},
        {"scale", "float", "the footprint's multiplier k", -1, "STEP == 1"},
        {"levelScale", "float", "s_l = 2^l", -1, "STEP == 2"}},
       {{"result", "vec4 -> R32F or R8", "F (step 1), H (step 2, -1: no reach), M'_l (step 3), M'_l AND NOT M_l "
         "(step 4) in r", 0}},
       "cpu_ref/effect_masks.cpp: effectFootprint, levelReach, dilateByReach (docs/spec.md §12): M'_l, the union of "
       "squares of side 2K + 1 around each q with M_l(q) = 1, K(q) = min(cap, floor(min(F_l(q) / s_l, cap + 1) + 1/2)); "
       "wideningOnly (§12.3, the ablation's effect-only arm): M'_l AND NOT M_l."},
      {"peers.frag", "fragment", "peers.tiles, peers.uniform, peers.broadcast, peers.levels",
       "TILE_MASKS: tiles' stage 3; COMPOSE: stage 5 of the peers (with JOINT_BILATERAL: uniform-k's joint bilateral "
       "upsampling, else tiles' broadcast); LEVEL_STAGES: c^_l, alpha_l, c'_l of the peers for --stages",
       {{"source", "sampler2D R8", "TILE_MASKS: E, the tiles' edge flags, or their rates", -1, "TILE_MASKS"},
        {"sub", "sampler2D", "c_k at level k", -1, "JOINT_BILATERAL"},
        {"coarsePositionHit", "sampler2D RGBA32F", "level k's G-buffer", -1, "JOINT_BILATERAL"},
        {"coarseNormalDepth", "sampler2D RGBA32F", "level k's G-buffer", -1, "JOINT_BILATERAL"},
        {"fullPositionHit", "sampler2D RGBA32F", "level 0's G-buffer, the guide", -1, "JOINT_BILATERAL"},
        {"fullNormalDepth", "sampler2D RGBA32F", "level 0's G-buffer, the guide", -1, "JOINT_BILATERAL"},
        {"rates", "sampler2D R8", "the tiles' rates on the tile grid", -1, "COMPOSE"},
        {"sub0", "sampler2D", "c_0", -1, "COMPOSE"},
        {"sub1", "sampler2D", "c_1", -1, "COMPOSE"},
        {"sub2", "sampler2D", "c_2", -1, "COMPOSE"},
        {"composed", "sampler2D", "COMPOSE's final value", -1, "LEVEL_STAGES"},
        {"levelMap", "sampler2D R8", "COMPOSE's level map", -1, "LEVEL_STAGES"},
        {"limit", "sampler2D RGBA32F", "step 4: limit.frag's output, l_min in a (padded full res)", -1, "TILE_MASKS"}},
       {{"step", "int", "TILE_MASKS: 1 tile edge flags, 2 rates, 3 per-level masks, 4 the level limit (SPEC §13)", -1,
         "TILE_MASKS"},
        {"sourceChannel", "int", "step 1: E's channel in the edge target", -1, "TILE_MASKS"},
        {"level", "int", "l (TILE_MASKS step 3), k (JOINT_BILATERAL), l (LEVEL_STAGES)"},
        {"perTile", "int", "step 3: level-l pixels per tile side, 16 / s_l", -1, "TILE_MASKS"},
        {"extent", "ivec2", "step 3: the level-l pixels whose block starts inside W x H", -1, "TILE_MASKS"},
        {"scale", "int", "s_k", -1, "JOINT_BILATERAL"},
        {"sigmaDepth", "float", "as the bilateral blur", -1, "JOINT_BILATERAL"},
        {"normalPower", "float", "as the bilateral blur", -1, "JOINT_BILATERAL"}},
       {{"result", "vec4 -> R32F or R8", "TILE_MASKS: flags, rates (steps 1, 2, 4), or S_l per level (step 3; M_l "
         "= the rate in g, a_l = S_l in b) in r", 0, "TILE_MASKS"},
        {"finalOut", "vec4 -> R32F or RGBA32F", "the final value (rgb)", 0, "COMPOSE"},
        {"levelOut", "vec4 -> R8", "the level it came from", 1, "COMPOSE"},
        {"cHat", "vec4", "c^_l", 0, "LEVEL_STAGES"},
        {"alphaOut", "vec4", "alpha_l", 1, "LEVEL_STAGES"},
        {"composite", "vec4", "c'_l", 2, "LEVEL_STAGES"}},
       "cpu_ref/peers.cpp: tileRates and tileMasks (16x16 tiles at rate 0, 1 or 2), common/frame.cpp limitTileRates "
       "(step 4), composePeer (uniform-k's joint "
       "bilateral upsampling, tiles' broadcast)."},
      {"refine_masks.frag", "fragment", "refine_masks.*",
       "STEP: 1 M_l |= marks, 3 S_l |= [a_l > 0] (step 2, the blur, is masks.frag STEP 2); SOURCE_CHANNEL: M_l's "
       "channel (step 1); WITH_READ (step 3): a level mrr-effect's trim cut, then S_l &= D_l",
       {{"source", "sampler2D R8", "step 1: M_l as its blur read it; step 3: S_l before the refinement"},
        {"marks", "sampler2D R8", "the limited a-posteriori marks at level l", -1, "STEP == 1"},
        {"alpha", "sampler2D R32F", "the refined a_l", -1, "STEP != 1"},
        {"read", "sampler2D R8", "D_l, the level pixels the blend reads (trim.frag)", -1, "WITH_READ"}},
       {},
       {{"result", "vec4 -> R8", "M_l | marks (step 1), S_l | [a_l > 0] (step 3) in r", 0}},
       "cpu_ref/effect_masks.cpp refineMasks (docs/spec.md §12.2 step 2): M_l |= marks; a_l = G * M_l again; S_l |= "
       "[a_l > 0], keeping what the closure gave S_l."},
      {"refinement_budget.frag", "fragment", "refinement_budget.*",
       "STEP: 2 each level-l pixel's price summed down its candidates' windows (level l's width, level n's height), "
       "3 the prices along the windows and the candidates' keys (level n), 4 the level's state (1x1), 5 the totals "
       "at kBudgetRadix thresholds per block of FACTOR^2 candidates, 6 those summed, 7 the threshold (1x1), 8 the "
       "marks (level n), 9 the report's counts (level n, after the clock); RATIO: 2^(n-l) (steps 2-3); PCF_SAMPLE "
       "(step 2): SSM's sample prices PCF; HYSTERESIS (step 3): the previous frame's marks; CHAINED (step 4): "
       "left from the refined level before; FACTOR (steps 5-6)",
       {{"stencil", "sampler2D R8", "the a-priori S_l", -1, "STEP == 2"},
        {"positionHit", "sampler2D RGBA32F", "level 0's G-buffer: hit in w", -1, "STEP == 2"},
        {"pcfSample", "sampler2D R8", "SSM: what PCSS pays per 8x8 block", -1, "STEP == 2 && PCF_SAMPLE"},
        {"range", "sampler2D R32F", "v(q), -1 off S_n (refinement_marks.frag RANGE_OUT)", -1, "STEP == 3"},
        {"previous", "sampler2D R8", "the previous frame's selection at this level", -1, "STEP == 3 && HYSTERESIS"}},
       {{"columns", "usampler2D RGBA32UI", "step 2's sums", -1, "STEP == 3"},
        {"before", "usampler2D RGBA32UI", "the refined level before: its final state", -1, "STEP == 4 && CHAINED"},
        {"state", "usampler2D RGBA32UI", "(T, left, S(T), share)", -1, "STEP >= 5"},
        {"candidates", "usampler2D RGBA32UI", "step 3's (price, key, marked before, 0)", -1, "STEP == 5 || STEP >= 8"},
        {"values0", "usampler2D RGBA32UI", "the totals at thresholds 0-3", -1, "STEP == 6 || STEP == 7"},
        {"values1", "usampler2D RGBA32UI", "the totals at thresholds 4-7", -1, "STEP == 6 || STEP == 7"},
        {"values2", "usampler2D RGBA32UI", "the totals at thresholds 8-11", -1, "STEP == 6 || STEP == 7"},
        {"values3", "usampler2D RGBA32UI", "the totals at thresholds 12-15", -1, "STEP == 6 || STEP == 7"},
        {"prices", "uvec3", "the class prices in units: paying, paying PCF, leaving", -1, "STEP == 2"},
        {"levelScale", "int", "s_l", -1, "STEP == 2"},
        {"radius", "int", "r_l, the level's blur radius", -1, "STEP == 2 || STEP == 3"},
        {"tau", "float", "tau_v", -1, "STEP == 3"},
        {"keepTau", "float", "(1 - h) tau_v", -1, "STEP == 3 && HYSTERESIS"},
        {"bonus", "uint", "the hysteresis' keys", -1, "STEP == 3 && HYSTERESIS"},
        {"levelsLeft", "int", "the refined levels from this one down", -1, "STEP == 4"},
        {"stride", "int", "the keys between two thresholds this round: 256, 16, 1", -1, "STEP == 5 || STEP == 7"},
        {"budget", "uint", "the frame's budget in units", -1, "STEP == 4 && !CHAINED"}},
       {{"result", "uvec4 -> RGBA32UI or vec4 -> R8",
         "the window's column sums (2), (price, key, before, 0) (3), the state (4, 7), the marks in r (8), "
         "(candidate, marked, kept, 0) (9)",
         0},
        {"sums0", "uvec4 -> RGBA32UI", "steps 5-6: the totals at thresholds 0-3", 0, "STEP == 5 || STEP == 6"},
        {"sums1", "uvec4 -> RGBA32UI", "steps 5-6: the totals at thresholds 4-7", 1, "STEP == 5 || STEP == 6"},
        {"sums2", "uvec4 -> RGBA32UI", "steps 5-6: the totals at thresholds 8-11", 2, "STEP == 5 || STEP == 6"},
        {"sums3", "uvec4 -> RGBA32UI", "steps 5-6: the totals at thresholds 12-15", 3, "STEP == 5 || STEP == 6"}},
       "common/effect_budget.cpp (docs/spec.md §12.4): candidatePrices (step 2), priorityKey (step 3), levelShare "
       "(step 4), selectRefinement (step 4a-c: the least key T whose total S(T) fits the share; the port finds it "
       "kBudgetRadix keys a pass, the host over a histogram: the same T). Whole numbers, sums held at 2^32 - 1: "
       "exact."},
      {"refinement_marks.frag", "fragment", "refinement_marks.*",
       "STEP: 1 the range test at the coarser level n, 2 each finer pixel takes its parent's mark; PASS (step 1): 1 "
       "along x, 2 along y (the separable form the pipeline draws), 0 the whole 3x3 at once (the readable form); "
       "CHANNELS: c_n's channels (step 1); RANGE_OUT (step 1): 1 writes v itself (R32F) for docs/spec.md §12.4's "
       "budget, 0 the mark; RATIO: 2^(n-l) (step 2)",
       {{"source", "sampler2D R32F, RGBA32F or R8",
         "step 1: c_n, the coarser level's result (pass 2: pass 1's minima); step 2: step 1's marks"},
        {"stencil", "sampler2D R8", "S_n", -1, "STEP == 1"},
        {"positionHit", "sampler2D RGBA32F", "level n's G-buffer: view position, hit", -1, "STEP == 1"},
        {"maxima", "sampler2D RGBA32F", "pass 1's maxima", -1, "STEP == 1 && PASS == 2"}},
       {{"tau", "float", "tau_v, the a-posteriori threshold", -1, "STEP == 1"}},
       {{"result", "vec4 -> R8, R32F or RGBA32F",
         "[v(q) > tau_v] or v (step 1; pass 1: each channel's minimum over the row of three), the mark at level l "
         "(step 2) in r",
         0},
        {"highest", "vec4 -> RGBA32F", "pass 1: each channel's maximum over the row of three", 1, "STEP == 1 && PASS == 1"}},
       "cpu_ref/effect_masks.cpp refinementMarks (docs/spec.md §12.2 step 1): v(q) = max - min of c_n over q's 3x3 "
       "neighbourhood of shaded hit pixels, the largest over the channels (localRangesSeparable, equal to localRange); "
       "a level-l pixel p is marked where v(floor(p / 2^(n-l))) > tau_v, or where §12.4's budget selected its parent. "
       "SPEC §13's limit is then masks.frag STEP 5."},
      {"rule.frag", "fragment", "rule.*",
       "STEP: 1 hits, 2 reach, 3 stencils, 4 shaded; WITH_PCF: SSM's PCF sample is read; WITH_SAMPLE: step 1 tests "
       "the edge sample's diagonal pixels (edge_test.glsl, with SHADOW_EDGES for SSM); WITH_HIT_BITS: step 3 reads "
       "the hits from step 1's bits; LEVEL: l (step 4)",
       {{"pcfSample", "sampler2D R8", "SSM: what PCSS pays per 8 x 8 block, the byte / 255", -1, "WITH_PCF"},
        {"stencil0", "sampler2D R8", "step 3: S_0", -1, "STEP == 3"},
        {"stencil1", "sampler2D R8", "step 3: S_1", -1, "STEP == 3"},
        {"stencil2", "sampler2D R8", "step 3: S_2", -1, "STEP == 3"},
        {"stencil3", "sampler2D R8", "step 3: S_3", -1, "STEP == 3"},
        {"stencil", "sampler2D R8", "step 4: S_l of level LEVEL", -1, "STEP == 4"}},
       {{"frame", "ivec2", "W x H (step 1)", -1, "STEP == 1"},
        {"hits", "usampler2D RGBA32UI", "step 2: step 1's counts2 (hit pixels, E^) per block", -1, "STEP == 2"},
        {"reachBlocks", "ivec3", "step 2: per level l < 3, the box R_l spans in blocks; -1: not counted", -1, "STEP == 2"},
        {"counted", "ivec4", "step 3: 1 where level l is enabled and shaded", -1, "STEP == 3"},
        {"hitBits", "usampler2D RGBA32UI", "step 3: step 1's counts2, each block's 64 hit bits in z, w", -1,
         "STEP == 3 && WITH_HIT_BITS"}},
       {{"counts0", "uvec4 -> RGBA32UI", "step 1: H, H_a, H_p, F; step 2: E^, R_0, R_1, R_2 (0/1); step 3: level 0's "
         "|S|, |S & hit|, |S & hit & searched|, |S & hit & pcf|; step 4: |S_l|, any (0/1), |S_l & hit| per 4 x 2 block",
         0},
        {"counts1", "uvec4 -> RGBA32UI", "step 1: B_0..B_3; step 2: R_0..R_2's hit pixels; step 3: level 1's", 1,
         "STEP != 4"},
        {"counts2", "uvec4 -> RGBA32UI",
         "step 1: the block's hit pixels (padded), E^ (0/1), its hit bits (rows 0-3, 4-7); step 3: level 2's", 2,
         "STEP == 1 || STEP == 3"},
        {"counts3", "uvec4 -> RGBA32UI", "step 3: level 3's", 3, "STEP == 3"}},
       "common/frame.cpp countHits, countEdgeSample, countForRule, countShadedPixels and countHitPixels, count for "
       "count, per 8 x 8 block (step 4: per 4 x 2 block of level l); docs/spec.md §11."},
      {"shade.frag", "fragment", "shade.0, shade.1, shade.2", "EFFECT: 0 SSAO, 1 SSM, 2 SSGI",
       {{"positionHit", "sampler2D RGBA32F", "the level-0 G-buffer: view position, hit"},
        {"normalDepth", "sampler2D RGBA32F", "the level-0 G-buffer: view normal, depth"},
        {"albedo", "sampler2D RGBA32F", "the level-0 G-buffer: base colour"},
        {"effect", "sampler2D R32F or RGBA32F", "the final effect buffer, W x H (AO, V or indirect RGB)"},
        {"shadowLit", "sampler2D R8", "SSGI: the one-tap shadow test, 1 lit"}},
       {{"toLight", "vec3", "unit, view space: toward the light"},
        {"lightColor", "vec3", "the light's colour, linear RGB"}},
       {{"shaded", "vec4 -> RGBA32F", "the shaded linear RGB for viewing", 0}},
       "cpu_ref/shade.cpp shadeFinal: albedo x (ambient x AO, or N.L x V, or direct + indirect) x light colour; sky "
       "colour on background."},
      {"shadowmap.frag", "fragment", "shadowmap, shadowtest", "SHADOW_TEST: the one-tap test at every level-0 pixel",
       {{"lightDepth", "in float", "distance from the light plane (shadowmap.vert)", -1, "default"},
        {"surfaceTexcoord", "in vec2", "texture coordinate for the alpha cutout (includes cutout.glsl)", -1, "default"},
        {"positionHit", "sampler2D RGBA32F", "the level-0 G-buffer: view position, hit", -1, "SHADOW_TEST"},
        {"normalDepth", "sampler2D RGBA32F", "the level-0 G-buffer: view normal, depth", -1, "SHADOW_TEST"}},
       {},
       {{"depth", "vec4 -> R32F", "the distance from the light plane in r (world units)", 0, "default"},
        {"lit", "vec4 -> R8", "the one-tap test, 1 lit, 0 shadowed (sky: 1)", 0, "SHADOW_TEST"}},
       "cpu_ref/shadowmap.cpp renderShadowMap (one ray per texel centre from the light plane) and shadowTestImage."},
      {"shadowmap.glsl", "include", "shadowmap, shadowtest, ssm, direct, effect_masks (step 1)", "",
       {{"shadowMap", "sampler2D R32F, size^2", "distance from the light plane, world units; kNoBlocker on a miss"}},
       {{"mapSize", "int", "texels per side (--shadow-map-size)"},
        {"mapTexel", "float", "world units per texel"},
        {"mapOrigin", "vec3", "world position of texel (0, 0)'s corner on the light plane"},
        {"mapRight", "vec3", "the light plane's x axis, world, unit"},
        {"mapUp", "vec3", "the light plane's y axis, world, unit"},
        {"mapForward", "vec3", "the light's direction, world, unit"},
        {"biasTexels", "float", "receiver offset and depth bias, in texels (and each tap follows the receiver's plane)"},
        {"viewEye", "vec3", "the camera's position, world"},
        {"viewRight", "vec3", "the camera's right axis, world"},
        {"viewUp", "vec3", "the camera's up axis, world"},
        {"viewForward", "vec3", "the camera's forward axis, world"}},
       {}, "cpu_ref/shadowmap.h ShadowMap::lightCoordinates, depthAt, receiverAt, shadowTest."},
      {"shadowmap.vert", "vertex", "shadowmap", "",
       {{"worldPosition", "vec3", "vertex position, world space", 0},
        {"texcoord", "vec2", "texture coordinate of a mesh with an alpha cutout (else (0, 0))", 2}},
       {{"farDepth", "float", "ShadowMap::farDepth: orders surfaces for the depth test (world units)"}},
       {{"lightDepth", "out float", "distance from the light plane, world units"},
        {"surfaceTexcoord", "out vec2", "the texture coordinate, for the cutout"}},
       "cpu_ref/shadowmap.cpp renderShadowMap: orthographic onto the same texel grid."},
      {"ssao.frag", "fragment", "ssao", "",
       {kPositionHit, kNormalDepth, kKernel},
       {kSamples, kLevel, kInvScale, kCamera,
        {"radius", "float", "R, the SSAO radius in world (view) units (--ao-radius; default 15% of the framed size)"},
        {"bias", "float", "the depth bias, world units (--ao-bias times R)"},
        {"tangentPlaneDepth", "bool", "occluder depth from the texel's tangent plane (false: --ao-texel-depth)"},
        kSeed},
       {{"ao", "vec4 -> R32F", "the ambient occlusion AO in [0, 1] in r (1 = unoccluded)", 0}},
       "cpu_ref/ssao.cpp renderSsao: N hemisphere samples of radius R about the receiver, each projected to the "
       "level's G-buffer; occluded when the buffer is in front by more than the bias, weighted by the range check. "
       "Drawn with the stencil test."},
      {"ssgi.frag", "fragment", "direct, ssgi", "DIRECT_LIGHT: the light each level pixel sends (includes shadowmap.glsl; the default variant includes common.glsl)",
       {kPositionHit, kNormalDepth,
        {"albedo", "sampler2D RGBA32F", "the level's G-buffer: base colour", -1, "DIRECT_LIGHT"},
        {"direct", "sampler2D RGBA32F", "the level's direct light (the DIRECT_LIGHT variant), RGB", -1, "default"},
        {"kernel", "sampler2D RGB32F, N x 1", "the host's hemisphere kernel", -1, "default"}},
       {{"toLight", "vec3", "unit, view space: toward the light", -1, "DIRECT_LIGHT"},
        {"lightColor", "vec3", "the light's colour, linear RGB", -1, "DIRECT_LIGHT"},
        {"samples", "int", "N", -1, "default"},
        {"level", "int", "l", -1, "default"},
        {"invScale", "float", "1 / s_l", -1, "default"},
        {"camera", "vec3", "(focal, cx, cy) in full-res pixels", -1, "default"},
        {"radius", "float", "R, world units (--gi-radius)", -1, "default"},
        {"patchArea", "float", "A = pi R^2 / N, world units squared", -1, "default"},
        {"minDistance2", "float", "(R/4)^2: the sender distance is clamped to it, world units squared", -1, "default"},
        {"seed", "uint", "the sampling seed (--seed; 0 = mrr's own): rotationHash(x, y, level, seed); optional", -1,
         "default"}},
       {{"direct", "vec4 -> RGBA32F", "albedo x max(N.L, 0) x shadow x light colour", 0, "DIRECT_LIGHT"},
        {"indirect", "vec4 -> RGBA32F", "the indirect light, rgb", 0, "default"}},
       "cpu_ref/ssgi.cpp directLight and renderSsgi: N hemisphere samples, each projected pixel a sender patch of "
       "area pi R^2 / N. Drawn with the stencil test."},
      {"ssm.frag", "fragment", "ssm, pcfsample",
       "PCF_SAMPLE: the never-slower rule's sample (SPEC 11), on a ceil(W/8) x ceil(H/8) target over the level-0 "
       "G-buffer, fragment (x, y) asking pixel (8x + 4, 8y + 4) (includes shadowmap.glsl: the shadow map and its "
       "uniforms)",
       {kPositionHit, kNormalDepth},
       {{"tanHalfAngle", "float", "tan(theta/2) of the light's angular diameter theta (--light-angle, radians)"},
        {"blockerGrid", "int", "blocker-search taps per side"},
        {"grid", "int", "PCF taps per side n (N = n^2 = --samples)"},
        {"blockerFactors", "float[16]", "tap i of the blocker grid sits at factor_i h (cpu_ref/ssm.h gridTapFactor)"},
        {"pcfFactors", "float[32]", "tap i of the PCF grid sits at factor_i h"}},
       {{"visibility", "vec4 -> R32F", "V in [0, 1] in r (1 = lit); PCF_SAMPLE: what the pixel pays, a byte of an R8 "
         "target: 0 facing away from the light, 1 the blocker search alone (and sky), 2 the search and PCF; where it "
         "searches on geometry, plus 4 x its map footprint in quarter texels, at most 63 (cpu_ref/ssm.cpp "
         "mapFootprintAt: how far its neighbours' receivers lie on the map)", 0}},
       "cpu_ref/ssm.cpp ssmAt: PCSS (Fernando 2005), a blocker search then an n x n PCF over the filter width. Drawn "
       "with the stencil test. PCF_SAMPLE: cpu_ref/ssm.cpp pcfSample."},
      {"temporal.frag", "fragment", "temporal.1, temporal.3", "CHANNELS: the effect's (1 or 3)",
       {{"positionHit", "sampler2D RGBA32F", "the level-0 G-buffer: view position, hit"},
        {"normalDepth", "sampler2D RGBA32F", "the level-0 G-buffer: view normal, depth"},
        {"stencil0", "sampler2D R8", "S_0"},
        {"alpha0", "sampler2D R32F", "a_0"},
        {"blended", "sampler2D R32F or RGBA32F", "the blend's final image c, W x H"},
        {"previousResult", "sampler2D R32F or RGBA32F", "the previous frame's result, W x H (uploaded)"},
        {"previousNormalDepth", "sampler2D RGBA32F", "the previous frame's view normal (rgb) and depth (a), W x H (uploaded)"}},
       {{"row0", "vec3", "row 0 of R, this view space to the previous one (common/temporal.h makeReprojection)"},
        {"row1", "vec3", "row 1 of R"},
        {"row2", "vec3", "row 2 of R"},
        {"offset", "vec3", "t: p' = R p + t"},
        {"previousProjection", "vec3", "the previous view's cx, cy and focal, full-res pixels"},
        {"lambda", "float", "lambda, the share of the history a coarse pixel keeps"},
        {"weight0", "float", "w_0, level 0's blend weight"},
        {"depthTolerance", "float", "delta: the same surface within delta z' (relative)"},
        {"normalCos", "float", "kappa: the same surface where n_t . n' >= kappa"}},
       {{"result", "vec4 -> R32F or RGBA32F", "final' = c + lambda_p (h - c)", 0},
        {"history", "vec4 -> RGBA32F", "h in rgb, lambda_p in a", 1}},
       "cpu_ref/temporal.cpp temporalTerm (docs/spec.md §14 steps 1-6): reprojectAt, historyTaps, sameSurface, "
       "historyAt, temporalWeight with levelZeroAlpha, temporalBlend."},
      {"trim.frag", "fragment", "trim.*",
       "STEP: 1 along x (level width x full-res height), 2 along y, 3 and 4 the margin along x and y, 5 S_l &= D_l; "
       "LEVEL: l; MARGIN: SSAO's blur radius (0: steps 3-4 not drawn)",
       {{"source", "sampler2D R8", "step 1: R(p), l/255 (blend.frag REACH); steps 2-4: the step before; step 5: S_l"},
        {"read", "sampler2D R8", "D_l", -1, "STEP == 5"}},
       {{"frame", "ivec2", "W x H, full-res pixels", -1, "STEP == 1 || STEP == 2"}},
       {{"result", "vec4 -> R8", "the step's map in r: D_l after step 4 (or 2), the trimmed S_l after step 5", 0}},
       "cpu_ref/masks.cpp blendReads and trimToBlend (docs/spec.md §12.5): D_l = the level pixels within the margin of "
       "a bilinear tap of a full-res pixel with R >= l; S_l &= D_l."},
      {"stencil.frag", "fragment", "stencil", "", {kStencilMask}, {}, {},
       "none: fills the stencil buffer from S_l (discard where S = 0); the effect passes then run with the stencil test."},
  };
  return table;
}

const ShaderContract* shaderContract(std::string_view file) {
  for (const ShaderContract& c : shaderContracts())
    if (c.file == file) return &c;
  return nullptr;
}

const ShaderVariable* findShaderVariable(std::string_view name) {
  for (const ShaderContract& c : shaderContracts()) {
    for (const ShaderVariable& v : c.uniforms)
      if (v.name == name) return &v;
    for (const ShaderVariable& v : c.inputs)
      if (v.name == name) return &v;
  }
  return nullptr;
}

namespace {
std::string cell(std::string_view s) {
  std::string out(s);
  for (size_t at = out.find('|'); at != std::string::npos; at = out.find('|', at + 2)) out.replace(at, 1, "\\|");
  return out;
}

std::string variables(const std::vector<ShaderVariable>& vars, bool withLocation) {
  std::string out = withLocation ? "| name | location | type / format | meaning | variant |\n|---|---|---|---|---|\n"
                                 : "| name | type / format | meaning, unit | variant |\n|---|---|---|---|\n";
  for (const ShaderVariable& v : vars) {
    out += "| `" + std::string(v.name) + "` | ";
    if (withLocation) out += (v.location >= 0 ? std::to_string(v.location) : std::string("-")) + " | ";
    out += cell(v.type) + " | " + cell(v.meaning) + " | " + (v.variant.empty() ? "all" : cell(v.variant)) + " |\n";
  }
  return out;
}
}  // namespace

std::string shaderContractMarkdown() {
  std::string md;
  md += "# The shader contract\n\n";
  md += "<!-- Generated by `mrr shaders contract` from common/stages.h and common/shader_contract.h; "
        "the test shader_contract_doc_is_current fails when this file and the code disagree. Do not edit. -->\n\n";
  md += "What each file of `gpu/shaders/` is given and must give back, so your own GLSL can replace it: "
        "`mrr shaders export DIR` writes the files, `--shaders DIR` on `render`, `probe`, `compare` and `bench` "
        "loads each file present in DIR in place of the built-in one (docs/validate-your-own.md).\n\n";
  md += "## Conventions\n\n";
  md += "- GLSL 3.30 core. The host pastes, right after the `#version` line, the variant's `#define`s and the shared "
        "constants of common/shader_constants.h as `const int` and `const float` lines (Shared constants, below), then "
        "`#line 2 0`: driver logs keep your file's line numbers. `#include \"FILE\"` at the start of a line pastes FILE "
        "(yours if DIR has it) as source string k (`#line 1 k`), so an error in it is reported as FILE:LINE.\n";
  md += "- Full-screen passes: `fullscreen.vert` draws one triangle over the target (or pixel rectangles, "
        "`useRects`); a fragment's pixel is `ivec2(gl_FragCoord.xy)`, its centre at (x + 0.5, y + 0.5). Every texture "
        "is read with `texelFetch` at integer texels (no filtering, no normalised coordinates). Images are stored "
        "top row first: GL row 0 is image row 0, so nothing is flipped.\n";
  md += "- Levels: level l has scale s_l = 2^l; its pixel (x, y) covers full-res pixels [x s_l, (x+1) s_l) and "
        "holds full-res pixel (x s_l + s_l/2, y s_l + s_l/2) (integer division): its G-buffer is level 0's at those "
        "pixels. Per-level passes run at the level's size.\n";
  md += "- Stencil: the effect passes (ssao, ssm, ssgi, bilateral) are drawn with the stencil test: "
        "`stencil.frag` marks the pixels with S_l = 1, and only those run. Pixels with S_l = 0 keep the cleared 0 "
        "(never evaluated); a shader must not rely on them.\n";
  md += "- Outputs are `layout(location = N) out vec4`; a one-channel target keeps `.r`. A uniform the built-in "
        "program has active must be active in yours (the host sets it), and each output at the same location; "
        "else mrr stops with an error naming it.\n";
  md += "- Tolerances: your stage is judged by the rules of common/tolerance.h (`mrr compare`), on the oracle's "
        "inputs (end to end) and on your own inputs (same input).\n\n";
  md += "## Stages\n\n";
  md += "From the stage list (common/stages.h): each image of a frame, the shader that makes it, its channels in "
        "the stages EXR and its rules.\n\n";
  md += "| part | step | per level | shader | EXR channels | end to end | same input | what |\n|---|---|---|---|---|---|---|---|\n";
  for (const PartInfo& p : kParts)
    md += "| `" + std::string(p.name) + "` | " + std::to_string(p.step) + " | " + (p.perLevel ? "yes" : "no") +
          " | " + cell(p.shader) + " | " + cell(p.channels) + " | " + (p.endToEnd.empty() ? "-" : cell(p.endToEnd)) +
          " | " + (p.sameInput.empty() ? "-" : cell(p.sameInput)) + " | " + cell(p.what) + " |\n";
  md += "\n`effect:X` is X for SSAO and SSM (one channel) and X.R, X.G, X.B for SSGI.\n\n";
  md += "## Shared constants\n\n";
  md += "The numbers the oracle and the shaders share, from common/shader_constants.h (which says what each is), "
        "exactly as the host pastes them into every shader, yours too: use them, and do not declare these names "
        "yourself (a second declaration does not compile). The GLSL type is the C++ one.\n\n";
  md += "```glsl\n";
  for (const ShaderConstant& k : kShaderConstants) md += k.glslDeclaration() + "\n";
  md += "```\n\n";
  md += "## Files\n\n";
  for (const ShaderContract& c : shaderContracts()) {
    md += "### " + std::string(c.file) + "\n\n";
    md += "- role: " + std::string(c.role) + "; host programs: " + std::string(c.programs) + "\n";
    std::string parts;
    for (const PartInfo& p : kParts)
      if (std::string_view(p.shader).find(c.file) != std::string_view::npos)
        parts.append(parts.empty() ? "" : ", ").append("`").append(p.name).append("`");
    if (!parts.empty()) md += "- makes: " + parts + "\n";
    md += "- defines: " + (c.defines.empty() ? std::string("none") : std::string(c.defines)) + "\n";
    md += "- the oracle: " + std::string(c.oracle) + "\n\n";
    if (!c.inputs.empty()) md += "Inputs:\n\n" + variables(c.inputs, false) + "\n";
    if (!c.uniforms.empty()) md += "Uniforms:\n\n" + variables(c.uniforms, false) + "\n";
    if (!c.outputs.empty()) md += "Outputs:\n\n" + variables(c.outputs, true) + "\n";
  }
  return md;
}

std::string shaderExportReadme() {
  std::string text =
      "# mrr's shaders, exported\n\n"
      "These are the port's GLSL 3.30 files (`mrr shaders export`). Edit any of them and run\n\n"
      "    mrr compare --shaders THIS_FOLDER --scene builtin:demo --effect ssao --size 320x180\n\n"
      "Each file present here replaces the built-in one of the same name (includes too); delete the\n"
      "files you do not change. `compare` judges every stage against the oracle and names the first\n"
      "stage that fails on its last line. Compile errors are reported as FILE:LINE, exit 2.\n\n"
      "The contract, in short (docs/shader-contract.md has every input, uniform and output):\n\n"
      "- the host pastes the variant's #defines and the shared constants after #version, then `#line 2 0` (do not "
      "declare those constants again: docs/shader-contract.md lists them);\n"
      "- full-screen passes: pixel = ivec2(gl_FragCoord.xy), read textures with texelFetch;\n"
      "- the effect passes run only where the stencil S_l = 1;\n"
      "- keep every uniform the built-in uses (`seed` excepted: a shader with its own noise may drop it), and every "
      "output at its location.\n\n"
      "`sampling/` holds mrr's sampling as data (the SSAO and SSGI kernels, the rotation hash with test vectors): "
      "draw the same samples and `compare` judges your SSAO pixel for pixel; draw your own and judge it with "
      "`compare --noise-aware` (docs/validate-your-own.md).\n\n"
      "| file | role | programs | outputs |\n|---|---|---|---|\n";
  for (const ShaderContract& c : shaderContracts()) {
    std::string outs;
    for (const ShaderVariable& v : c.outputs)
      if (v.location >= 0) outs += (outs.empty() ? "" : ", ") + std::string(v.name) + "@" + std::to_string(v.location);
    text += "| " + std::string(c.file) + " | " + std::string(c.role) + " | " + std::string(c.programs) + " | " +
            (outs.empty() ? "-" : outs) + " |\n";
  }
  return text;
}

}  // namespace mrr
