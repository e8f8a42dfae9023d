// `relief info`: the backends this machine can run: the CPU's threads, and for GL each EGL device
// and the context the backend would create (renderer, vendor, version), or why there is none.
#include <cstdio>
#include <thread>

#include "apps/commands.h"
#include "apps/version.h"
#include "gl/context.h"
#include "gl/gl_backend.h"
#include "gl/shader.h"
#include "plugins/registry.h"

namespace relief::cli {

void register_info(CLI::App& app, Action& action) {
  auto* sub = app.add_subcommand("info", "List the backends and devices available here");
  auto gpu = std::make_shared<int>(-1);
  sub->add_option("--gpu", *gpu, "Probe this EGL device index for the GL backend (-1 = default)");
  sub->callback([&action, gpu] {
    action = [gpu] {
      std::printf("%s", build_info_text().c_str());
      const unsigned hw = std::thread::hardware_concurrency();
      std::printf("cpu: available, %u threads (hardware concurrency)\n", hw ? hw : 1u);

      Result<std::vector<gl::EglDevice>> devices = gl::list_egl_devices();
      Result<std::unique_ptr<gl::Context>> ctx = gl::Context::create(*gpu);
      if (ctx.ok()) {
        const gl::ContextInfo& i = (*ctx)->info();
        std::printf("gl: available\n");
        std::printf("  display:  %s (EGL %s)\n", i.platform.c_str(), i.egl_version.c_str());
        std::printf("  renderer: %s\n", i.renderer.c_str());
        std::printf("  vendor:   %s\n", i.vendor.c_str());
        std::printf("  version:  %s, GLSL %s\n", i.version.c_str(), i.glsl_version.c_str());
        std::string ext;
        for (const std::string& e : i.extensions) ext += (ext.empty() ? "" : " ") + e;
        std::printf("  extensions: %s\n", ext.empty() ? "(none of interest)" : ext.c_str());
      } else {
        std::printf("gl: unavailable (%s)\n", ctx.status().message().c_str());
      }
      if (devices.ok()) {
        std::printf("  EGL devices:\n");
        for (const gl::EglDevice& d : *devices)
          std::printf("    %d: %s%s\n", d.index, d.name.c_str(), d.software ? " (software)" : "");
      } else {
        std::printf("  EGL devices: none listed (%s)\n", devices.status().message().c_str());
      }
      std::string twins, missing;
      for (const PluginDescriptor* p : PluginRegistry::global().all()) {
        std::string& list = gl_has_twin(p->name) ? twins : missing;
        list += (list.empty() ? "" : " ") + std::string(p->name);
      }
      std::printf("  shaders:  %s\n", gl::shader_source_location().c_str());
      std::printf("  GLSL twins: %s\n", twins.empty() ? "(none)" : twins.c_str());
      if (!missing.empty()) std::printf("  no twin (cpu only): %s\n", missing.c_str());
      return 0;
    };
  });
}

void register_version(CLI::App& app, Action& action) {
  auto* sub = app.add_subcommand(
      "version", "Print the version, commit, build type, SIMD path and backends (as --version)");
  auto json = std::make_shared<bool>(false);
  sub->add_flag("--json", *json, "As one JSON object (the \"build\" object of --stats)");
  sub->callback([&action, json] {
    action = [json] {
      if (*json)
        std::printf("%s\n", build_info_json().dump().c_str());
      else
        std::printf("%s", build_info_text().c_str());
      return 0;
    };
  });
}

}  // namespace relief::cli
