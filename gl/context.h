// A headless OpenGL 4.5 core context through EGL (DESIGN.md, "The GL backend").
//
// Display selection: EGL_EXT_platform_device first (headless GPU servers): device `gpu` when
// gpu >= 0, otherwise the first hardware device (devices whose extensions name
// EGL_MESA_device_software are skipped while a hardware one exists). Without a hardware device,
// or when it cannot be initialised, EGL_MESA_platform_surfaceless (Mesa llvmpipe: CI and CPU
// machines), then a software EGL device, then EGL_DEFAULT_DISPLAY. The context is created with
// eglBindAPI(EGL_OPENGL_API), core profile 4.5 and no surface (EGL_KHR_surfaceless_context);
// rendering goes to framebuffer objects.
//
// Failure is a Status of one line ("no EGL display: ..."), never a crash, so a program that only
// renders on the CPU keeps working on machines without EGL drivers.
//
// Threads: a context is current on one thread at a time; make_current() binds it to the calling
// thread (the backend calls it at the start of each frame).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "base/status.h"

namespace relief::gl {

// One EGL device as EGL_EXT_device_query describes it.
struct EglDevice {
  int index = 0;
  std::string name;        // DRM node, renderer name or "software" when the driver reports none
  std::string extensions;  // device extension string
  bool software = false;   // EGL_MESA_device_software
};

// Devices from eglQueryDevicesEXT, or the Status explaining why none can be listed.
Result<std::vector<EglDevice>> list_egl_devices();

struct ContextInfo {
  std::string platform;  // "device 0 (/dev/dri/renderD128)", "surfaceless", "default display"
  std::string egl_version;
  std::string renderer;  // GL_RENDERER
  std::string vendor;    // GL_VENDOR
  std::string version;   // GL_VERSION
  std::string glsl_version;
  std::vector<std::string> extensions;  // GL extensions the backend cares about, present ones
};

class Context {
 public:
  // gpu: EGL device index, or -1 to pick (see above). An explicit index that does not exist or
  // cannot be initialised is an error; it never falls back to another display.
  static Result<std::unique_ptr<Context>> create(int gpu = -1);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Makes the context current on the calling thread.
  Status make_current();
  const ContextInfo& info() const { return info_; }
  bool has_extension(const char* name) const;

 private:
  Context() = default;
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  ContextInfo info_;
  std::vector<std::string> all_extensions_;
};

}  // namespace relief::gl
