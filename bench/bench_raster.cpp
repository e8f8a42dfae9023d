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

#include <glm/geometric.hpp>

#include "base/simd.h"
#include "builtin/builtin.h"
#include "gl/gl_backend.h"
#include "render/render.h"
#include "render/renderer.h"
#include "sweep/sweep.h"

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

// Arguments: threads, recycle (0: a new framebuffer every frame, as a one-frame render has).
void run_frame(benchmark::State& state, const Scene& scene, const RenderOptions& options) {
  const int threads = static_cast<int>(state.range(0));
  const bool recycle = state.range(1) != 0;  // hand each frame back: no allocation per frame
  Renderer renderer(make_cpu_backend({.threads = threads}));
  Result<Plan> plan = renderer.plan(scene, options);
  if (!plan.ok()) {
    state.SkipWithError(plan.status().message().c_str());
    return;
  }
  uint64_t fragments = 0;
  double setup_ms = 0.0, raster_ms = 0.0, other_ms = 0.0;
  (void)renderer.execute(scene, *plan);  // warm-up
  for (auto _ : state) {
    Result<RenderResult> r = renderer.execute(scene, *plan);
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

void run_plane(benchmark::State& state, const char* technique) {
  run_frame(state, *make_builtin_scene("plane"), plane_options(technique));
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
// The CPU side of `relief bench`'s appendix yardstick (sweep.h appendix_lean; issue 26, goal 3):
// a field (0: `bricks`, 1: `pattern`, whose rays go deeper) at 30 degrees, 1920x1080, `relief`
// 10+5 lod=zero without self-shadow, shadows or depth writes. Its items are the fragments shaded
// (the covered pixels).
void BM_Raster_ReliefLean(benchmark::State& state) {
  Result<sweep::Field> field = sweep::builtin_field(state.range(2) == 0 ? "bricks" : "pattern");
  if (!field.ok()) {
    state.SkipWithError(field.status().message().c_str());
    return;
  }
  const sweep::AppendixLean lean =
      sweep::appendix_lean(sweep::view_scene(*field, 30.0, 1920, 1080), 1920, 1080);
  run_frame(state, lean.scene, lean.options);
}

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
BENCHMARK(BM_Raster_ReliefLean)
    ->ArgsProduct({{1, 2}, {1}, {0, 1}})
    ->ArgNames({"threads", "recycle", "field"})
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

// The heavy-mesh frame (issue 26, goal 7; scripts/make-grid-gltf.py writes it as a glTF file):
// a 2 m square grid of 1000 x 1000 quads (2 M triangles, 1 M vertices), `flat`, seen at 45
// degrees from 4.2 m at 1920x1080, where it covers about 270 k pixels and most triangles hold no
// pixel centre.
Scene grid_scene() {
  constexpr int kCells = 1000;
  constexpr float kSide = 2.0f;
  Scene s;
  s.name = "grid";
  Mesh m;
  m.name = "grid";
  const int n = kCells + 1;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float u = static_cast<float>(i) / kCells, v = static_cast<float>(j) / kCells;
      m.positions.emplace_back((u - 0.5f) * kSide, 0.0f, (v - 0.5f) * kSide);
      m.normals.emplace_back(0.0f, 1.0f, 0.0f);
      m.uvs.emplace_back(u, v);
    }
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const uint32_t a = static_cast<uint32_t>(j * n + i), b = a + 1, c = a + n, d = c + 1;
      m.indices.insert(m.indices.end(), {a, c, b, b, c, d});  // counter-clockwise from +y
    }
  s.meshes.push_back(std::move(m));
  Material flat;
  flat.name = "flat";
  flat.technique = "flat";
  flat.base_color = glm::vec4(0.8f, 0.7f, 0.5f, 1.0f);
  s.materials.push_back(flat);
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  Light sun;
  sun.direction = glm::normalize(glm::vec3(-0.6f, -0.7f, -0.4f));
  sun.color = glm::vec3(2.0f);
  s.lights.push_back(sun);
  Camera cam;
  cam.position = glm::vec3(0.0f, 3.0f, 3.0f);
  cam.yfov_deg = 45.84f;  // the glTF file's 0.8 rad
  cam.zfar = 50.0f;
  s.cameras.push_back(cam);
  return s;
}

RenderOptions grid_options() {
  RenderOptions opt;
  opt.width = 1920;
  opt.height = 1080;
  return opt;
}

// CPU: triangles per second of the main pass (items), its setup and raster parts and the frame.
void BM_Raster_Grid(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const Scene scene = grid_scene();
  Renderer renderer(make_cpu_backend({.threads = threads}));
  Result<Plan> plan = renderer.plan(scene, grid_options());
  uint64_t triangles = 0;
  double setup_ms = 0.0, raster_ms = 0.0, pass_ms = 0.0, frame_ms = 0.0;
  (void)renderer.execute(scene, *plan);  // warm-up
  for (auto _ : state) {
    Result<RenderResult> r = renderer.execute(scene, *plan);
    for (const PassStats& p : r->passes) {
      triangles += p.raster.triangles_in;
      setup_ms += p.raster.setup_ms;
      raster_ms += p.raster.raster_ms;
      pass_ms += p.ms;
    }
    frame_ms += r->frame_ms;
    renderer.recycle(std::move(r).value());
  }
  state.SetItemsProcessed(static_cast<int64_t>(triangles));
  const double n = static_cast<double>(state.iterations());
  state.counters["setup_ms"] = setup_ms / n;
  state.counters["raster_ms"] = raster_ms / n;
  state.counters["pass_ms"] = pass_ms / n;
  state.counters["frame_ms"] = frame_ms / n;
  state.SetLabel(simd_level_name(simd_level()));
}
BENCHMARK(BM_Raster_Grid)
    ->ArgsProduct({{1, 2}})
    ->ArgNames({"threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// GL, steady state: the frame's wall time (the geometry cached since the warm-up frame), with the
// main pass and the frame/pass ratio as counters. Arg: 0 GPU interpolation, 1 the CPU's planes.
void BM_Raster_Grid_GL(benchmark::State& state) {
  const Scene scene = grid_scene();
  BackendConfig config;
  if (state.range(0)) config.gl_interpolation = GlInterpolation::kCpuPlanes;
  auto backend = make_gl_backend(config);
  if (!backend) {
    state.SkipWithError(backend.status().message().c_str());
    return;
  }
  Renderer renderer(std::move(backend).value());
  Result<Plan> plan = renderer.plan(scene, grid_options());
  (void)renderer.execute(scene, *plan);  // warm-up: compile, upload
  double pass_ms = 0.0, frame_ms = 0.0, geometry_ms = 0.0;
  for (auto _ : state) {
    Result<RenderResult> r = renderer.execute(scene, *plan);
    for (const PassStats& p : r->passes) pass_ms += p.ms;
    frame_ms += r->frame_ms;
    geometry_ms += r->geometry_ms;
    state.SetIterationTime(r->frame_ms * 1e-3);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["pass_ms"] = pass_ms / n;
  state.counters["geometry_ms"] = geometry_ms / n;
  state.counters["frame_per_pass"] = pass_ms > 0.0 ? frame_ms / pass_ms : 0.0;
}
BENCHMARK(BM_Raster_Grid_GL)
    ->Arg(0)
    ->Arg(1)
    ->ArgNames({"cpu_planes"})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

}  // namespace
}  // namespace relief

BENCHMARK_MAIN();
