// LeakSanitizer and Mesa: at eglTerminate (gl/context.cpp, when the last Context goes) Mesa's
// libEGL_mesa dlcloses its DRI driver (swrast_dri.so for llvmpipe, Mesa 22.3). Memory the driver
// allocated (two 56-byte calloc blocks in swrast_dri.so) is then referenced only from the
// driver's own globals, which are unmapped, so LSan reports it as leaked, with frames in an
// unloaded module that no suppression can name. Keeping the driver mapped (RTLD_NODELETE) shows
// that nothing else leaks: with it the GL tests run clean under ASan. So under ASan only, after
// the last test and before the static contexts are destroyed, every loaded *_dri.so is marked
// RTLD_NODELETE. Release builds keep the real unload path.
#include <gtest/gtest.h>

#if defined(__SANITIZE_ADDRESS__)
#define RELIEF_PIN_MESA_DRIVERS 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RELIEF_PIN_MESA_DRIVERS 1
#endif
#endif

#if RELIEF_PIN_MESA_DRIVERS
#include <dlfcn.h>
#include <link.h>

#include <cstring>
#include <string>
#include <vector>

namespace {

class PinMesaDrivers : public ::testing::Environment {
 public:
  void TearDown() override {
    std::vector<std::string> drivers;
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void* out) {
          const char* n = info->dlpi_name;
          if (n && std::strstr(n, "/dri/") && std::strstr(n, "_dri.so"))
            static_cast<std::vector<std::string>*>(out)->push_back(n);
          return 0;
        },
        &drivers);
    for (const std::string& d : drivers) dlopen(d.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
  }
};

const auto* const kPin = ::testing::AddGlobalTestEnvironment(new PinMesaDrivers);

}  // namespace
#endif
