// The intersection kernels alone (issue 8), isolated from rasterization and shading: each runs on
// a fixed batch of 4096 texture-space rays over the `pattern` depth map (make_pattern_depth, 256 x
// 256, level 0, bilinear, depth_scale 0.05), eight lanes at a time (F8), start uv uniform over the
// tile, azimuth uniform, at the view angle given as the argument (degrees from the normal). Items
// per second are rays; the counters are fetches and search steps per ray, exact counts.
// Kernels: parallax (Kaneko 2001; Welsh 2004), steep parallax (McGuire and McGuire 2005), POM
// (Tatarchuk 2006), relief linear + binary (Policarpo, Oliveira and Comba 2005), conservative cone
// stepping (Dummer 2006), quad-directional and relaxed cone stepping (Policarpo and Oliveira 2007,
// GPU Gems 3 ch. 18) and the exact max-mip reference (after Tevs, Ihrke and Seidel 2008). Full
// frames with shading are bench_techniques.
//
//   build/bin/bench_kernels --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "bench/bench_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "base/simd.h"
#include "builtin/builtin.h"
#include "render/derived_maps.h"
#include "shaders_cpp/cone.h"
#include "shaders_cpp/exact_trace.h"
#include "shaders_cpp/search.h"

#if HWY_ONCE
namespace relief {
namespace {

constexpr int kRays = 4096;
constexpr float kDepthScale = 0.05f;

struct Fixture {
  Material material;  // depth (level 0) and its derived cone maps
  TexturePtr depth, cone, cone_quad, cone_relaxed;
  SamplerState sampler;  // bilinear, repeat
  HeightField field;
  std::vector<float> u, v, dsx, dsy;  // per ray

  Fixture() {
    Texture t = make_pattern_depth(256);
    std::vector<float> d(256 * 256);
    for (int y = 0; y < 256; ++y)
      for (int x = 0; x < 256; ++x) d[y * 256 + x] = t.fetch_r(0, x, y);
    depth = std::make_shared<Texture>(Texture::from_floats(TexFormat::kR8, 256, 256, d.data()));
    sampler.filter = Filter::kBilinear;
    material.name = "pattern";
    material.textures["depth"] = depth;
    material.sampler = sampler;
    cone = derive_map(material, "cone_conservative")->texture;
    cone_quad = derive_map(material, "cone_quad")->texture;
    cone_relaxed = derive_map(material, "cone_relaxed")->texture;
    field = HeightField::from_texture(*depth, sampler);
  }

  void aim(double angle_deg) {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    const float tan_a = static_cast<float>(std::tan(angle_deg * M_PI / 180.0));
    u.resize(kRays);
    v.resize(kRays);
    dsx.resize(kRays);
    dsy.resize(kRays);
    for (int i = 0; i < kRays; ++i) {
      const float az = 2.0f * static_cast<float>(M_PI) * uni(rng);
      u[i] = uni(rng);
      v[i] = uni(rng);
      dsx[i] = std::cos(az) * tan_a * kDepthScale;
      dsy[i] = std::sin(az) * tan_a * kDepthScale;
    }
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

// Runs `search(uv, ds, vz)` over the batch, eight rays at a time, and reports rays per second and
// the kernel's fetches and steps per ray.
template <class Search>
void run(benchmark::State& state, Search&& search) {
  Fixture& f = fixture();
  const double angle = static_cast<double>(state.range(0));
  f.aim(angle);
  const F8 vz(static_cast<float>(-std::cos(angle * M_PI / 180.0)));
  double fetches = 0.0, steps = 0.0, rays = 0.0;
  for (auto _ : state) {
    F8 sum_f(0.0f), sum_s(0.0f), sink(0.0f);
    for (int i = 0; i < kRays; i += 8) {
      const V2<F8> uv{F8::load(&f.u[i]), F8::load(&f.v[i])};
      const V2<F8> ds{F8::load(&f.dsx[i]), F8::load(&f.dsy[i])};
      const SearchHit<F8> h = search(uv, ds, vz);
      sum_f = sum_f + h.fetches;
      sum_s = sum_s + h.steps;
      sink = sink + h.depth + h.uv.x;
    }
    benchmark::DoNotOptimize(sink);
    for (int l = 0; l < 8; ++l) {
      fetches += lane(sum_f, l);
      steps += lane(sum_s, l);
    }
    rays += kRays;
  }
  state.SetItemsProcessed(static_cast<int64_t>(rays));
  state.counters["fetches_per_ray"] = fetches / rays;
  state.counters["steps_per_ray"] = steps / rays;
}

TextureDepth depth_source() {
  TextureDepth d;
  d.texture = fixture().depth.get();
  d.sampler = &fixture().sampler;
  return d;
}
TextureCone cone_source(const TexturePtr& t) {
  TextureCone c;
  c.texture = t.get();
  c.sampler = cone_sampler(fixture().sampler);
  return c;
}
const mask_t<F8> kAll = true_mask<F8>();

void BM_Kernel_Parallax(benchmark::State& state) {
  const TextureDepth d = depth_source();
  run(state,
      [&](V2<F8> uv, V2<F8> ds, F8 vz) { return parallax_offset(d, uv, ds, vz, true, kAll); });
}
void BM_Kernel_SteepParallax(benchmark::State& state) {
  const TextureDepth d = depth_source();
  run(state,
      [&](V2<F8> uv, V2<F8> ds, F8) { return steep_parallax_search(d, uv, ds, F8(32.0f), kAll); });
}
void BM_Kernel_Pom(benchmark::State& state) {
  const TextureDepth d = depth_source();
  run(state, [&](V2<F8> uv, V2<F8> ds, F8) { return pom_search(d, uv, ds, F8(32.0f), kAll); });
}
void BM_Kernel_Relief(benchmark::State& state) {
  const TextureDepth d = depth_source();
  run(state,
      [&](V2<F8> uv, V2<F8> ds, F8) { return relief_search(d, uv, ds, F8(32.0f), 8, kAll); });
}
// The plugins' view-ray fallback floor (plugins/cone_shell.h) over the fixture's depth map.
F8 floor_of(const V2<F8>& ds) {
  return half_texel_along(fixture().depth->width(), fixture().depth->height(), ds);
}
void BM_Kernel_Cone(benchmark::State& state) {
  const TextureDepth d = depth_source();
  const TextureCone c = cone_source(fixture().cone);
  run(state, [&](V2<F8> uv, V2<F8> ds, F8) {
    return cone_search(d, c, uv, ds, 15, 8, 6, floor_of(ds), kAll);
  });
}
void BM_Kernel_ConeQuad(benchmark::State& state) {
  const TextureDepth d = depth_source();
  QuadTextureCone c;
  c.texture = fixture().cone_quad.get();
  c.sampler = cone_sampler(fixture().sampler);
  run(state, [&](V2<F8> uv, V2<F8> ds, F8) {
    QuadTextureCone aimed = c;
    aimed.aim(ds);
    return cone_search(d, aimed, uv, ds, 15, 8, 6, floor_of(ds), kAll);
  });
}
void BM_Kernel_RelaxedCone(benchmark::State& state) {
  const TextureDepth d = depth_source();
  const TextureCone c = cone_source(fixture().cone_relaxed);
  run(state, [&](V2<F8> uv, V2<F8> ds, F8) {
    return cone_search(d, c, uv, ds, 15, 8, 6, floor_of(ds), kAll);
  });
}
void BM_Kernel_Exact(benchmark::State& state) {
  const HeightField& field = fixture().field;
  run(state, [&](V2<F8> uv, V2<F8> ds, F8) { return exact_search(field, uv, ds, kAll); });
}

// The depth read alone: kReads lanes at independent uvs read kLanes at a time through one
// TextureDepth, as a search step makes them (no search), and the colour read a shaded fragment
// makes twice (base colour and normal map). Both loops are compiled for every SIMD target (the
// per-target section at the end of this file) and run at the level in use (base/simd.h;
// RELIEF_SIMD=baseline|avx2|avx512 picks one): the benchmark's label names it. Items are reads
// of 8 lanes (a 16-lane read counts as two), so levels compare per fragment.
constexpr int kReads = 4096;
float reads_planned(const Texture& t, const SamplerState& s, const float* u, const float* v);
float reads_unplanned(const Texture& t, const SamplerState& s, const float* u, const float* v);
template <class Loop>
void run_reads(benchmark::State& state, Loop&& loop) {
  Fixture& f = fixture();
  f.aim(45.0);
  for (auto _ : state) {
    float sink = loop(*f.depth, f.sampler, f.u.data(), f.v.data());
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * (kReads / 8));
  state.SetLabel(simd_level_name(simd_level()));
}
void BM_Kernel_DepthReadUnplanned(benchmark::State& state) {
  run_reads(state, reads_unplanned);
}
void BM_Kernel_DepthRead(benchmark::State& state) {
  run_reads(state, reads_planned);
}
BENCHMARK(BM_Kernel_DepthReadUnplanned);
BENCHMARK(BM_Kernel_DepthRead);

// texture_grad of a 512 x 512 RGBA8 texture (random texels, sRGB or linear, trilinear, repeat),
// one 8-lane read per 2 x 4 pixel packet (a 16-lane read covers two), packets in 64 x 64 pixel
// tiles over 1024 x 1024 pixels (as the rasterizer walks them), uv derivatives 1/1024 (magnified:
// one level) or 1/300 (two levels).
struct ColorReads {
  Texture texture;
  std::vector<float> u, v;  // 8 lanes per packet
  explicit ColorReads(ColorSpace cs) {
    std::mt19937 rng(5);
    std::vector<uint8_t> texels(512 * 512 * 4);
    for (auto& b : texels) b = static_cast<uint8_t>(rng());
    texture = Texture(TexFormat::kRGBA8, 512, 512, texels.data(), cs);
    texture.generate_mips();
    for (int ty = 0; ty < 1024; ty += 64)
      for (int tx = 0; tx < 1024; tx += 64)
        for (int py = ty; py < ty + 64; py += 2)
          for (int px = tx; px < tx + 64; px += 4)
            for (int k = 0; k < 8; ++k) {
              u.push_back((static_cast<float>(px + (k & 3)) + 0.5f) / 1024.0f);
              v.push_back((static_cast<float>(py + (k >> 2)) + 0.5f) / 1024.0f);
            }
  }
};
float color_reads(const Texture& t, const float* u, const float* v, size_t n, float step);
void BM_Kernel_ColorRead(benchmark::State& state) {
  static const ColorReads srgb(ColorSpace::kSRGB), linear(ColorSpace::kLinear);
  const ColorReads& c = state.range(0) ? srgb : linear;
  const float step = 1.0f / static_cast<float>(state.range(1));
  for (auto _ : state)
    benchmark::DoNotOptimize(color_reads(c.texture, c.u.data(), c.v.data(), c.u.size(), step));
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(c.u.size() / 8));
  state.SetLabel(simd_level_name(simd_level()));
}
BENCHMARK(BM_Kernel_ColorRead)
    ->ArgNames({"srgb", "px_per_uv"})
    ->Args({1, 1024})
    ->Args({0, 1024})
    ->Args({1, 300})
    ->Unit(benchmark::kMicrosecond);

#define RELIEF_KERNEL_BENCH(name) BENCHMARK(name)->Arg(45)->Arg(80)->Unit(benchmark::kMicrosecond)
RELIEF_KERNEL_BENCH(BM_Kernel_Parallax);
RELIEF_KERNEL_BENCH(BM_Kernel_SteepParallax);
RELIEF_KERNEL_BENCH(BM_Kernel_Pom);
RELIEF_KERNEL_BENCH(BM_Kernel_Relief);
RELIEF_KERNEL_BENCH(BM_Kernel_Cone);
RELIEF_KERNEL_BENCH(BM_Kernel_ConeQuad);
RELIEF_KERNEL_BENCH(BM_Kernel_RelaxedCone);
RELIEF_KERNEL_BENCH(BM_Kernel_Exact);

}  // namespace
}  // namespace relief
#endif  // HWY_ONCE

// ---- the read loops, once per SIMD target ----
HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

// The sum of the reads, through the plan (kPlanned) or the whole sampler per read (level choice
// per read, as before RLodPlan).
template <bool kPlanned>
float sum_reads(const Texture& t, const SamplerState& s, const float* u, const float* v, int n) {
  TextureDepth d;
  d.texture = &t;
  d.sampler = &s;
  FN acc(0.0f);
  const FN lod = FN::load(d.lod);
  for (int i = 0; i + kLanes <= n; i += kLanes) {
    const V2<FN> uv(FN::load(u + i), FN::load(v + i));
    if constexpr (kPlanned)
      acc = acc + d.lanes(uv);
    else
      acc = acc + texture_r_lod_lanes(t, s, uv, lod);
  }
  return lane(acc, 0) + lane(acc, kLanes - 1);
}
float reads_planned_target(const Texture& t, const SamplerState& s, const float* u, const float* v,
                           int n) {
  return sum_reads<true>(t, s, u, v, n);
}
float reads_unplanned_target(const Texture& t, const SamplerState& s, const float* u,
                             const float* v, int n) {
  return sum_reads<false>(t, s, u, v, n);
}
// relaxed_cone's view-ray search (15 cone steps, 32 fallback, 6 halvings) at the native lanes
// over the rays u, v, dx, dy: one packet at a time (cone_search) or two side by side
// (cone_search_pair, as the cone plugins' lane loop runs it). Returns the sum of the hit depths.
float cone_searches_target(const Texture& depth, const Texture& cone, const SamplerState& s,
                           const float* u, const float* v, const float* dx, const float* dy, int n,
                           bool paired) {
  TextureDepth d[2];
  TextureCone c[2];
  for (int p = 0; p < 2; ++p) {
    d[p].texture = &depth;
    d[p].sampler = &s;
    c[p].texture = &cone;
    c[p].sampler = cone_sampler(s);
  }
  const float w = static_cast<float>(depth.width());
  FN acc(0.0f);
  const int step = paired ? 2 * kLanes : kLanes;
  for (int i = 0; i + step <= n; i += step) {
    const auto ray = [&](int p) {
      const int at = i + p * kLanes;
      const V2<FN> ds(FN::load(dx + at), FN::load(dy + at));
      return ConeRay<FN, TextureDepth, TextureCone>{
          &d[p],
          &c[p],
          V2<FN>(FN::load(u + at), FN::load(v + at)),
          ds,
          half_texel_along(static_cast<int>(w), static_cast<int>(w), ds),
          true_mask<FN>()};
    };
    if (paired) {
      SearchHit<FN> a, b;
      cone_search_pair(ray(0), ray(1), 15, 32, 6, a, b);
      acc = acc + a.depth + b.depth;
    } else {
      const ConeRay<FN, TextureDepth, TextureCone> r = ray(0);
      acc =
          acc + cone_search(*r.depth, *r.cone, r.uv, r.ds, 15, 32, 6, r.view_floor, r.active).depth;
    }
  }
  return lane(acc, 0) + lane(acc, kLanes - 1);
}
float color_reads_target(const Texture& t, const float* u, const float* v, size_t n, float step) {
  SamplerState s;
  s.filter = Filter::kTrilinear;
  const V2<FN> dx(FN(step), FN(0.0f)), dy(FN(0.0f), FN(step));
  FN acc(0.0f);
  for (size_t i = 0; i + kLanes <= n; i += kLanes) {
    const V2<FN> uv(FN::load(&u[i]), FN::load(&v[i]));
    const V4<FN> rgba = texture_grad_lanes(t, s, uv, dx, dy);
    acc = acc + rgba.x + rgba.w;
  }
  return lane(acc, 0) + lane(acc, kLanes - 1);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {
namespace {
HWY_EXPORT(reads_planned_target);
HWY_EXPORT(reads_unplanned_target);
HWY_EXPORT(color_reads_target);
HWY_EXPORT(cone_searches_target);
// relaxed_cone's view-ray search over the fixture's rays at the SIMD level in use, one packet at a
// time (paired:0) or two side by side (paired:1, what the cone plugins run): rays per second.
void BM_Kernel_RelaxedConeLanes(benchmark::State& state) {
  Fixture& f = fixture();
  f.aim(static_cast<double>(state.range(1)));
  for (auto _ : state)
    benchmark::DoNotOptimize(HWY_DYNAMIC_DISPATCH(cone_searches_target)(
        *f.depth, *f.cone_relaxed, f.sampler, f.u.data(), f.v.data(), f.dsx.data(), f.dsy.data(),
        kRays, state.range(0) != 0));
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * kRays);
  state.SetLabel(simd_level_name(simd_level()));
}
BENCHMARK(BM_Kernel_RelaxedConeLanes)
    ->ArgNames({"paired", "deg"})
    ->Args({0, 45})
    ->Args({1, 45})
    ->Args({0, 80})
    ->Args({1, 80})
    ->Unit(benchmark::kMicrosecond);
float reads_planned(const Texture& t, const SamplerState& s, const float* u, const float* v) {
  return HWY_DYNAMIC_DISPATCH(reads_planned_target)(t, s, u, v, kReads);
}
float reads_unplanned(const Texture& t, const SamplerState& s, const float* u, const float* v) {
  return HWY_DYNAMIC_DISPATCH(reads_unplanned_target)(t, s, u, v, kReads);
}
float color_reads(const Texture& t, const float* u, const float* v, size_t n, float step) {
  return HWY_DYNAMIC_DISPATCH(color_reads_target)(t, u, v, n, step);
}
}  // namespace
}  // namespace relief

BENCHMARK_MAIN();
#endif  // HWY_ONCE
