// The GL backend against the CPU backend: every built-in scene with every technique that has a
// GLSL twin, rendered at 256x192 by both, as the scene is authored and, for techniques with
// effects, with every material forced to each combination of self_shadow and depth_write; shadow
// passes as the planner makes them, sized to the view (--shadow-size view: room's spot light a
// 498^2 map where the light asks for 1024^2, teatime 822^2, materials 785^2; relief casters
// writing their corrected depth from the light, every material receiving), so the same plan
// drives both. The backends read the map the plan sizes whatever its size; the view's size
// keeps the run short (room's agreement took 265 s of a CI run with the light's 1024^2).
// Metric (render/compare.h, sRGB-encoded RGB): PSNR >= 35 dB and at most 0.5% of the pixels with
// a channel off by more than 8/255. Depth: where both cover a pixel and both searches took the same
// path to the same relief point (the same step count, hit uv within 1e-4, hit depth within 5e-4
// depth units), the view depths
// (recovered from the reversed-Z buffer through the camera's projection) agree within 1e-4 world
// units. Pixels covered by one backend only, pixels whose searches ended at different points with
// view depths more than 1e-4 apart, and same-path pixels over the depth bound count against the
// same 0.5% budget (different end points whose view depths agree within 1e-4 meet the bound).
// Different hits cannot be ruled out between two rasterisers: both interpolate uv within ~2.5e-5 of
// the exact value on the near-clipped plane (measured against the analytic ray-plane uv; neither is
// closer), and a relief hit jumps along every step contour of a linear search and every silhouette
// of the height field, so a pixel on such a line can land on either side in either backend. Work
// counters (GL counts them with atomics when asked) agree within 1%.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "builtin/builtin.h"
#include "gl/gl_backend.h"
#include "plugins/registry.h"
#include "render/compare.h"
#include "tests/gl/gl_agreement.h"
#include "tests/gl/gl_test_util.h"

namespace relief {
namespace {

constexpr int kWidth = 256;
constexpr int kHeight = 192;
using gl::testing::kMaxOverFraction;
using gl::testing::kMinPsnr;
using gl::testing::kThreshold;
constexpr double kMaxViewDepthError = 1e-4;
constexpr double kMaxCounterDifference = 0.01;

// View-space distance along the view axis for a reversed-Z depth value d (> 0).
double view_depth(const glm::mat4& p, float d) {
  // clip.z = A z + B, clip.w = C z + D for the camera's perspective or orthographic matrix.
  const double a = p[2][2], b = p[3][2], c = p[2][3], dd = p[3][3];
  const double z = (d * dd - b) / (a - d * c);
  return -z;
}

struct DepthAgreement {
  size_t coverage_mismatch = 0;
  size_t hit_mismatch = 0;  // both covered, different relief points, view depths off by > 1e-4
  size_t other_hit_same_depth = 0;  // different relief points, view depths still within 1e-4
  size_t both = 0;
  double max_error = 0.0;
  size_t over = 0;  // both covered, same hit, error above the bound
};

constexpr float kSameHitDepth = 5e-4f;  // depth-map units
constexpr float kSameHitUv = 1e-4f;

DepthAgreement compare_depth(const Framebuffer& cpu_fb, const Framebuffer& gl_fb,
                             const glm::mat4& proj) {
  const Plane& cpu = cpu_fb.depth;
  const Plane& gl = gl_fb.depth;
  DepthAgreement r;
  for (int y = 0; y < cpu.height; ++y)
    for (int x = 0; x < cpu.width; ++x) {
      const float a = cpu.at(x, y), b = gl.at(x, y);
      if ((a > 0.0f) != (b > 0.0f)) {
        ++r.coverage_mismatch;
        continue;
      }
      if (a <= 0.0f) continue;
      const float* ha = cpu_fb.aov_at(x, y);
      const float* hb = gl_fb.aov_at(x, y);
      const int uv = kAovOffset[static_cast<int>(Aov::kHitUv)];
      const int hd = kAovOffset[static_cast<int>(Aov::kHitDepth)];
      const int st = kAovOffset[static_cast<int>(Aov::kSteps)];
      const double e = std::fabs(view_depth(proj, a) - view_depth(proj, b));
      if (ha[st] != hb[st] || std::fabs(ha[hd] - hb[hd]) > kSameHitDepth ||
          std::fabs(ha[uv] - hb[uv]) > kSameHitUv ||
          std::fabs(ha[uv + 1] - hb[uv + 1]) > kSameHitUv) {
        // Cone steps stop short of the surface after `steps` iterations: where the march is
        // slow (grazing rays), inputs 1e-6 apart end a few 1e-4 apart in depth-map units yet
        // still within the view-depth bound, which is the criterion.
        if (e <= kMaxViewDepthError)
          ++r.other_hit_same_depth;
        else
          ++r.hit_mismatch;
        continue;
      }
      ++r.both;
      r.max_error = std::max(r.max_error, e);
      if (e > kMaxViewDepthError) ++r.over;
    }
  return r;
}

// Relative difference of two counts (0 when both are 0).
double relative(uint64_t a, uint64_t b) {
  const double m = static_cast<double>(std::max(a, b));
  return m > 0.0 ? std::fabs(static_cast<double>(a) - static_cast<double>(b)) / m : 0.0;
}

// The scene as authored (-1), then every material forced to self_shadow = bit 0, depth_write =
// bit 1 of the variant.
Scene with_effects(const Scene& authored, int variant) {
  Scene s = authored;
  if (variant >= 0)
    for (Material& m : s.materials) {
      m.self_shadow = (variant & 1) != 0;
      m.depth_write = (variant & 2) != 0;
    }
  return s;
}

// One built-in scene per test (so that ctest runs them side by side and none nears the timeout),
// named by the scene.
class GlAgreementScene : public ::testing::TestWithParam<std::string> {};

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> names;
  for (const BuiltinSceneInfo& info : builtin_scenes()) names.push_back(info.name);
  return names;
}

TEST_P(GlAgreementScene, MatchesCpu) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl =
      make_gl_backend({.count_work = true, .gl_interpolation = GlInterpolation::kCpuPlanes});
  ASSERT_TRUE(gl.ok()) << gl.status().message();
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 0});
  int compared = 0, shadow_passes = 0;
  std::set<EffectMask> variants_seen;
  {
    const std::string& scene_name = GetParam();
    Result<Scene> authored = make_builtin_scene(scene_name);
    ASSERT_TRUE(authored.ok()) << authored.status().message();
    // Each twin forced on every material, then (null) the scene's own techniques: scenes that
    // mix techniques, or whose materials cannot all take one (no depth map), run as authored.
    // A plugin with a `search` choice runs once per search (relief_quadric: linear,
    // relaxed_cone), and once more per further `distance` choice with its default search
    // (relief_quadric: distance=accurate). A run's setting is "name=value" or empty.
    std::vector<std::pair<const PluginDescriptor*, std::string>> runs;
    for (const PluginDescriptor* p : PluginRegistry::global().all()) {
      const int search = param_index(*p, "search");
      const int distance = param_index(*p, "distance");
      if (search < 0) runs.emplace_back(p, "");
      if (search >= 0)
        for (const std::string& choice : split_choices(p->params[search].choices))
          runs.emplace_back(p, "search=" + choice);
      if (distance >= 0) {
        const std::vector<std::string> choices = split_choices(p->params[distance].choices);
        for (size_t c = 1; c < choices.size(); ++c) runs.emplace_back(p, "distance=" + choices[c]);
      }
    }
    runs.emplace_back(nullptr, "");
    for (const auto& run : runs) {
      const PluginDescriptor* plugin = run.first;
      const std::string& setting = run.second;  // (no structured binding: clang 14 and lambdas)
      if (plugin && !gl_has_twin(plugin->name)) continue;
      const bool has_effects =
          !plugin || (plugin->supported_effects & (kEffectSelfShadow | kEffectDepthWrite)) != 0;
      for (int variant = -1; variant < (has_effects ? 4 : 0); ++variant) {
        const Scene scene_v = with_effects(*authored, variant);
        const Scene* scene = &scene_v;
        const std::string label =
            scene_name + " / " + (plugin ? plugin->name : "(its own techniques)") +
            (setting.empty() ? std::string() : " " + setting) +
            (variant < 0
                 ? std::string()
                 : std::string(" (forced") + (variant & 1 ? " self_shadow" : "") +
                       (variant & 2 ? " depth_write" : "") + (variant == 0 ? " none" : "") + ")");
        SCOPED_TRACE(label);
        RenderOptions opt;
        opt.width = kWidth;
        opt.height = kHeight;
        opt.technique = plugin ? plugin->name : "";
        if (!setting.empty())
          opt.params[setting.substr(0, setting.find('='))] = setting.substr(setting.find('=') + 1);
        // A layered technique (shells) at 8 layers here: every layer is a full draw on
        // llvmpipe, and its own agreement test (fur_agreement_test.cpp) covers 16 and 32.
        if (plugin && param_index(*plugin, "layers") >= 0) opt.params["layers"] = "8";
        opt.aovs = aov_bit(Aov::kHitUv) | aov_bit(Aov::kHitDepth) | aov_bit(Aov::kSteps);
        opt.shadow_size = ShadowSize::kView;
        Result<Plan> plan = make_plan(*scene, opt);
        if (!plan.ok()) {
          std::printf("[ skip     ] %s: %s\n", label.c_str(), plan.status().message().c_str());
          continue;
        }
        if (!plugin &&
            std::any_of(plan->materials.begin(), plan->materials.end(),
                        [](const BoundMaterial& m) { return !gl_has_twin(m.plugin->name); })) {
          std::printf("[ skip     ] %s: a technique without a GLSL twin\n", label.c_str());
          continue;
        }
        for (const BoundMaterial& m : plan->materials) variants_seen.insert(m.effects);
        // Whole shadow maps, as GL draws them, so that the shadow passes' counters compare (the
        // image is the same drawn on demand: tests/frames/shadow_test.cpp).
        plan->shadow_on_demand = false;
        Result<RenderResult> rc = cpu->render(*scene, *plan);
        ASSERT_TRUE(rc.ok()) << rc.status().message();
        Result<RenderResult> rg = (*gl)->render(*scene, *plan);
        ASSERT_TRUE(rg.ok()) << rg.status().message();
        const ImageDiff d =
            compare_images(rc->framebuffer.color, rg->framebuffer.color, kThreshold);
        const Camera& cam = scene->cameras[opt.camera];
        const glm::mat4 proj = cam.projection(static_cast<float>(kWidth) / kHeight);
        const DepthAgreement z = compare_depth(rc->framebuffer, rg->framebuffer, proj);
        const double pixels = static_cast<double>(kWidth) * kHeight;
        const double off = static_cast<double>(d.over_count) / pixels;
        const double cov = static_cast<double>(z.coverage_mismatch) / pixels;
        const double hits = static_cast<double>(z.hit_mismatch) / pixels;
        // The main pass is the last one on both backends.
        const WorkCounters& wc = rc->passes.back().raster.work;
        const WorkCounters& wg = rg->passes.back().raster.work;
        ASSERT_EQ(rc->passes.size(), rg->passes.size());
        for (size_t p = 0; p + 1 < rc->passes.size(); ++p) {
          // Shadow passes: relief casters search from the light on both backends.
          const WorkCounters& sc = rc->passes[p].raster.work;
          const WorkCounters& sg = rg->passes[p].raster.work;
          EXPECT_EQ(rc->passes[p].name, rg->passes[p].name);
          shadow_passes += 1;
          // As for the main pass below: relief casters write depth, so where one lies behind a
          // caster drawn earlier (the materials floor behind its spheres) GL counts fragments
          // the CPU rejects early; where GL counts more, the work is not compared.
          if (sg.fragments > sc.fragments) {
            std::printf(
                "[ note     ] %s, %s: GL shaded %llu fragments hidden before its depth "
                "test\n",
                label.c_str(), rc->passes[p].name.c_str(),
                static_cast<unsigned long long>(sg.fragments - sc.fragments));
            continue;
          }
          EXPECT_LE(relative(sc.texture_fetches, sg.texture_fetches), kMaxCounterDifference);
          EXPECT_LE(relative(sc.search_steps, sg.search_steps), kMaxCounterDifference);
        }
        std::printf(
            "[ measure  ] %s: PSNR %.2f dB, RMSE %.5f, max %.1f/255, over 8/255 %.3f%%; "
            "coverage mismatch %.3f%%, other hit %.3f%% (+%.3f%% within 1e-4), view depth max "
            "|err| "
            "%.3g over %zu px "
            "(%zu above 1e-4); fetches cpu %llu gl %llu, steps cpu %llu gl %llu, shadow steps cpu "
            "%llu gl %llu\n",
            label.c_str(), d.psnr_db, d.rmse, d.max_error * 255.0, 100.0 * off, 100.0 * cov,
            100.0 * hits, 100.0 * static_cast<double>(z.other_hit_same_depth) / pixels, z.max_error,
            z.both, z.over, static_cast<unsigned long long>(wc.texture_fetches),
            static_cast<unsigned long long>(wg.texture_fetches),
            static_cast<unsigned long long>(wc.search_steps),
            static_cast<unsigned long long>(wg.search_steps),
            static_cast<unsigned long long>(wc.shadow_steps),
            static_cast<unsigned long long>(wg.shadow_steps));
        EXPECT_GE(d.psnr_db, kMinPsnr);
        EXPECT_LE(off, kMaxOverFraction);
        // Same-path pixels whose view depths differ by more than 1e-4 count against the budget
        // too: depth correction divides by the tangent-space view z, so on a silhouette seen
        // edge-on the two rasterisers' rounding of the interpolated frame grows past the bound
        // (room, one pixel: 2.5e-4). The max error is printed above.
        const double depth_over = static_cast<double>(z.over) / pixels;
        EXPECT_LE(cov + hits + depth_over, kMaxOverFraction);
        EXPECT_GT(z.both, 0u);
        // A variant writing depth is tested early against its polygon depth on the CPU
        // (DepthTest::kConservative); GL runs a shader with side effects (the counting atomics)
        // before any depth test, so where a surface lies behind one drawn earlier (teapot, torus)
        // GL counts the fragments the CPU rejects early. Those variants: GL counts at least the
        // CPU's fragments, and the per-fragment work is compared where no fragment was hidden.
        // The twins that can discard (the plugins supporting kEffectSilhouette: relief_quadric,
        // relief_dual) run without early tests too (common.glsl RELIEF_MAY_DISCARD), and so do
        // MASK materials (the layered `shells` is always MASK).
        bool writes_depth = false;
        for (const BoundMaterial& m : plan->materials)
          writes_depth = writes_depth || m.plugin->depth_output(m.effects) != DepthOutput::kNone ||
                         (m.plugin->supported_effects & kEffectSilhouette) != 0 ||
                         m.uniforms.alpha_mode == AlphaMode::kMask;
        if (writes_depth && wg.fragments != wc.fragments) {
          EXPECT_GT(wg.fragments, wc.fragments);
          std::printf("[ note     ] %s: GL shaded %llu fragments hidden before its depth test\n",
                      label.c_str(), static_cast<unsigned long long>(wg.fragments - wc.fragments));
        } else {
          EXPECT_EQ(wc.fragments, wg.fragments);
          EXPECT_LE(relative(wc.texture_fetches, wg.texture_fetches), kMaxCounterDifference);
          EXPECT_LE(relative(wc.search_steps, wg.search_steps), kMaxCounterDifference);
          EXPECT_LE(relative(wc.shadow_steps, wg.shadow_steps), kMaxCounterDifference);
        }
        ++compared;
      }
    }
  }
  EXPECT_GE(compared, 1);
  // room plans a shadow pass: the comparison ran with shadow maps.
  if (GetParam() == "room") {
    EXPECT_GT(shadow_passes, 0);
  }
  // The relief family ran with and without each effect (on plane, every twin's effects).
  if (GetParam() == "plane") {
    EXPECT_TRUE(variants_seen.count(0));
    EXPECT_TRUE(variants_seen.count(kEffectSelfShadow));
    EXPECT_TRUE(variants_seen.count(kEffectDepthWrite));
    EXPECT_TRUE(variants_seen.count(kEffectSelfShadow | kEffectDepthWrite));
  }
}

INSTANTIATE_TEST_SUITE_P(BuiltinScenes, GlAgreementScene,
                         ::testing::ValuesIn(builtin_scene_names()),
                         [](const ::testing::TestParamInfo<std::string>& i) { return i.param; });

// The searches' `lod` parameter (plugins/relief_shell.h SearchLod) on both backends: `zero` and
// `max-mip` (the derived chain, uploaded from the CPU's texels) agree with the CPU as closely as
// the default does (same metric as above), on `plane`, whose bricks map has mips the camera uses.
// Each mode changes the CPU image against the default (so the parameter reaches the search).
TEST(GlBackend, SearchLodModesMatchCpu) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl =
      make_gl_backend({.gl_interpolation = GlInterpolation::kCpuPlanes});
  ASSERT_TRUE(gl.ok()) << gl.status().message();
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 0});
  Result<Scene> scene = make_builtin_scene("plane");
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  for (const char* technique : {"relief", "pom", "steep_parallax", "relief_quadric"}) {
    RenderOptions opt;
    opt.width = kWidth;
    opt.height = kHeight;
    opt.technique = technique;
    Result<Plan> base_plan = make_plan(*scene, opt);
    ASSERT_TRUE(base_plan.ok()) << base_plan.status().message();
    Result<RenderResult> base = cpu->render(*scene, *base_plan);
    ASSERT_TRUE(base.ok()) << base.status().message();
    for (const char* lod : {"zero", "max-mip"}) {
      SCOPED_TRACE(std::string(technique) + " lod=" + lod);
      opt.params["lod"] = lod;
      Result<Plan> plan = make_plan(*scene, opt);
      ASSERT_TRUE(plan.ok()) << plan.status().message();
      Result<RenderResult> rc = cpu->render(*scene, *plan);
      ASSERT_TRUE(rc.ok()) << rc.status().message();
      Result<RenderResult> rg = (*gl)->render(*scene, *plan);
      ASSERT_TRUE(rg.ok()) << rg.status().message();
      const ImageDiff d = compare_images(rc->framebuffer.color, rg->framebuffer.color, kThreshold);
      const double off =
          static_cast<double>(d.over_count) / (static_cast<double>(kWidth) * kHeight);
      std::printf("[ measure  ] plane / %s lod=%s: PSNR %.2f dB, over 8/255 %.3f%%\n", technique,
                  lod, d.psnr_db, 100.0 * off);
      EXPECT_GE(d.psnr_db, kMinPsnr);
      EXPECT_LE(off, kMaxOverFraction);
      const ImageDiff vs_quad =
          compare_images(base->framebuffer.color, rc->framebuffer.color, kThreshold);
      EXPECT_GT(vs_quad.over_count, 0u) << "lod=" << lod << " renders as lod=quad";
    }
  }
}

TEST(GlBackend, SecondFrameCompilesNothingAndIsIdentical) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl =
      make_gl_backend({.gl_interpolation = GlInterpolation::kCpuPlanes});
  ASSERT_TRUE(gl.ok()) << gl.status().message();
  Result<Scene> scene = make_builtin_scene(default_scene_name());
  ASSERT_TRUE(scene.ok());
  RenderOptions opt;
  opt.width = 64;
  opt.height = 48;
  opt.technique = "flat";
  Result<Plan> plan = make_plan(*scene, opt);
  ASSERT_TRUE(plan.ok());
  Result<RenderResult> a = (*gl)->render(*scene, *plan);
  Result<RenderResult> b = (*gl)->render(*scene, *plan);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_GT(a->compile_ms, 0.0);
  EXPECT_EQ(b->compile_ms, 0.0);
  // every planned pass (shadow passes of the default scene included), main last, each timed
  ASSERT_EQ(b->passes.size(), plan->passes.size());
  EXPECT_EQ(b->passes.back().name, "main");
  for (const PassStats& p : b->passes) EXPECT_GT(p.ms, 0.0) << p.name;
  EXPECT_FALSE(b->device.empty());
  EXPECT_EQ(a->framebuffer.color.pixels, b->framebuffer.color.pixels);
  EXPECT_EQ(a->framebuffer.depth.values, b->framebuffer.depth.values);
}

TEST(GlBackend, ImageIsTopDownAndBackgroundIsCleared) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl =
      make_gl_backend({.gl_interpolation = GlInterpolation::kCpuPlanes});
  ASSERT_TRUE(gl.ok());
  // One triangle in the top half of the view, facing the camera.
  Scene s;
  s.name = "tri";
  Mesh m;
  m.positions = {{-1.0f, 0.1f, 0.0f}, {1.0f, 0.1f, 0.0f}, {0.0f, 0.9f, 0.0f}};
  m.normals.assign(3, glm::vec3(0, 0, 1));
  m.uvs.assign(3, glm::vec2(0));
  m.tangents.assign(3, glm::vec4(1, 0, 0, 1));
  m.indices = {0, 1, 2};  // counter-clockwise seen from +z
  s.meshes.push_back(m);
  Material mat;
  mat.technique = "flat";
  mat.base_color = glm::vec4(1.0f);
  s.materials.push_back(mat);
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  Camera cam;
  cam.position = {0, 0, 3};
  s.cameras.push_back(cam);
  s.ambient = glm::vec3(1.0f);
  s.background = glm::vec4(0.0f, 0.0f, 1.0f, 1.0f);
  RenderOptions opt;
  opt.width = 40;
  opt.height = 30;
  opt.studio_environment = false;  // lit by the ambient colour alone (the scene has no lights)
  Result<Plan> plan = make_plan(s, opt);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  Result<RenderResult> r = (*gl)->render(s, *plan);
  ASSERT_TRUE(r.ok()) << r.status().message();
  const Framebuffer& fb = r->framebuffer;
  // Covered near the top centre, background at the bottom; depth 0 where nothing was drawn.
  EXPECT_GT(fb.depth.at(20, 10), 0.0f);
  EXPECT_EQ(fb.depth.at(20, 25), 0.0f);
  EXPECT_EQ(fb.color.at(20, 25), glm::vec4(0.0f, 0.0f, 1.0f, 1.0f));
  EXPECT_NEAR(fb.color.at(20, 10).r, 1.0f, 1e-5f);  // ambient 1 x albedo 1
  // Seen from behind, the single-sided triangle is culled.
  s.cameras[0].position = {0, 0, -3};
  Result<Plan> back = make_plan(s, opt);
  ASSERT_TRUE(back.ok());
  r = (*gl)->render(s, *back);
  ASSERT_TRUE(r.ok());
  float covered = 0.0f;
  for (float v : r->framebuffer.depth.values) covered += v > 0.0f ? 1.0f : 0.0f;
  EXPECT_EQ(covered, 0.0f);
  // Double-sided: drawn from behind too.
  s.materials[0].double_sided = true;
  Result<Plan> both = make_plan(s, opt);
  ASSERT_TRUE(both.ok());
  r = (*gl)->render(s, *both);
  ASSERT_TRUE(r.ok());
  EXPECT_GT(r->framebuffer.depth.at(20, 10), 0.0f);
}

// Directional (orthographic, fitted) and point (cube of six faces) lights on `room`, whose only
// shadow-casting light is a spot: the spot turned into each kind, CPU and GL from the same plan,
// the same bounds as the built-in comparison; the maps must darken something.
TEST(GlBackend, ShadowPassesOfEveryLightKindMatchCpu) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl =
      make_gl_backend({.gl_interpolation = GlInterpolation::kCpuPlanes});
  ASSERT_TRUE(gl.ok()) << gl.status().message();
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 0});
  Result<Scene> room = make_builtin_scene("room");
  ASSERT_TRUE(room.ok()) << room.status().message();
  int spot = -1;
  for (size_t i = 0; i < room->lights.size(); ++i)
    if (room->lights[i].casts_shadows) spot = static_cast<int>(i);
  ASSERT_GE(spot, 0);
  for (LightType type : {LightType::kSpot, LightType::kDirectional, LightType::kPoint}) {
    Scene scene = *room;
    Light& l = scene.lights[spot];
    l.type = type;
    l.shadow_resolution = 512;
    if (type == LightType::kDirectional)
      l.direction = glm::normalize(glm::vec3(0.4f, -1.0f, -0.3f));
    SCOPED_TRACE(static_cast<int>(type));
    RenderOptions opt;
    opt.width = kWidth;
    opt.height = kHeight;
    Result<Plan> plan = make_plan(scene, opt);
    ASSERT_TRUE(plan.ok()) << plan.status().message();
    ASSERT_EQ(plan->passes.size(), 2u);
    ASSERT_EQ(plan->passes[0].kind, PassPlan::Kind::kShadow);
    Result<RenderResult> rc = cpu->render(scene, *plan);
    Result<RenderResult> rg = (*gl)->render(scene, *plan);
    ASSERT_TRUE(rc.ok() && rg.ok()) << (rg.ok() ? "" : rg.status().message());
    ASSERT_EQ(rg->passes.size(), 2u);
    EXPECT_EQ(rg->passes[0].kind, PassPlan::Kind::kShadow);
    EXPECT_EQ(rg->passes[0].faces, type == LightType::kPoint ? 6 : 1);
    EXPECT_EQ(rg->passes[0].resolution, 512);
    const ImageDiff d = compare_images(rc->framebuffer.color, rg->framebuffer.color, kThreshold);
    const double off = static_cast<double>(d.over_count) / (static_cast<double>(kWidth) * kHeight);
    std::printf("[ measure  ] room, shadowing light as type %d: PSNR %.2f dB, over 8/255 %.3f%%\n",
                static_cast<int>(type), d.psnr_db, 100.0 * off);
    EXPECT_GE(d.psnr_db, kMinPsnr);
    EXPECT_LE(off, kMaxOverFraction);
    // Without the shadow pass the GL image is clearly different: the maps were read.
    RenderOptions none = opt;
    none.shadows = false;
    Result<Plan> unshadowed = make_plan(scene, none);
    ASSERT_TRUE(unshadowed.ok());
    Result<RenderResult> ru = (*gl)->render(scene, *unshadowed);
    ASSERT_TRUE(ru.ok());
    const ImageDiff lit = compare_images(ru->framebuffer.color, rg->framebuffer.color, kThreshold);
    EXPECT_GT(lit.over_count, 100u);
  }
}

// A plan whose material is bound to a technique without a GLSL twin (a copy of a built-in's
// descriptor under a new name, as an external plugin would be) fails on the GL backend with one
// clear error instead of drawing something else.
TEST(GlBackend, UnknownTwinIsAnError) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl =
      make_gl_backend({.gl_interpolation = GlInterpolation::kCpuPlanes});
  ASSERT_TRUE(gl.ok());
  Result<Scene> scene = make_builtin_scene("plane");
  ASSERT_TRUE(scene.ok());
  RenderOptions opt;
  opt.width = 16;
  opt.height = 16;
  opt.technique = "relief";
  Result<Plan> plan = make_plan(*scene, opt);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  ASSERT_FALSE(plan->materials.empty());
  ASSERT_TRUE(gl_has_twin("relief"));
  ASSERT_FALSE(gl_has_twin("relief_without_twin"));
  PluginDescriptor copy = *plan->materials[0].plugin;
  copy.name = "relief_without_twin";
  for (BoundMaterial& m : plan->materials) m.plugin = &copy;
  Result<RenderResult> r = (*gl)->render(*scene, *plan);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("no GLSL twin"), std::string::npos) << r.status().message();
  EXPECT_NE(r.status().message().find("relief_without_twin"), std::string::npos)
      << r.status().message();
}

}  // namespace
}  // namespace relief
