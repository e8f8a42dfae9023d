// Cost of relief mapping with correct silhouettes (Oliveira and Policarpo 2005): relief_quadric
// with the accurate (equation 6) and approximate (equation 7) distances against plain relief on
// the `torus` scene at 1024 x 768, 2 threads, the same 32 + 8 search; and the per-vertex quadric
// fit (scene/mesh_prep.h) of a 100k-vertex torus.
#include <benchmark/benchmark.h>

#include <chrono>
#include <map>
#include <string>

#include "render/render.h"
#include "scene/builtin.h"
#include "scene/builtin_curved.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

struct Case {
  const char* name;
  const char* technique;
  std::map<std::string, std::string> params;
};

const std::map<std::string, std::string> kSearch = {
    {"steps", "32"}, {"min_steps", "32"}, {"binary_steps", "8"}};
std::map<std::string, std::string> with(std::map<std::string, std::string> p, const char* k,
                                        const char* v) {
  p[k] = v;
  return p;
}

const Case kCases[] = {
    {"Relief_32_8", "relief", kSearch},
    {"Quadric_Approximate_32_8", "relief_quadric", with(kSearch, "distance", "approximate")},
    {"Quadric_Accurate_32_8", "relief_quadric", with(kSearch, "distance", "accurate")},
};

void run_case(benchmark::State& state, const Case& c) {
  Result<Scene> scene = make_builtin_scene("torus");
  RenderOptions opt;
  opt.width = 1024;
  opt.height = 768;
  opt.threads = 2;
  opt.technique = c.technique;
  opt.params = c.params;
  Result<Plan> plan = make_plan(*scene, opt);
  if (!scene.ok() || !plan.ok()) {
    state.SkipWithError(plan.ok() ? "no scene" : plan.status().message().c_str());
    return;
  }
  auto backend = make_cpu_backend(opt.threads);
  (void)backend->render(*scene, *plan, opt);
  WorkCounters work;
  double ns = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    Result<RenderResult> r = backend->render(*scene, *plan, opt);
    ns += std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
    if (!r.ok()) {
      state.SkipWithError(r.status().message().c_str());
      return;
    }
    for (const PassStats& p : r->passes) work += p.raster.work;
    benchmark::DoNotOptimize(r->framebuffer.color.pixels.data());
    backend->recycle(std::move(r).value());
  }
  const double f = static_cast<double>(work.fragments);
  if (f == 0.0) return;
  state.counters["ns_per_fragment"] = ns / f;
  state.counters["steps_per_fragment"] = static_cast<double>(work.search_steps) / f;
  state.counters["discarded_per_fragment"] = static_cast<double>(work.discarded) / f;
  state.SetItemsProcessed(static_cast<int64_t>(work.fragments));
}

// 316 x 316 cells: 317^2 = 100489 vertices.
void BM_QuadricFit_100k(benchmark::State& state) {
  const Mesh base = parametric_mesh("torus", torus_surface(1.0f, 0.4f), 316, 316, {8, 2});
  for (auto _ : state) {
    Mesh m = base;
    compute_quadrics(m);
    benchmark::DoNotOptimize(m.quadric.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(base.positions.size()));
}
BENCHMARK(BM_QuadricFit_100k)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace relief

int main(int argc, char** argv) {
  for (const relief::Case& c : relief::kCases)
    benchmark::RegisterBenchmark((std::string("BM_Torus_") + c.name).c_str(),
                                 [&c](benchmark::State& s) { relief::run_case(s, c); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
