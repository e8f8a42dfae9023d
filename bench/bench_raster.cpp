// Rasterizer throughput: the `plane` scene full-screen at 1920x1080 with the `flat` and `normal`
// plugins, 1 and 2 threads. Reports fragments per second (items) and ms per frame.
#include <benchmark/benchmark.h>

#include "render/render.h"
#include "scene/builtin.h"

namespace relief {
namespace {

void run_plane(benchmark::State& state, const char* technique) {
  const int threads = static_cast<int>(state.range(0));
  Result<Scene> scene = make_builtin_scene("plane");
  RenderOptions opt;
  opt.width = 1920;
  opt.height = 1080;
  opt.threads = threads;
  opt.technique = technique;
  Result<Plan> plan = make_plan(*scene, opt);
  auto backend = make_cpu_backend(threads);
  uint64_t fragments = 0;
  (void)backend->render(*scene, *plan, opt);  // warm-up
  for (auto _ : state) {
    Result<RenderResult> r = backend->render(*scene, *plan, opt);
    fragments += r->passes[0].raster.work.fragments;
    benchmark::DoNotOptimize(r->framebuffer.color.pixels.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(fragments));
}

void BM_Raster_Flat(benchmark::State& state) { run_plane(state, "flat"); }
void BM_Raster_Normal(benchmark::State& state) { run_plane(state, "normal"); }

BENCHMARK(BM_Raster_Flat)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Raster_Normal)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace relief

BENCHMARK_MAIN();
