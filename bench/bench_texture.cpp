// Texture sampling throughput: samples per second for the relief-search hot path (sample_r_lod),
// full RGBA sampling, anisotropic gradients, raw fetches and mip generation. A 512x512 texture with
// a full mip chain; uv walks a short ray-like path (coherent, as in a linear search) with a
// per-iteration jitter so the work cannot be hoisted.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "rasterizer/texture.h"

namespace relief {
namespace {

constexpr int kSize = 512;
constexpr int kBatch = 1024;  // samples per benchmark iteration

Texture bench_texture(TexFormat f, ColorSpace cs = ColorSpace::kLinear) {
  const int ch = format_channels(f);
  std::vector<float> v(static_cast<size_t>(kSize) * kSize * ch);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      for (int c = 0; c < ch; ++c)
        v[(static_cast<size_t>(y) * kSize + x) * ch + c] =
            0.5f + 0.4f * std::sin(0.05f * x + 0.3f * c) * std::cos(0.07f * y);
  Texture t = Texture::from_floats(f, kSize, kSize, v.data(), cs);
  t.generate_mips();
  return t;
}

// Coherent uv path: kBatch steps along a slanted line, as a linear search marches.
std::vector<glm::vec2> ray_path() {
  std::vector<glm::vec2> uv(kBatch);
  for (int i = 0; i < kBatch; ++i) uv[i] = glm::vec2(0.1f + 0.0007f * i, 0.2f + 0.0003f * i);
  return uv;
}

void sample_r(benchmark::State& state, TexFormat f, Filter filter, float lod) {
  const Texture t = bench_texture(f);
  SamplerState s;
  s.filter = filter;
  const std::vector<glm::vec2> uv = ray_path();
  float jitter = 0.0f;
  for (auto _ : state) {
    float acc = 0.0f;
    for (int i = 0; i < kBatch; ++i) acc += sample_r_lod(t, s, uv[i] + jitter, lod);
    benchmark::DoNotOptimize(acc);
    jitter = jitter > 0.5f ? 0.0f : jitter + 1e-4f;
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
}

void BM_Texture_SampleRLod_Bilinear(benchmark::State& state) {
  sample_r(state, TexFormat::kR8, Filter::kBilinear, 0.0f);
}
void BM_Texture_SampleRLod_BilinearR16(benchmark::State& state) {
  sample_r(state, TexFormat::kR16, Filter::kBilinear, 0.0f);
}
void BM_Texture_SampleRLod_BilinearR32F(benchmark::State& state) {
  sample_r(state, TexFormat::kR32F, Filter::kBilinear, 0.0f);
}
void BM_Texture_SampleRLod_Trilinear(benchmark::State& state) {
  sample_r(state, TexFormat::kR8, Filter::kTrilinear, 1.4f);
}
void BM_Texture_SampleRLod_Nearest(benchmark::State& state) {
  sample_r(state, TexFormat::kR8, Filter::kNearest, 0.0f);
}
// The alpha-as-depth layout (RGB normal, A depth) reads channel 0 of an RGBA8 texture.
void BM_Texture_SampleRLod_BilinearRGBA8(benchmark::State& state) {
  sample_r(state, TexFormat::kRGBA8, Filter::kBilinear, 0.0f);
}

void BM_Texture_SampleLod_TrilinearRGBA8(benchmark::State& state) {
  const Texture t = bench_texture(TexFormat::kRGBA8);
  SamplerState s;
  s.filter = Filter::kTrilinear;
  const std::vector<glm::vec2> uv = ray_path();
  float jitter = 0.0f;
  for (auto _ : state) {
    glm::vec4 acc(0.0f);
    for (int i = 0; i < kBatch; ++i) acc += sample_lod(t, s, uv[i] + jitter, 1.4f);
    benchmark::DoNotOptimize(acc);
    jitter = jitter > 0.5f ? 0.0f : jitter + 1e-4f;
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
}

void BM_Texture_SampleGrad_Anisotropic(benchmark::State& state) {
  const Texture t = bench_texture(TexFormat::kRGBA8);
  SamplerState s;
  s.filter = Filter::kAnisotropic;
  const std::vector<glm::vec2> uv = ray_path();
  // A 4:1 footprint, 4 texels long: four trilinear probes at lod 0.
  const glm::vec2 dx(4.0f / kSize, 0.0f), dy(0.0f, 1.0f / kSize);
  float jitter = 0.0f;
  for (auto _ : state) {
    glm::vec4 acc(0.0f);
    for (int i = 0; i < kBatch; ++i) acc += sample_grad(t, s, uv[i] + jitter, dx, dy);
    benchmark::DoNotOptimize(acc);
    jitter = jitter > 0.5f ? 0.0f : jitter + 1e-4f;
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
}

void BM_Texture_FetchR_R8(benchmark::State& state) {
  const Texture t = bench_texture(TexFormat::kR8);
  int x0 = 0;
  for (auto _ : state) {
    float acc = 0.0f;
    for (int i = 0; i < kBatch; ++i)
      acc += t.fetch_r(0, (x0 + i) & (kSize - 1), (i >> 3) & (kSize - 1));
    benchmark::DoNotOptimize(acc);
    x0 = (x0 + 1) & (kSize - 1);
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
}

void BM_Texture_GenerateMips_R8(benchmark::State& state) {
  Texture t = bench_texture(TexFormat::kR8);
  for (auto _ : state) {
    t.generate_mips(MipReduce::kAverage);
    benchmark::DoNotOptimize(t.level(1).data.data());
  }
  state.SetItemsProcessed(state.iterations() * kSize * kSize);  // level-0 texels
}

// A colour texture as glTF base colours are: RGBA8, sRGB (each level decoded, averaged in linear
// light and encoded again).
void BM_Texture_GenerateMips_RGBA8Srgb(benchmark::State& state) {
  Texture t = bench_texture(TexFormat::kRGBA8, ColorSpace::kSRGB);
  for (auto _ : state) {
    t.generate_mips(MipReduce::kAverage);
    benchmark::DoNotOptimize(t.level(1).data.data());
  }
  state.SetItemsProcessed(state.iterations() * kSize * kSize);  // level-0 texels
}

BENCHMARK(BM_Texture_SampleRLod_Bilinear);
BENCHMARK(BM_Texture_SampleRLod_BilinearR16);
BENCHMARK(BM_Texture_SampleRLod_BilinearR32F);
BENCHMARK(BM_Texture_SampleRLod_BilinearRGBA8);
BENCHMARK(BM_Texture_SampleRLod_Trilinear);
BENCHMARK(BM_Texture_SampleRLod_Nearest);
BENCHMARK(BM_Texture_SampleLod_TrilinearRGBA8);
BENCHMARK(BM_Texture_SampleGrad_Anisotropic);
BENCHMARK(BM_Texture_FetchR_R8);
BENCHMARK(BM_Texture_GenerateMips_R8)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Texture_GenerateMips_RGBA8Srgb)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace relief

BENCHMARK_MAIN();
