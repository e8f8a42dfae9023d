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

// The EGL devices a context may be made on (EGL_EXT_platform_device), or why there are none.
struct PlatformDevices {
  bool platform_base = false;  // EGL_EXT_platform_base or EGL 1.5: eglGetPlatformDisplayEXT
  std::vector<EGLDeviceEXT> devices;
  std::string why;  // when devices is empty
};

PlatformDevices platform_devices() {
  PlatformDevices d;
  d.platform_base =
      has_client_extension("EGL_EXT_platform_base") || epoxy_egl_version(EGL_NO_DISPLAY) >= 15;
  if (d.platform_base && has_client_extension("EGL_EXT_platform_device"))
    d.devices = query_devices(&d.why);
  else
    d.why = "EGL_EXT_platform_device not supported";
  return d;
}

Candidate device_candidate(const PlatformDevices& d, int i) {
  const EGLDeviceEXT dev = d.devices[static_cast<size_t>(i)];
  // The display first, then the label: the order EGL is asked in.
  const EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, dev, nullptr);
  return {display, "device " + std::to_string(i) + " (" + describe_device(dev, i).name + ")"};
}

// An explicit gpu index is the only candidate.
Result<std::vector<Candidate>> requested_device(const PlatformDevices& d, int gpu) {
  if (d.devices.empty())
    return Status::error("no EGL display: EGL device " + std::to_string(gpu) + " requested but " +
                         d.why);
  if (gpu >= static_cast<int>(d.devices.size()))
    return Status::error("no EGL display: EGL device " + std::to_string(gpu) + " requested, " +
                         std::to_string(d.devices.size()) + " available");
  return std::vector<Candidate>{device_candidate(d, gpu)};
}

// Without an index: the hardware devices, surfaceless, the first software device, the default
// display.
std::vector<Candidate> default_candidates(const PlatformDevices& d) {
  std::vector<Candidate> candidates;
  int software = -1;
  for (int i = 0; i < static_cast<int>(d.devices.size()); ++i) {
    if (describe_device(d.devices[static_cast<size_t>(i)], i).software) {
      if (software < 0) software = i;
      continue;
    }
    candidates.push_back(device_candidate(d, i));
  }
  if (d.platform_base && has_client_extension("EGL_MESA_platform_surfaceless"))
    candidates.push_back(
        {eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
         "surfaceless"});
  if (software >= 0) candidates.push_back(device_candidate(d, software));
  candidates.push_back({eglGetDisplay(EGL_DEFAULT_DISPLAY), "default display"});
  return candidates;
}

// Displays to try, in order.
Result<std::vector<Candidate>> display_candidates(const PlatformDevices& d, int gpu) {
  if (gpu >= 0) return requested_device(d, gpu);
  return default_candidates(d);
}

// The config of an OpenGL context on dpy: none with EGL_KHR_no_config_context.
Result<EGLConfig> choose_config(EGLDisplay dpy) {
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (epoxy_has_egl_extension(dpy, "EGL_KHR_no_config_context")) return config;
  const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
  EGLint n = 0;
  if (!eglChooseConfig(dpy, attribs, &config, 1, &n) || n < 1)
    return Status::error("no EGL config with EGL_OPENGL_BIT");
  return config;
}

// An OpenGL 4.5 core context on an initialised display (not yet current).
Result<EGLContext> create_context(EGLDisplay dpy) {
  if (!epoxy_has_egl_extension(dpy, "EGL_KHR_surfaceless_context"))
    return Status::error("EGL_KHR_surfaceless_context not supported");
  if (!eglBindAPI(EGL_OPENGL_API))
    return Status::error("eglBindAPI(EGL_OPENGL_API) failed: " + egl_error());
  Result<EGLConfig> config = choose_config(dpy);
  if (!config.ok()) return config.status();
  const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                4,
                                EGL_CONTEXT_MINOR_VERSION,
                                5,
                                EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                EGL_NONE};
  EGLContext ctx = eglCreateContext(dpy, *config, EGL_NO_CONTEXT, ctx_attribs);
  if (ctx == EGL_NO_CONTEXT) return Status::error("no OpenGL 4.5 core context: " + egl_error());
  return ctx;
}

// Initialises c's display and makes a context current on it with no surface. On failure, appends
// "platform: why" to `errors` (the display released again) and returns EGL_NO_CONTEXT.
EGLContext open_candidate(const Candidate& c, std::string* egl_version, std::string& errors) {
  auto note = [&](const std::string& what) {
    errors += (errors.empty() ? "" : "; ") + c.platform + ": " + what;
  };
  if (c.display == EGL_NO_DISPLAY) {
    note("no display " + egl_error());
    return EGL_NO_CONTEXT;
  }
  if (Status s = initialize_display(c.display, egl_version); !s.ok()) {
    note(s.message());
    return EGL_NO_CONTEXT;
  }
  auto fail = [&](const std::string& what) {
    note(what);
    release_display(c.display);
  };
  Result<EGLContext> ctx = create_context(c.display);
  if (!ctx.ok()) {
    fail(ctx.status().message());
    return EGL_NO_CONTEXT;
  }
  if (!eglMakeCurrent(c.display, EGL_NO_SURFACE, EGL_NO_SURFACE, *ctx)) {
    fail("eglMakeCurrent failed: " + egl_error());
    eglDestroyContext(c.display, *ctx);
    return EGL_NO_CONTEXT;
  }
  return *ctx;
}

std::string gl_string(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
}

// The current context's description (its extensions apart).
ContextInfo current_info(const std::string& platform, const std::string& egl_version) {
  ContextInfo info;
  info.platform = platform;
  info.egl_version = egl_version;
  info.renderer = gl_string(GL_RENDERER);
  info.vendor = gl_string(GL_VENDOR);
  info.version = gl_string(GL_VERSION);
  info.glsl_version = gl_string(GL_SHADING_LANGUAGE_VERSION);
  return info;
}

std::vector<std::string> current_extensions() {
  std::vector<std::string> out;
  GLint n = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &n);
  for (GLint i = 0; i < n; ++i) {
    const GLubyte* e = glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i));
    if (e) out.emplace_back(reinterpret_cast<const char*>(e));
  }
  return out;
}

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
  const PlatformDevices devices = platform_devices();
  Result<std::vector<Candidate>> candidates = display_candidates(devices, gpu);
  if (!candidates.ok()) return candidates.status();
  std::string errors;
  for (const Candidate& c : *candidates) {
    std::string egl_version;
    EGLContext ctx = open_candidate(c, &egl_version, errors);
    if (ctx == EGL_NO_CONTEXT) continue;
    std::unique_ptr<Context> out(new Context());
    out->display_ = c.display;
    out->context_ = ctx;
    out->info_ = current_info(c.platform, egl_version);
    out->all_extensions_ = current_extensions();
    for (const char* e : {"GL_ARB_texture_filter_anisotropic", "GL_EXT_texture_filter_anisotropic",
                          "GL_ARB_timer_query", "GL_KHR_debug"})
      if (out->has_extension(e)) out->info_.extensions.emplace_back(e);
    if (epoxy_gl_version() < 45)
      return Status::error("no OpenGL 4.5: " + c.platform + " gives \"" + out->info_.version +
                           "\"");
    return out;
  }
  if (errors.empty()) errors = "no candidate display (" + devices.why + ")";
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
