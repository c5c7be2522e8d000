// TEMPORARY: timing of block-run draws on llvmpipe (not committed)
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <gtest/gtest.h>
#include <chrono>
#include <random>
#include "common/frame.h"
#include "gpu/context.h"
#include "gpu/gbuffer.h"
#include "gpu/masks.h"
#include "gpu/program.h"
#include "tests/gpu/gl_test.h"
namespace mrr { namespace {
double ms(std::chrono::steady_clock::time_point t0) { return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(); }
TEST(ZzGsBench, Time) {
  MRR_REQUIRE_GL_OR_SKIP();
  gpu::GlContext context;
  if (std::getenv("GEOM_DIR")) gpu::loadShaderDirectory(std::getenv("GEOM_DIR"));
  Scene empty;
  const gpu::GpuScene scene(empty);
  std::mt19937 rng(3);
  const int bw = 320, bh = 180, bs = 4, tw = 1280, th = 720;
  ImageU8 blocks(bw, bh);
  // edges: random lines of blocks
  for (int k = 0; k < 60; ++k) { int x = rng() % bw, y = rng() % bh, dx = (int)(rng()%3)-1, dy = (int)(rng()%3)-1; for (int i = 0; i < 80; ++i) { if (x>=0&&y>=0&&x<bw&&y<bh) blocks.at(x,y)=1; x+=dx; y+=dy; if(!dx&&!dy) x++; } }
  auto map = scene.target(bw, bh, 1, false, gpu::Texel::R8);
  std::vector<uint8_t> bytes(blocks.data.size()); for (size_t i=0;i<bytes.size();++i) bytes[i]=blocks.data[i]?255:0;
  glBindTexture(GL_TEXTURE_2D, map->texture(0)); glPixelStorei(GL_UNPACK_ALIGNMENT,1);
  glTexSubImage2D(GL_TEXTURE_2D,0,0,0,bw,bh,GL_RED,GL_UNSIGNED_BYTE,bytes.data());
  const std::string fs = "#version 330 core\nlayout(location = 0) out vec4 c;\nvoid main() { c = vec4(1.0); }\n";
  const unsigned pb = gpu::compileProgramFromSource("b", "blocks.vert", gpu::shaderSource("blocks.vert"), "stencil.frag", fs);
  const unsigned pf = gpu::compileProgramFromSource("f", "fullscreen.vert", gpu::shaderSource("fullscreen.vert"), "stencil.frag", fs);
  auto target = scene.target(tw, th, 1, false, gpu::Texel::R8);
  const auto rects = gpu::blockRects(blocks, 1, bs, tw, th);
  int set = 0; for (auto v : blocks.data) set += v;
  std::printf("set blocks %d of %d, rects %zu\n", set, bw*bh, rects.size());
  for (int rep = 0; rep < 3; ++rep) {
    target->bind(); glFinish();
    auto t0 = std::chrono::steady_clock::now(); glUseProgram(pb); scene.draw(gpu::Cover::blocksOf(*map, bs, 1), tw, th); glFinish(); double a = ms(t0);
    t0 = std::chrono::steady_clock::now(); glUseProgram(pb); scene.draw(gpu::Cover::blocksOf(*map, bs, 0), tw, th); glFinish(); double a0 = ms(t0);
    t0 = std::chrono::steady_clock::now(); glUseProgram(pf); scene.drawRects(rects, tw, th); glFinish(); double b = ms(t0);
    t0 = std::chrono::steady_clock::now(); glUseProgram(pf); scene.drawFullscreen(); glFinish(); double c = ms(t0);
    auto zero = scene.target(bw, bh, 1, false, gpu::Texel::R8); zero->bind(); const float z[4]={0,0,0,0}; glClearBufferfv(GL_COLOR,0,z); target->bind(); glFinish();
    t0 = std::chrono::steady_clock::now(); glUseProgram(pb); scene.draw(gpu::Cover::blocksOf(*zero, bs, 1), tw, th); glFinish(); double d = ms(t0);
    std::printf("blocks set %.2f ms, blocks clear %.2f ms, host rects %.2f ms, fullscreen %.2f ms, scan-only %.2f\n", a, a0, b, c, d);
  }
}
}}
