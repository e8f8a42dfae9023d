// The cone-stepping plugins (cone, cone_quad, relaxed_cone; Dummer 2006 and Policarpo & Oliveira,
// GPU Gems 3 ch. 18): registered with a cone-map slot, every effect variant shades finite output
// with the scalar and 8-lane paths bit-identical and counting their work, the `plane` and
// `pattern` scenes render without NaN/Inf with maps derived from depth on first use, and the
// derived-map cache (render/derived_maps.h) survives a corrupt file and an unwritable folder.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "bake/cone_map.h"
#include "builtin/builtin.h"
#include "plugins/plugin.h"
#include "plugins/registry.h"
#include "render/derived_maps.h"
#include "render/render.h"
#include "tests/plugins/packet_fixture.h"
#include "tests/test_dir.h"

namespace relief {

// The cone techniques' descriptors (plugins/cone.cpp, cone_quad.cpp, relaxed_cone.cpp).
extern const PluginDescriptor kConePlugin;
extern const PluginDescriptor kConeQuadPlugin;
extern const PluginDescriptor kRelaxedConePlugin;

namespace {

namespace fs = std::filesystem;

const PluginDescriptor* const kCones[] = {&kConePlugin, &kConeQuadPlugin, &kRelaxedConePlugin};

// Each test process bakes into its own cache folder.
class ConePlugins : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::test_dir_path("relief_cone_cache");
    fs::remove_all(dir_);
    ::setenv("RELIEF_CACHE_DIR", dir_.c_str(), 1);
    clear_derived_map_memory_cache();
  }
  void TearDown() override {
    ::unsetenv("RELIEF_CACHE_DIR");
    std::error_code ec;
    fs::permissions(dir_, fs::perms::owner_all, ec);
    fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

TEST_F(ConePlugins, RegisteredWithAConeMapSlot) {
  const char* slots[] = {"cone_conservative", "cone_quad", "cone_relaxed"};
  for (int i = 0; i < 3; ++i) {
    const PluginDescriptor* p = PluginRegistry::global().find(kCones[i]->name);
    ASSERT_EQ(p, kCones[i]);
    ASSERT_EQ(p->num_textures, 4);
    EXPECT_STREQ(p->textures[3].name, slots[i]);
    EXPECT_TRUE(is_derived_slot(p->textures[3].name));
    EXPECT_STREQ(p->textures[2].name, "depth");
    EXPECT_EQ(p->depth_output(kEffectDepthWrite), DepthOutput::kFarther);
    for (int k = 0; k < p->num_params; ++k) {
      EXPECT_GE(p->params[k].default_value, p->params[k].min_value);
      EXPECT_LE(p->params[k].default_value, p->params[k].max_value);
    }
  }
  EXPECT_FALSE(is_derived_slot("depth"));
}

// An 8 x 8 patch of a flat quad (z = 0, uv = world xy) over the pattern depth map, seen at an
// angle, as in tests/plugins/techniques_test.cpp.
struct Packet {
  Texture depth = make_pattern_depth(64);
  Texture cone;
  FrameUniforms frame;
  MaterialUniforms material;
  FragmentPacket packet;

  explicit Packet(const PluginDescriptor& p) {
    ConeBakeOptions o;
    o.wrap = true;
    o.kind = std::strcmp(p.name, "cone") == 0        ? ConeKind::kConservative
             : std::strcmp(p.name, "cone_quad") == 0 ? ConeKind::kQuad
                                                     : ConeKind::kRelaxed;
    o.bilinear = true;
    cone = bake_cone_map(depth, o);
    testing::set_oblique_frame(frame);
    for (int i = 0; i < p.num_params; ++i) material.params[i] = p.params[i].default_value;
    material.textures[2] = &depth;
    material.textures[3] = &cone;
    testing::fill_plane_packet(packet, frame, 0.004f, /*partial_quad=*/5);
  }
  std::unique_ptr<FragmentOutput> shade(const PluginDescriptor& p, EffectMask e, bool scalar,
                                        WorkCounters& wc) {
    frame.scalar_lanes = scalar;
    ShadeContext ctx{&frame, &material, nullptr, e};
    auto out = std::make_unique<FragmentOutput>();
    std::memset(out.get(), 0, sizeof(FragmentOutput));
    p.select(e)(ctx, packet, *out, wc);
    return out;
  }
};

TEST_F(ConePlugins, EveryVariantShadesFiniteAndLanePathsAgree) {
  for (const PluginDescriptor* p : kCones) {
    Packet s(*p);
    for (EffectMask e :
         {EffectMask(0), EffectMask(kEffectSelfShadow),
          EffectMask(kEffectDepthWrite | kEffectSelfShadow), EffectMask(kEffectShadowPass)}) {
      ASSERT_EQ(e & ~p->supported_effects, 0u) << p->name;
      WorkCounters w8, w1;
      auto o8 = s.shade(*p, e, false, w8);
      auto o1 = s.shade(*p, e, true, w1);
      for (int ln = 0; ln < kPacketLanes; ++ln) {
        if (!s.packet.lane_covered(ln)) continue;
        for (int c = 0; c < 4; ++c) ASSERT_TRUE(std::isfinite(o8->color[c][ln])) << p->name;
        const float hd = o8->aov[kAovOffset[1]][ln];
        ASSERT_GE(hd, 0.0f) << p->name;
        ASSERT_LE(hd, 1.0f) << p->name;
        if (e & (kEffectDepthWrite | kEffectShadowPass)) {
          ASSERT_TRUE(std::isfinite(o8->depth[ln]));
          ASSERT_LE(o8->depth[ln], s.packet.frag_z[ln]) << p->name;  // never closer
        }
      }
      EXPECT_EQ(std::memcmp(o8->color, o1->color, sizeof(o8->color)), 0) << p->name << " " << e;
      EXPECT_EQ(std::memcmp(o8->aov, o1->aov, sizeof(o8->aov)), 0) << p->name << " " << e;
      EXPECT_EQ(std::memcmp(o8->depth, o1->depth, sizeof(o8->depth)), 0) << p->name << " " << e;
      EXPECT_EQ(w8.texture_fetches, w1.texture_fetches) << p->name;
      EXPECT_EQ(w8.search_steps, w1.search_steps) << p->name;
      EXPECT_EQ(w8.shadow_steps, w1.shadow_steps) << p->name;
      // at least one cone step (two fetches) per covered fragment; the halvings (binary_steps,
      // 8 by default) take one fetch each
      EXPECT_GE(w8.search_steps, 62u) << p->name;
      EXPECT_GE(w8.texture_fetches, 2 * w8.search_steps - 62u * 8) << p->name;
      if (e & kEffectSelfShadow) {
        EXPECT_GT(w8.shadow_steps, 0u) << p->name;
      }
      if (e == 0) {
        EXPECT_EQ(w8.shadow_steps, 0u) << p->name;
      }
    }
  }
}

// Renders a built-in scene with `technique` at 160 x 90; asserts no NaN/Inf anywhere.
RenderResult render_scene(const std::string& scene_name, const std::string& technique,
                          std::string* explain = nullptr) {
  Result<Scene> scene = make_builtin_scene(scene_name);
  EXPECT_TRUE(scene.ok());
  RenderOptions opt;
  opt.width = 160;
  opt.height = 90;
  opt.technique = technique;
  opt.aovs = aov_bit(Aov::kHitUv) | aov_bit(Aov::kHitDepth);
  Result<Plan> plan = make_plan(*scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  if (!plan.ok()) return {};
  if (explain) *explain = plan->explain();
  Result<RenderResult> r = make_cpu_backend({.threads = 2})->render(*scene, *plan);
  EXPECT_TRUE(r.ok());
  if (!r.ok()) return {};
  const Framebuffer& fb = r->framebuffer;
  for (const glm::vec4& c : fb.color.pixels)
    for (int k = 0; k < 4; ++k) EXPECT_TRUE(std::isfinite(c[k])) << scene_name << " " << technique;
  for (float d : fb.depth.values) EXPECT_TRUE(std::isfinite(d));
  for (float a : fb.aov) EXPECT_TRUE(std::isfinite(a));
  return std::move(r).value();
}

// Pattern with all three; plane (512 x 512 bricks, whose quad and relaxed bakes take 10-25 s on
// two busy cores) with `cone` only.
TEST_F(ConePlugins, PatternAndPlaneRenderFiniteWithDerivedMaps) {
  for (const char* scene : {"pattern", "plane"})
    for (const PluginDescriptor* p : kCones) {
      if (std::strcmp(scene, "plane") == 0 && p != &kConePlugin) continue;
      std::string explain;
      const RenderResult r = render_scene(scene, p->name, &explain);
      EXPECT_NE(explain.find("from depth"), std::string::npos) << explain;
      ASSERT_FALSE(r.passes.empty());
      EXPECT_GT(r.passes[0].raster.work.texture_fetches, 0u);
    }
}

TEST_F(ConePlugins, DerivedMapsAreCachedInMemoryAndOnDisk) {
  std::string first, second, third;
  const RenderResult a = render_scene("pattern", "relaxed_cone", &first);
  EXPECT_NE(first.find("baked from depth"), std::string::npos) << first;
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) files += e.path().extension() == ".bin";
  EXPECT_EQ(files, 1);
  const RenderResult b = render_scene("pattern", "relaxed_cone", &second);
  EXPECT_NE(second.find("memory cache"), std::string::npos) << second;
  clear_derived_map_memory_cache();
  const RenderResult c = render_scene("pattern", "relaxed_cone", &third);
  EXPECT_NE(third.find("disk cache"), std::string::npos) << third;
  EXPECT_EQ(a.framebuffer.color.pixels, c.framebuffer.color.pixels);
}

TEST_F(ConePlugins, CorruptCacheIsRebakedAndUnwritableCacheIgnored) {
  const RenderResult ref = render_scene("pattern", "cone");
  for (const auto& e : fs::directory_iterator(dir_)) {
    std::fstream f(e.path(), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    const char junk[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    f.write(junk, sizeof junk);
  }
  clear_derived_map_memory_cache();
  std::string explain;
  const RenderResult again = render_scene("pattern", "cone", &explain);
  EXPECT_NE(explain.find("baked from depth"), std::string::npos) << explain;
  EXPECT_EQ(ref.framebuffer.color.pixels, again.framebuffer.color.pixels);

  // a cache folder that cannot be created: a warning, the same image
  const fs::path blocker = dir_ / "file";
  { std::ofstream(blocker) << "x"; }
  ::setenv("RELIEF_CACHE_DIR", (blocker / "sub").c_str(), 1);
  clear_derived_map_memory_cache();
  const RenderResult nowrite = render_scene("pattern", "cone");
  EXPECT_EQ(ref.framebuffer.color.pixels, nowrite.framebuffer.color.pixels);
}

TEST_F(ConePlugins, MissingDepthIsAnErrorNotABake) {
  Result<Scene> scene = make_builtin_scene("pattern");
  ASSERT_TRUE(scene.ok());
  scene->materials[0].textures.erase("depth");
  RenderOptions opt;
  opt.technique = "relaxed_cone";
  Result<Plan> plan = make_plan(*scene, opt);
  ASSERT_FALSE(plan.ok());
  EXPECT_NE(plan.status().message().find("depth"), std::string::npos);
  Result<DerivedMap> d = derive_map(scene->materials[0], "cone_relaxed");
  ASSERT_FALSE(d.ok());
}

}  // namespace
}  // namespace relief
