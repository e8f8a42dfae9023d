// Fur and grass (issue 27, docs/fur.md): the steep parallax poster's claim that its fur is faster
// than the shell method at comparable quality, as whole frames of the built-in `fur` and `grass`
// scenes at 1024x768 on 2 threads. Steep parallax with the poster's depth-darkening self-shadow
// at 16, 32 and 64 planes against `shells` at 16, 32, 64 and 128 layers (the same darkening).
// Each iteration is one frame (shadow pass and main pass); counters: ns_per_pixel (frame time per
// covered pixel: every layer a pixel's shells shade is its cost) and fragments_per_pixel (shaded
// fragments per covered pixel: 1 for steep, the overdraw for shells). The quality of each setting
// against the 256-plane reference is measured by tests/frames/fur_test.cpp (FurScenes.*).
#include "bench/bench_util.h"

namespace relief {
namespace {

// The settings, each run on both scenes.
const TechniqueCase kSettings[] = {
    {"Steep16", "steep_parallax", {{"steps", "16"}, {"shadow", "depth"}}},
    {"Steep32", "steep_parallax", {{"steps", "32"}, {"shadow", "depth"}}},
    {"Steep64", "steep_parallax", {{"steps", "64"}, {"shadow", "depth"}}},
    {"Shells16", "shells", {{"layers", "16"}}},
    {"Shells32", "shells", {{"layers", "32"}}},
    {"Shells64", "shells", {{"layers", "64"}}},
    {"Shells128", "shells", {{"layers", "128"}}},
};

// Covered pixels of one untimed frame of `scene_name` with c's technique.
double covered_pixels(const char* scene_name, const TechniqueCase& c) {
  Result<Scene> scene = make_builtin_scene(scene_name);
  if (!scene.ok()) return 0.0;
  RenderOptions opt;
  opt.width = c.width;
  opt.height = c.height;
  opt.technique = c.technique;
  opt.params = c.params;
  Renderer renderer(make_cpu_backend({.threads = 2}));
  Result<Frame> f = renderer.render(*scene, opt);
  if (!f.ok()) return 0.0;
  double n = 0.0;
  for (float d : f->result.framebuffer.depth.values) n += d > 0.0f ? 1.0 : 0.0;
  return n;
}

void run_scene(benchmark::State& state, const char* scene_name, const TechniqueCase& c) {
  const WorkCounters work = time_technique(state, scene_name, c);
  const double pixels = covered_pixels(scene_name, c);
  if (work.fragments == 0 || pixels == 0.0) return;
  const double frames = static_cast<double>(state.iterations());
  const double ns = state.counters["ns_per_fragment"] * static_cast<double>(work.fragments);
  state.counters["ns_per_pixel"] = ns / (pixels * frames);
  state.counters["fragments_per_pixel"] = static_cast<double>(work.fragments) / (pixels * frames);
}

}  // namespace
}  // namespace relief

int main(int argc, char** argv) {
  for (const char* scene : {"fur", "grass"})
    for (const relief::TechniqueCase& c : relief::kSettings)
      benchmark::RegisterBenchmark(
          (std::string("BM_") + (scene[0] == 'f' ? "Fur_" : "Grass_") + c.name).c_str(),
          [scene, &c](benchmark::State& s) { relief::run_scene(s, scene, c); })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
  return relief::run_registered_benchmarks(argc, argv);
}
