#include "gl/context.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>
#include <sstream>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#ifndef EGL_RENDERER_EXT
#define EGL_RENDERER_EXT 0x335F
#endif
#ifndef EGL_DRM_RENDER_NODE_FILE_EXT
#define EGL_DRM_RENDER_NODE_FILE_EXT 0x3377
#endif

namespace relief::gl {
namespace {

const char* egl_error_name(EGLint e) {
  switch (e) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CURRENT_SURFACE:
      return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_SURFACE:
      return "EGL_BAD_SURFACE";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    case EGL_BAD_NATIVE_PIXMAP:
      return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
      return "EGL_BAD_NATIVE_WINDOW";
    case EGL_CONTEXT_LOST:
      return "EGL_CONTEXT_LOST";
    default:
      return "unknown EGL error";
  }
}

std::string egl_error() {
  char buf[64];
  const EGLint e = eglGetError();
  std::snprintf(buf, sizeof(buf), "%s (0x%04x)", egl_error_name(e), static_cast<unsigned>(e));
  return buf;
}

// libepoxy aborts when it cannot find libEGL; check first so EGL's absence is an error value.
bool egl_library_present() {
  static const bool present = [] {
    void* h = dlopen("libEGL.so.1", RTLD_LAZY | RTLD_LOCAL);
    if (!h) h = dlopen("libEGL.so", RTLD_LAZY | RTLD_LOCAL);
    return h != nullptr;  // kept open: epoxy resolves through it
  }();
  return present;
}

bool has_client_extension(const char* name) {
  // Client extensions (EGL_EXT_client_extensions) are queried on EGL_NO_DISPLAY.
  const char* ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!ext) {
    eglGetError();  // clear EGL_BAD_DISPLAY from an EGL without client extensions
    return false;
  }
  std::istringstream in(ext);
  std::string word;
  while (in >> word)
    if (word == name) return true;
  return false;
}

bool contains_word(const std::string& list, const char* word) {
  std::istringstream in(list);
  std::string w;
  while (in >> w)
    if (w == word) return true;
  return false;
}

// Initialised displays are shared by every context on them (EGL returns the same handle for the
// same platform and native display), so they are terminated when the last context goes.
std::mutex& display_mutex() {
  static std::mutex m;
  return m;
}
std::map<EGLDisplay, int>& display_refs() {
  static auto* refs = new std::map<EGLDisplay, int>();
  return *refs;
}

Status initialize_display(EGLDisplay dpy, std::string* version) {
  std::lock_guard<std::mutex> lock(display_mutex());
  EGLint major = 0, minor = 0;
  if (!eglInitialize(dpy, &major, &minor))
    return Status::error("eglInitialize failed: " + egl_error());
  ++display_refs()[dpy];
  *version = std::to_string(major) + "." + std::to_string(minor);
  return {};
}

void release_display(EGLDisplay dpy) {
  std::lock_guard<std::mutex> lock(display_mutex());
  auto it = display_refs().find(dpy);
  if (it == display_refs().end()) return;
  if (--it->second == 0) {
    display_refs().erase(it);
    eglTerminate(dpy);
  }
}

std::vector<EGLDeviceEXT> query_devices(std::string* why) {
  if (!has_client_extension("EGL_EXT_device_enumeration") &&
      !has_client_extension("EGL_EXT_device_base")) {
    *why = "EGL_EXT_device_enumeration not supported";
    return {};
  }
  EGLint n = 0;
  if (!eglQueryDevicesEXT(0, nullptr, &n)) {
    *why = "eglQueryDevicesEXT failed: " + egl_error();
    return {};
  }
  std::vector<EGLDeviceEXT> devices(static_cast<size_t>(std::max(n, 0)));
  if (n > 0 && !eglQueryDevicesEXT(n, devices.data(), &n)) {
    *why = "eglQueryDevicesEXT failed: " + egl_error();
    return {};
  }
  devices.resize(static_cast<size_t>(std::max(n, 0)));
  if (devices.empty()) *why = "no EGL devices";
  return devices;
}

EglDevice describe_device(EGLDeviceEXT dev, int index) {
  EglDevice d;
  d.index = index;
  const char* ext = eglQueryDeviceStringEXT(dev, EGL_EXTENSIONS);
  d.extensions = ext ? ext : "";
  d.software = contains_word(d.extensions, "EGL_MESA_device_software");
  auto query = [&](const char* extension, EGLint what) -> std::string {
    if (!contains_word(d.extensions, extension)) return "";
    const char* s = eglQueryDeviceStringEXT(dev, what);
    if (!s) eglGetError();
    return s ? s : "";
  };
  std::string name = query("EGL_EXT_device_query_name", EGL_RENDERER_EXT);
  if (name.empty()) name = query("EGL_EXT_device_drm_render_node", EGL_DRM_RENDER_NODE_FILE_EXT);
  if (name.empty()) name = query("EGL_EXT_device_drm", EGL_DRM_DEVICE_FILE_EXT);
  if (name.empty() && contains_word(d.extensions, "EGL_NV_device_cuda")) name = "cuda";
  if (name.empty()) name = d.software ? "software" : "unnamed";
  d.name = name;
  return d;
}

struct Candidate {
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string platform;
};

}  // namespace

Result<std::vector<EglDevice>> list_egl_devices() {
  if (!egl_library_present()) return Status::error("no EGL display: libEGL.so.1 not found");
  std::string why;
  std::vector<EGLDeviceEXT> devices = query_devices(&why);
  if (devices.empty()) return Status::error(why);
  std::vector<EglDevice> out;
  for (size_t i = 0; i < devices.size(); ++i)
    out.push_back(describe_device(devices[i], static_cast<int>(i)));
  return out;
}

Result<std::unique_ptr<Context>> Context::create(int gpu) {
  if (!egl_library_present()) return Status::error("no EGL display: libEGL.so.1 not found");
  const bool platform_base =
      has_client_extension("EGL_EXT_platform_base") || epoxy_egl_version(EGL_NO_DISPLAY) >= 15;
  std::string why;
  std::vector<EGLDeviceEXT> devices;
  if (platform_base && has_client_extension("EGL_EXT_platform_device"))
    devices = query_devices(&why);
  else
    why = "EGL_EXT_platform_device not supported";

  auto device_display = [&](int i) -> EGLDisplay {
    return eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[static_cast<size_t>(i)],
                                    nullptr);
  };
  auto device_label = [&](int i) {
    return "device " + std::to_string(i) + " (" +
           describe_device(devices[static_cast<size_t>(i)], i).name + ")";
  };

  // Displays to try, in order. An explicit gpu index is the only candidate.
  std::vector<Candidate> candidates;
  if (gpu >= 0) {
    if (devices.empty())
      return Status::error("no EGL display: EGL device " + std::to_string(gpu) + " requested but " +
                           why);
    if (gpu >= static_cast<int>(devices.size()))
      return Status::error("no EGL display: EGL device " + std::to_string(gpu) + " requested, " +
                           std::to_string(devices.size()) + " available");
    candidates.push_back({device_display(gpu), device_label(gpu)});
  } else {
    int software = -1;
    for (int i = 0; i < static_cast<int>(devices.size()); ++i) {
      if (describe_device(devices[static_cast<size_t>(i)], i).software) {
        if (software < 0) software = i;
        continue;
      }
      candidates.push_back({device_display(i), device_label(i)});
    }
    if (platform_base && has_client_extension("EGL_MESA_platform_surfaceless"))
      candidates.push_back(
          {eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
           "surfaceless"});
    if (software >= 0) candidates.push_back({device_display(software), device_label(software)});
    candidates.push_back({eglGetDisplay(EGL_DEFAULT_DISPLAY), "default display"});
  }

  std::string errors;
  for (const Candidate& c : candidates) {
    if (c.display == EGL_NO_DISPLAY) {
      errors += (errors.empty() ? "" : "; ") + c.platform + ": no display " + egl_error();
      continue;
    }
    std::string egl_version;
    Status s = initialize_display(c.display, &egl_version);
    if (!s.ok()) {
      errors += (errors.empty() ? "" : "; ") + c.platform + ": " + s.message();
      continue;
    }
    auto fail = [&](const std::string& what) {
      errors += (errors.empty() ? "" : "; ") + c.platform + ": " + what;
      release_display(c.display);
    };
    if (!epoxy_has_egl_extension(c.display, "EGL_KHR_surfaceless_context")) {
      fail("EGL_KHR_surfaceless_context not supported");
      continue;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
      fail("eglBindAPI(EGL_OPENGL_API) failed: " + egl_error());
      continue;
    }
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!epoxy_has_egl_extension(c.display, "EGL_KHR_no_config_context")) {
      const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(c.display, attribs, &config, 1, &n) || n < 1) {
        fail("no EGL config with EGL_OPENGL_BIT");
        continue;
      }
    }
    const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                  4,
                                  EGL_CONTEXT_MINOR_VERSION,
                                  5,
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                  EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                  EGL_NONE};
    EGLContext ctx = eglCreateContext(c.display, config, EGL_NO_CONTEXT, ctx_attribs);
    if (ctx == EGL_NO_CONTEXT) {
      fail("no OpenGL 4.5 core context: " + egl_error());
      continue;
    }
    if (!eglMakeCurrent(c.display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
      fail("eglMakeCurrent failed: " + egl_error());
      eglDestroyContext(c.display, ctx);
      continue;
    }
    std::unique_ptr<Context> out(new Context());
    out->display_ = c.display;
    out->context_ = ctx;
    ContextInfo& info = out->info_;
    info.platform = c.platform;
    info.egl_version = egl_version;
    auto str = [](GLenum name) {
      const GLubyte* s = glGetString(name);
      return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    info.renderer = str(GL_RENDERER);
    info.vendor = str(GL_VENDOR);
    info.version = str(GL_VERSION);
    info.glsl_version = str(GL_SHADING_LANGUAGE_VERSION);
    GLint n = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &n);
    for (GLint i = 0; i < n; ++i) {
      const GLubyte* e = glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i));
      if (e) out->all_extensions_.emplace_back(reinterpret_cast<const char*>(e));
    }
    for (const char* e : {"GL_ARB_texture_filter_anisotropic", "GL_EXT_texture_filter_anisotropic",
                          "GL_ARB_timer_query", "GL_KHR_debug"})
      if (out->has_extension(e)) info.extensions.emplace_back(e);
    if (epoxy_gl_version() < 45) {
      const std::string v = info.version;
      return Status::error("no OpenGL 4.5: " + c.platform + " gives \"" + v + "\"");
    }
    return out;
  }
  if (errors.empty()) errors = "no candidate display (" + why + ")";
  return Status::error("no EGL display: " + errors);
}

Context::~Context() {
  EGLDisplay dpy = static_cast<EGLDisplay>(display_);
  EGLContext ctx = static_cast<EGLContext>(context_);
  if (!dpy) return;
  if (eglGetCurrentContext() == ctx)
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (ctx) eglDestroyContext(dpy, ctx);
  release_display(dpy);
}

Status Context::make_current() {
  EGLDisplay dpy = static_cast<EGLDisplay>(display_);
  EGLContext ctx = static_cast<EGLContext>(context_);
  if (eglGetCurrentContext() == ctx) return {};
  if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx))
    return Status::error("eglMakeCurrent failed: " + egl_error());
  return {};
}

bool Context::has_extension(const char* name) const {
  return std::find(all_extensions_.begin(), all_extensions_.end(), name) != all_extensions_.end();
}

}  // namespace relief::gl
