// Cone map and normal map baking: texels per second. Fast bakers at 256, 512 and 1024 (issue 4
// target: 512 x 512 relaxed under 5 s on two threads), the brute-force oracles at 128; the
// bilinear-safe conservative, quad and relaxed maps the cone plugins derive
// (ConeBakeOptions::bilinear). The depth map is smooth bumps plus noise (cones both long and
// short); two threads.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "bake/cone_map.h"
#include "bake/normal_map.h"

namespace relief {
namespace {

constexpr int kThreads = 2;

Texture bench_depth(int n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> noise(0.0f, 1.0f);
  std::vector<float> v(static_cast<size_t>(n) * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const float u = (x + 0.5f) / n, w = (y + 0.5f) / n;
      const float d = 0.5f + 0.3f * std::sin(6.2831853f * 3 * u) * std::cos(6.2831853f * 2 * w) +
                      0.1f * std::sin(6.2831853f * 11 * (u + w)) + 0.05f * noise(rng);
      v[static_cast<size_t>(y) * n + x] = std::fmin(1.0f, std::fmax(0.0f, d));
    }
  return Texture::from_floats(TexFormat::kR32F, n, n, v.data());
}

void run(benchmark::State& state, ConeKind kind, bool brute, bool bilinear = false) {
  const int n = static_cast<int>(state.range(0));
  const Texture depth = bench_depth(n);
  ConeBakeOptions o;
  o.kind = kind;
  o.wrap = true;
  o.threads = kThreads;
  o.bilinear = bilinear;
  for (auto _ : state) {
    ConeRatios r = brute ? bake_cone_ratios_brute_force(depth, o) : bake_cone_ratios(depth, o);
    benchmark::DoNotOptimize(r.values.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(n) * n);
}

void BM_Bake_Conservative(benchmark::State& s) {
  run(s, ConeKind::kConservative, false);
}
void BM_Bake_Quad(benchmark::State& s) {
  run(s, ConeKind::kQuad, false);
}
void BM_Bake_Relaxed(benchmark::State& s) {
  run(s, ConeKind::kRelaxed, false);
}
void BM_Bake_ConservativeBilinear(benchmark::State& s) {
  run(s, ConeKind::kConservative, false, true);
}
void BM_Bake_QuadBilinear(benchmark::State& s) {
  run(s, ConeKind::kQuad, false, true);
}
void BM_Bake_RelaxedBilinear(benchmark::State& s) {
  run(s, ConeKind::kRelaxed, false, true);
}
void BM_Bake_ConservativeBruteForce(benchmark::State& s) {
  run(s, ConeKind::kConservative, true);
}
void BM_Bake_RelaxedBruteForce(benchmark::State& s) {
  run(s, ConeKind::kRelaxed, true);
}

void BM_Bake_NormalMap(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Texture depth = bench_depth(n);
  for (auto _ : state) {
    Texture t = normal_map_from_depth(depth, 0.1f, true);
    benchmark::DoNotOptimize(&t);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(n) * n);
}

BENCHMARK(BM_Bake_Conservative)
    ->Arg(256)
    ->Arg(512)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Bake_Quad)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Bake_Relaxed)
    ->Arg(256)
    ->Arg(512)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Bake_ConservativeBilinear)
    ->Arg(256)
    ->Arg(512)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Bake_QuadBilinear)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Bake_RelaxedBilinear)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Bake_ConservativeBruteForce)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Bake_RelaxedBruteForce)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Bake_NormalMap)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace relief

BENCHMARK_MAIN();
