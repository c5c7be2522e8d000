#pragma once
// A headless OpenGL 3.3 core context through EGL, with no display and no window
// (docs/platform.md): devices are enumerated with EGL_EXT_platform_device (the route on NVIDIA),
// falling back to Mesa's surfaceless platform (llvmpipe). Rendering goes to framebuffer
// objects only.
#include <EGL/egl.h>

#include <string>

namespace mrr::gpu {

class GlContext {
 public:
  // deviceIndex < 0: the first device that gives a 3.3 core context. Throws MrrError with one
  // line when no EGL device or no 3.3 core context can be had.
  explicit GlContext(int deviceIndex = -1);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  const std::string& renderer() const { return renderer_; }  // GL_RENDERER, e.g. "llvmpipe (LLVM 15…)"
  const std::string& platform() const { return platform_; }  // "device 0" or "surfaceless"

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  std::string renderer_, platform_;
};

// True when a context can be made here (tests skip with this reason otherwise).
bool glAvailable(std::string* why = nullptr);

}  // namespace mrr::gpu
