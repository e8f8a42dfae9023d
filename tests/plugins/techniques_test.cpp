// The relief technique plugins (every registered plugin with a required `depth` slot: parallax,
// steep_parallax, pom, relief, exact, and those registered later) shade one packet of a flat,
// relief-mapped quad seen at an angle: finite output, counters, AOVs, the scalar and 8-lane paths
// bit-identical, depth correction only ever farther, and relief close to the exact plugin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "plugins/plugin.h"
#include "plugins/registry.h"
#include "tests/plugins/packet_fixture.h"

namespace relief {

extern const PluginDescriptor kParallaxPlugin;
extern const PluginDescriptor kSteepParallaxPlugin;
extern const PluginDescriptor kPomPlugin;
extern const PluginDescriptor kReliefPlugin;
extern const PluginDescriptor kExactPlugin;

namespace {

constexpr int kN = 64;

Texture smooth_depth() {
  std::vector<float> d(kN * kN);
  const double k = 2.0 * M_PI / kN;
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < kN; ++i)
      d[j * kN + i] = static_cast<float>(0.5 + 0.3 * std::sin(2 * k * i) * std::cos(3 * k * j) +
                                         0.15 * std::sin(5 * k * (i + j) + 1.0));
  Texture t = Texture::from_floats(TexFormat::kR32F, kN, kN, d.data());
  t.generate_mips(MipReduce::kAverage);
  return t;
}

int depth_slot(const PluginDescriptor& p) {
  for (int s = 0; s < p.num_textures; ++s)
    if (std::strcmp(p.textures[s].name, "depth") == 0) return s;
  return -1;
}

// Plane z = 0, N = +z, T = +x, B = +y, uv = world (x, y); a 8 x 8 pixel patch of fragments spaced
// 0.004 apart around (0.4, 0.6), seen from an eye at an angle.
struct Scene {
  Texture depth = smooth_depth();
  FrameUniforms frame;
  MaterialUniforms material;
  FragmentPacket packet;
  const float kSpacing = 0.004f;

  explicit Scene(const PluginDescriptor& p) {
    testing::set_oblique_frame(frame);
    for (int i = 0; i < p.num_params; ++i) material.params[i] = p.params[i].default_value;
    const int slot = depth_slot(p);
    material.textures[slot] = &depth;
    material.samplers[slot].filter = Filter::kTrilinear;
    testing::fill_plane_packet(packet, frame, kSpacing);
  }
  void set(const PluginDescriptor& p, const char* name, float v) {
    for (int i = 0; i < p.num_params; ++i)
      if (std::strcmp(p.params[i].name, name) == 0) material.params[i] = v;
  }
  // Shades the packet with `effects`, scalar or 8 lanes.
  std::unique_ptr<FragmentOutput> shade(const PluginDescriptor& p, EffectMask effects, bool scalar,
                                        WorkCounters& wc) {
    frame.scalar_lanes = scalar;
    void* state = p.create_state ? p.create_state(material) : nullptr;
    ShadeContext ctx{&frame, &material, state, effects};
    auto out = std::make_unique<FragmentOutput>();
    std::memset(out.get(), 0, sizeof(FragmentOutput));
    p.select(effects)(ctx, packet, *out, wc);
    if (state) p.destroy_state(state);
    return out;
  }
};

// The registered plugins whose one required texture is `depth` and that search the height field
// per fragment (plugins that need more derived maps are covered on rendered scenes by
// tests/sweep/techniques_render_test.cpp; layered ones, `shells`, which draw the relief as
// geometry and never search or write depth, by tests/frames/shells_test.cpp).
std::vector<const PluginDescriptor*> relief_plugins() {
  std::vector<const PluginDescriptor*> out;
  for (const PluginDescriptor* p : PluginRegistry::global().all()) {
    int required = 0;
    for (int s = 0; s < p->num_textures; ++s) required += p->textures[s].required;
    const int d = depth_slot(*p);
    if (d >= 0 && p->textures[d].required && required == 1 && !p->layers) out.push_back(p);
  }
  return out;
}

TEST(Techniques, RegistryHoldsTheReliefFamily) {
  std::vector<const PluginDescriptor*> all = relief_plugins();
  for (const PluginDescriptor* p :
       {&kParallaxPlugin, &kSteepParallaxPlugin, &kPomPlugin, &kReliefPlugin, &kExactPlugin})
    EXPECT_NE(std::find(all.begin(), all.end(), p), all.end()) << p->name;
}

TEST(Techniques, EveryVariantShadesFiniteAndLanePathsAgree) {
  for (const PluginDescriptor* p : relief_plugins()) {
    Scene s(*p);
    for (EffectMask e :
         {EffectMask(0), EffectMask(kEffectSelfShadow),
          EffectMask(kEffectDepthWrite | kEffectSelfShadow), EffectMask(kEffectShadowPass)}) {
      // relief_quadric shadows by shadow maps only (quadric paper, section 3.5)
      if ((e & kEffectSelfShadow) && std::string(p->name) == "relief_quadric") continue;
      ASSERT_EQ(e & ~p->supported_effects, 0u) << p->name;
      WorkCounters w8, w1;
      auto o8 = s.shade(*p, e, false, w8);
      auto o1 = s.shade(*p, e, true, w1);
      for (int ln = 0; ln < kPacketLanes; ++ln) {
        for (int c = 0; c < 4; ++c) ASSERT_TRUE(std::isfinite(o8->color[c][ln])) << p->name;
        const float hd = o8->aov[kAovOffset[1]][ln];
        ASSERT_GE(hd, 0.0f) << p->name;
        ASSERT_LE(hd, 1.0f) << p->name;
        if (e & (kEffectDepthWrite | kEffectShadowPass)) {
          ASSERT_LE(o8->depth[ln], s.packet.frag_z[ln]) << p->name;  // never closer
          ASSERT_GE(o8->depth[ln], 0.0f);
          if (hd > 0.05f) {
            ASSERT_LT(o8->depth[ln], s.packet.frag_z[ln]) << p->name;
          }
        }
      }
      EXPECT_EQ(std::memcmp(o8->color, o1->color, sizeof(o8->color)), 0) << p->name << " " << e;
      EXPECT_EQ(std::memcmp(o8->aov, o1->aov, sizeof(o8->aov)), 0) << p->name << " " << e;
      EXPECT_EQ(std::memcmp(o8->depth, o1->depth, sizeof(o8->depth)), 0) << p->name << " " << e;
      EXPECT_EQ(w8.texture_fetches, w1.texture_fetches) << p->name;
      EXPECT_EQ(w8.search_steps, w1.search_steps) << p->name;
      EXPECT_EQ(w8.shadow_steps, w1.shadow_steps) << p->name;
      EXPECT_GE(w8.search_steps, static_cast<uint64_t>(kPacketLanes)) << p->name;
      if (e & kEffectSelfShadow) {
        EXPECT_GT(w8.shadow_steps, 0u) << p->name;
      }
      if (e == 0) {
        EXPECT_EQ(w8.shadow_steps, 0u) << p->name;
      }
    }
  }
}

// Relief at 64 + 8 steps lands within 0.05 texel of the exact plugin's hit on average, and
// parallax (one offset) is much farther off than relief at this angle.
TEST(Techniques, ReliefMatchesExactPlugin) {
  Scene se(kExactPlugin), sr(kReliefPlugin), sp(kParallaxPlugin);
  sr.set(kReliefPlugin, "steps", 64.0f);
  sr.set(kReliefPlugin, "min_steps", 64.0f);
  sr.set(kReliefPlugin, "binary_steps", 8.0f);
  const float scale = 0.05f;
  se.set(kExactPlugin, "depth_scale", scale);
  sr.set(kReliefPlugin, "depth_scale", scale);
  sp.set(kParallaxPlugin, "depth_scale", scale);
  sp.set(kParallaxPlugin, "offset_limiting", 0.0f);
  WorkCounters w;
  auto oe = se.shade(kExactPlugin, 0, false, w);
  auto orl = sr.shade(kReliefPlugin, 0, false, w);
  auto op = sp.shade(kParallaxPlugin, 0, false, w);
  double err_relief = 0.0, err_parallax = 0.0;
  for (int ln = 0; ln < kPacketLanes; ++ln) {
    const double eu = oe->aov[0][ln], ev = oe->aov[1][ln];
    err_relief += std::hypot(orl->aov[0][ln] - eu, orl->aov[1][ln] - ev) * kN;
    err_parallax += std::hypot(op->aov[0][ln] - eu, op->aov[1][ln] - ev) * kN;
  }
  err_relief /= kPacketLanes;
  err_parallax /= kPacketLanes;
  RecordProperty("relief_mean_texel_error", std::to_string(err_relief));
  RecordProperty("parallax_mean_texel_error", std::to_string(err_parallax));
  EXPECT_LT(err_relief, 0.05);
  EXPECT_GT(err_parallax, 4.0 * err_relief);
}

TEST(Techniques, SchemasAndEffects) {
  for (const PluginDescriptor* p : relief_plugins()) {
    EXPECT_EQ(p->abi_version, kPluginAbiVersion);
    if (std::string(p->name) != "relief_quadric") {  // shadow maps only (quadric paper, 3.5)
      EXPECT_NE(p->supported_effects & kEffectSelfShadow, 0u) << p->name;
    }
    EXPECT_EQ(p->depth_output(kEffectDepthWrite), DepthOutput::kFarther) << p->name;
    EXPECT_EQ(p->depth_output(0), DepthOutput::kNone) << p->name;
    bool has_scale = false;
    for (int i = 0; i < p->num_params; ++i) {
      has_scale |= std::strcmp(p->params[i].name, "depth_scale") == 0;
      EXPECT_GE(p->params[i].default_value, p->params[i].min_value);
      EXPECT_LE(p->params[i].default_value, p->params[i].max_value);
    }
    EXPECT_TRUE(has_scale) << p->name;
  }
}

}  // namespace
}  // namespace relief
