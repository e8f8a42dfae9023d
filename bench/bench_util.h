// Shared by the technique-cost benchmarks (bench_techniques, bench_quadric): one case of a
// technique with its parameters, and the timing loop over frames of a built-in scene.
#pragma once

#include <benchmark/benchmark.h>

#include <chrono>
#include <map>
#include <string>

#include "bake/environment_bake.h"
#include "builtin/builtin.h"
#include "render/derived_maps.h"
#include "render/render.h"
#include "render/renderer.h"

namespace relief {

struct TechniqueCase {
  const char* name;  // the benchmark's name after its prefix
  const char* technique;
  std::map<std::string, std::string> params;
  // Light every material with the glTF metallic-roughness BRDF (a dielectric of roughness 0.5)
  // in place of the scene's Blinn-Phong (docs/scene-format.md, "Shading").
  bool metallic_roughness = false;
  // Height-field ambient occlusion on every relief material with this many rays (0: off;
  // RenderOptions::height_ao_rays, docs/effects.md).
  int height_ao_rays = 0;
  // Image-based light from the built-in studio environment (baked once, untimed) beside the
  // scene's lights (docs/environment.md).
  bool environment = false;
  int width = 1024, height = 768;
};

// Renders the built-in scene `scene_name` at c.width x c.height on 2 threads with `c`'s technique
// and parameters: one untimed warm-up frame (derived state, caches), then one timed frame per
// iteration, each handed back to the backend (no framebuffer allocation per frame). Sets the
// counters ns_per_fragment and steps_per_fragment and the items processed (fragments); returns
// the summed work, or sets the error on `state` and returns no fragments.
inline WorkCounters time_technique(benchmark::State& state, const char* scene_name,
                                   const TechniqueCase& c) {
  Result<Scene> scene = make_builtin_scene(scene_name);
  if (scene.ok() && c.metallic_roughness)
    for (Material& m : scene->materials) {
      m.shading = ShadingModel::kMetallicRoughness;
      m.metallic = 0.0f;
      m.roughness = 0.5f;
    }
  RenderOptions opt;
  opt.width = c.width;
  opt.height = c.height;
  if (c.environment) {
    Result<DerivedEnvironment> env = derived_environment(studio_environment(512, 256));
    if (!env.ok()) {
      state.SkipWithError(env.status().message().c_str());
      return {};
    }
    opt.environment = env->maps;
  }
  opt.technique = c.technique;
  opt.params = c.params;
  if (c.height_ao_rays > 0) opt.height_ao_rays = c.height_ao_rays;
  Renderer renderer(make_cpu_backend({.threads = 2}));
  Result<Plan> plan = renderer.plan(*scene, opt);
  if (!scene.ok() || !plan.ok()) {
    state.SkipWithError(plan.ok() ? "no scene" : plan.status().message().c_str());
    return {};
  }
  (void)renderer.execute(*scene, *plan);
  WorkCounters work;
  double ns = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    Result<RenderResult> r = renderer.execute(*scene, *plan);
    ns += std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
    if (!r.ok()) {
      state.SkipWithError(r.status().message().c_str());
      return {};
    }
    for (const PassStats& p : r->passes) work += p.raster.work;
    benchmark::DoNotOptimize(r->framebuffer.color.pixels.data());
    renderer.recycle(std::move(r).value());
  }
  const double f = static_cast<double>(work.fragments);
  if (f == 0.0) return work;
  state.counters["ns_per_fragment"] = ns / f;
  state.counters["steps_per_fragment"] = static_cast<double>(work.search_steps) / f;
  state.SetItemsProcessed(static_cast<int64_t>(work.fragments));
  return work;
}

// Runs the registered benchmarks the command line selects; the tail of a benchmark's main().
inline int run_registered_benchmarks(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

// Registers one benchmark `prefix` + case name per case (milliseconds, real time), then runs
// those the command line selects; the body of a benchmark's main().
template <size_t N, typename Run>
int run_technique_cases(int argc, char** argv, const char* prefix, const TechniqueCase (&cases)[N],
                        Run run) {
  for (const TechniqueCase& c : cases)
    benchmark::RegisterBenchmark((std::string(prefix) + c.name).c_str(),
                                 [&c, run](benchmark::State& s) { run(s, c); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  return run_registered_benchmarks(argc, argv);
}

}  // namespace relief
