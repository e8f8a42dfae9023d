// Rasterizer throughput: the `plane` scene full-screen at 1920x1080 with the `flat` and `normal`
// plugins, 1 and 2 threads. Reports fragments per second (items) and ms per frame, and per frame
// the serial part of the rasterizer (setup_ms: clip, setup, binning), its parallel part
// (raster_ms: traversal and shading) and the backend's remainder (other_ms: framebuffer, vertex
// preparation). RELIEF_SIMD=baseline runs the baseline (SSE2) code paths.
//
// BM_Raster_*_GL renders the same frame with the GL backend (the GLSL twins; on this machine Mesa
// llvmpipe, whose threads are set by LP_NUM_THREADS), so one run gives the CPU/llvmpipe ratio.
// Its time is the main pass up to glFinish (PassStats::ms): no upload, no readback, no counters.
#include <benchmark/benchmark.h>

#include "base/simd.h"
#include "builtin/builtin.h"
#include "gl/gl_backend.h"
#include "render/render.h"
#include "render/renderer.h"

namespace relief {
namespace {

// The benchmarked frame: `plane` at 1920x1080 with `technique`.
RenderOptions plane_options(const char* technique) {
  RenderOptions opt;
  opt.width = 1920;
  opt.height = 1080;
  opt.technique = technique;
  return opt;
}

void run_plane(benchmark::State& state, const char* technique) {
  const int threads = static_cast<int>(state.range(0));
  const bool recycle = state.range(1) != 0;  // hand each frame back: no allocation per frame
  Result<Scene> scene = make_builtin_scene("plane");
  Renderer renderer(make_cpu_backend({.threads = threads}));
  Result<Plan> plan = renderer.plan(*scene, plane_options(technique));
  uint64_t fragments = 0;
  double setup_ms = 0.0, raster_ms = 0.0, other_ms = 0.0;
  (void)renderer.execute(*scene, *plan);  // warm-up
  for (auto _ : state) {
    Result<RenderResult> r = renderer.execute(*scene, *plan);
    double pass_ms = 0.0;
    for (const PassStats& p : r->passes) {
      fragments += p.raster.work.fragments;
      setup_ms += p.raster.setup_ms;
      raster_ms += p.raster.raster_ms;
      pass_ms += p.raster.setup_ms + p.raster.raster_ms;
    }
    other_ms += r->frame_ms - pass_ms;
    benchmark::DoNotOptimize(r->framebuffer.color.pixels.data());
    if (recycle) renderer.recycle(std::move(r).value());
  }
  state.SetItemsProcessed(static_cast<int64_t>(fragments));
  const double n = static_cast<double>(state.iterations());
  state.counters["setup_ms"] = setup_ms / n;
  state.counters["raster_ms"] = raster_ms / n;
  state.counters["other_ms"] = other_ms / n;
  state.SetLabel(simd_level_name(simd_level()));
}

// The same frame on the GL backend: manual time = the main pass (PassStats::ms).
void run_plane_gl(benchmark::State& state, const char* technique) {
  Result<Scene> scene = make_builtin_scene("plane");
  const RenderOptions opt = plane_options(technique);  // llvmpipe's threads: LP_NUM_THREADS
  auto backend = make_gl_backend();
  if (!backend) {
    state.SkipWithError(backend.status().message().c_str());
    return;
  }
  Renderer renderer(std::move(backend).value());
  Result<Plan> plan = renderer.plan(*scene, opt);
  (void)renderer.execute(*scene, *plan);  // warm-up: llvmpipe compiles its variants
  uint64_t fragments = 0;
  for (auto _ : state) {
    Result<RenderResult> r = renderer.execute(*scene, *plan);
    double pass_ms = 0.0;
    for (const PassStats& p : r->passes) pass_ms += p.ms;
    fragments += static_cast<uint64_t>(opt.width) * static_cast<uint64_t>(opt.height);
    state.SetIterationTime(pass_ms * 1e-3);
  }
  state.SetItemsProcessed(static_cast<int64_t>(fragments));
}

void BM_Raster_Flat(benchmark::State& state) {
  run_plane(state, "flat");
}
void BM_Raster_Normal(benchmark::State& state) {
  run_plane(state, "normal");
}

// Arguments: threads, recycle (0: a new framebuffer every frame, as a one-frame render has).
BENCHMARK(BM_Raster_Flat)
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->ArgNames({"threads", "recycle"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Raster_Normal)
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->ArgNames({"threads", "recycle"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_Raster_Flat_GL(benchmark::State& state) {
  run_plane_gl(state, "flat");
}
void BM_Raster_Normal_GL(benchmark::State& state) {
  run_plane_gl(state, "normal");
}
BENCHMARK(BM_Raster_Flat_GL)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_Raster_Normal_GL)->Unit(benchmark::kMillisecond)->UseManualTime();

}  // namespace
}  // namespace relief

BENCHMARK_MAIN();
