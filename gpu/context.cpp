#include "gpu/context.h"

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <vector>

#include "common/error.h"

namespace mrr::gpu {

namespace {

// Initialises `display` and makes a 3.3 core context current on it, or returns false.
bool tryDisplay(EGLDisplay display, EGLContext& context) {
  if (display == EGL_NO_DISPLAY) return false;
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) return false;
  if (!eglBindAPI(EGL_OPENGL_API)) return false;
  const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  if (!eglChooseConfig(display, configAttributes, &config, 1, &count) || count < 1) config = EGL_NO_CONFIG_KHR;
  const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
  if (context == EGL_NO_CONTEXT) {
    eglTerminate(display);
    return false;
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {  // EGL_KHR_surfaceless_context
    eglDestroyContext(display, context);
    context = EGL_NO_CONTEXT;
    eglTerminate(display);
    return false;
  }
  return true;
}

}  // namespace

GlContext::GlContext(int deviceIndex) {
  auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto platformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  std::vector<EGLDeviceEXT> devices(16);
  EGLint deviceCount = 0;
  if (queryDevices && platformDisplay && queryDevices(static_cast<EGLint>(devices.size()), devices.data(), &deviceCount)) {
    require(deviceIndex < deviceCount, "--gl-device " + std::to_string(deviceIndex) + ": only " +
                                           std::to_string(deviceCount) + " EGL device(s)");
    for (EGLint i = 0; i < deviceCount; ++i) {
      if (deviceIndex >= 0 && i != deviceIndex) continue;
      EGLDisplay d = platformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[static_cast<size_t>(i)], nullptr);
      if (tryDisplay(d, context_)) {
        display_ = d;
        platform_ = "EGL device " + std::to_string(i);
        break;
      }
    }
  }
  if (display_ == EGL_NO_DISPLAY && deviceIndex < 0 && platformDisplay) {
    EGLDisplay d = platformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (tryDisplay(d, context_)) {
      display_ = d;
      platform_ = "surfaceless";
    }
  }
  require(display_ != EGL_NO_DISPLAY,
          "gpu: no EGL device gives an OpenGL 3.3 core context (install libegl-mesa0 and libgl1-mesa-dri, "
          "or use --path cpu)");
  const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  renderer_ = name ? name : "unknown renderer";
}

GlContext::~GlContext() {
  if (display_ == EGL_NO_DISPLAY) return;
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
  eglTerminate(display_);
}

bool glAvailable(std::string* why) {
  try {
    GlContext context;
    return true;
  } catch (const std::exception& e) {
    if (why) *why = e.what();
    return false;
  }
}

}  // namespace mrr::gpu
