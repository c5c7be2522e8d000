// SPEC §13 on the port: limit.frag and the masks' level-limit pass against the oracle through
// compareFrames (the check `mrr compare` makes), with a gaze and with a previous frame, for mrr
// and tiles; and the port's limit is the oracle's on the port's own G-buffer.
#include <gtest/gtest.h>

#include <memory>

#include "common/stages.h"
#include "compare/parity/parity.h"
#include "cpu_ref/foveation.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "tests/gpu/gl_test.h"
#include "tests/oracle/render_helpers.h"

namespace mrr {
namespace {

TEST(GpuFoveation, CompareAgreesWithAGazeAndWithAPreviousFrame) {
  MRR_REQUIRE_GL_OR_SKIP();
  gpu::GlContext context;
  for (const Mode mode : {Mode::Mrr, Mode::Tiles})
    for (const bool motion : {false, true}) {
      Settings s = test::ssaoSettings(320, 192, 8, mode);
      const auto r = test::renderScene("builtin:demo", s);  // the camera, and the scene
      if (motion) {
        const glm::vec3 side = glm::normalize(glm::cross(r.camera.target - r.camera.eye, r.camera.up));
        const float step = 0.02f * glm::length(r.camera.target - r.camera.eye);
        s.foveation.motion = true;
        s.foveation.prevEye = r.camera.eye + step * side;
        s.foveation.prevTarget = r.camera.target + step * side;
        s.foveation.prevUp = r.camera.up;
        s.foveation.prevYfov = r.camera.yfov;
      } else {
        s.foveation.gaze = true;
        s.foveation.gazeX = 100;
        s.foveation.gazeY = 80;
        s.foveation.ppd = 30.0f;
      }
      const Constants k = makeConstants(s, r.scene->bounds().diagonal());
      const FrameResult cpu = r.renderer->render(r.camera, k);
      const gpu::GpuRenderer port(*r.scene);
      const FrameResult gpu = port.render(r.camera, k);
      const std::string name = toString(mode) + (motion ? " motion" : " gaze");
      ASSERT_FALSE(gpu.levelLimit.empty()) << name;
      const ParityResult result = compareFrames(cpu, gpu, r.scene->light);
      EXPECT_TRUE(result.pass()) << name << ": first failing " << result.firstFailing();
      const StageRow* limit = result.row(partName(Part::LevelLimit));
      ASSERT_NE(limit, nullptr) << name;
      const StageRow* term = result.row(partName(motion ? Part::Motion : Part::Eccentricity));
      ASSERT_NE(term, nullptr) << name;
      // The limit is not trivial: some pixels coarsen, and the port's M_0 is cleared there too.
      int64_t coarse = 0;
      for (int y = 0; y < 192; ++y)
        for (int x = 0; x < 320; ++x) coarse += gpu.levelLimit.at(x, y, kLimitLevel) > 0;
      EXPECT_GT(coarse, 1000) << name;
      if (mode == Mode::Mrr) {
        const LevelLimit same = levelLimit(gpu.levels[0].gbuffer, gpu.view, gpu.constants);
        int64_t differ = 0;
        for (size_t i = 0; i < same.limit.data.size(); ++i) differ += same.limit.data[i] != gpu.levelLimit.data[i];
        EXPECT_LE(differ, motion ? 64 : 0) << name << ": the eye's levels are exact integer tests";
      }
    }
}

// --pan on the port: the previous view made on the host (previousView), the same as the oracle's.
TEST(GpuFoveation, CompareAgreesWithAPan) {
  MRR_REQUIRE_GL_OR_SKIP();
  gpu::GlContext context;
  Settings s = test::ssaoSettings(320, 192, 8, Mode::Mrr);
  const auto r = test::renderScene("builtin:demo", s);
  s.foveation.motion = true;
  s.foveation.panned = true;
  s.foveation.pan = 0.02f * glm::length(r.camera.target - r.camera.eye);
  const Constants k = makeConstants(s, r.scene->bounds().diagonal());
  const FrameResult cpu = r.renderer->render(r.camera, k);
  const gpu::GpuRenderer port(*r.scene);
  const FrameResult gpu = port.render(r.camera, k);
  ASSERT_FALSE(gpu.levelLimit.empty());
  const ParityResult result = compareFrames(cpu, gpu, r.scene->light);
  EXPECT_TRUE(result.pass()) << "first failing " << result.firstFailing();
  int64_t coarse = 0;
  for (int y = 0; y < 192; ++y)
    for (int x = 0; x < 320; ++x) coarse += gpu.levelLimit.at(x, y, kLimitLevel) > 0;
  EXPECT_GT(coarse, 1000);
}

}  // namespace
}  // namespace mrr
