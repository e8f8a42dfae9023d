// Every SIMD level (base/simd.h: baseline, AVX2, AVX-512, each a Highway target compiled into
// its own namespace) gives bit-identical frames, and so does the scalar reference path: traversal,
// interpolation, sampling and lighting do the same IEEE operations on every target, with no FMA
// contraction (-ffp-contract=off). Levels this CPU lacks are skipped, saying so.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "base/simd.h"
#include "builtin/builtin.h"
#include "render/render.h"

namespace relief {
namespace {

// One small frame of a built-in scene per technique, rendered at the SIMD level in use.
class SceneFrames {
 public:
  explicit SceneFrames(const char* scene = "plane")
      : scene_(make_builtin_scene(scene)), backend_(make_cpu_backend({.threads = 2})) {
    opt_.width = 240;
    opt_.height = 136;
    opt_.aovs = aov_bit(Aov::kHitUv) | aov_bit(Aov::kNormal);
    // room's shadow pass at the map this view resolves (393^2, not the light's 1024^2): the
    // same pass and receivers on every level, a seventh of the fragments (the pass was most of this
    // test's time, and of its ASan and TSan runs)
    opt_.shadow_size = ShadowSize::kView;
  }
  Framebuffer frame(const char* technique, bool scalar_lanes) {
    opt_.technique = technique;
    opt_.scalar_lanes = scalar_lanes;
    Result<Plan> plan = make_plan(*scene_, opt_);
    EXPECT_TRUE(plan.ok()) << plan.status().message();
    Result<RenderResult> r = backend_->render(*scene_, *plan);
    EXPECT_TRUE(r.ok());
    return std::move(r).value().framebuffer;
  }

 private:
  Result<Scene> scene_;
  std::unique_ptr<Backend> backend_;
  RenderOptions opt_;
};

bool identical(const Framebuffer& a, const Framebuffer& b) {
  return a.color.pixels == b.color.pixels && a.depth.values == b.depth.values && a.aov == b.aov;
}

struct RestoreLevel {
  SimdLevel saved = simd_level();
  ~RestoreLevel() { set_simd_level(saved); }
};

TEST(Simd, SetLevelIsClampedToTheCpu) {
  RestoreLevel restore;
  EXPECT_EQ(set_simd_level(SimdLevel::kBaseline), SimdLevel::kBaseline);
  EXPECT_EQ(simd_level(), SimdLevel::kBaseline);
  EXPECT_EQ(set_simd_level(SimdLevel::kAvx512), simd_supported());
  const std::vector<SimdLevel> levels = simd_levels_supported();
  ASSERT_FALSE(levels.empty());
  EXPECT_EQ(levels.front(), SimdLevel::kBaseline);
  EXPECT_EQ(levels.back(), simd_supported());
  // A level the CPU lacks clamps to the best one below it.
  const SimdLevel avx2 = set_simd_level(SimdLevel::kAvx2);
  EXPECT_TRUE(avx2 == SimdLevel::kAvx2 || avx2 == SimdLevel::kBaseline);
  EXPECT_STREQ(simd_level_name(SimdLevel::kAvx2), "avx2");
  EXPECT_STREQ(simd_level_name(SimdLevel::kAvx512), "avx512");
  EXPECT_STREQ(simd_level_name(SimdLevel::kBaseline), "baseline");
}

// The levels above baseline this CPU runs; says which are skipped.
std::vector<SimdLevel> vector_levels() {
  std::vector<SimdLevel> out;
  for (SimdLevel l : simd_levels_supported())
    if (l != SimdLevel::kBaseline) out.push_back(l);
  if (simd_supported() != SimdLevel::kAvx512)
    std::printf("[ SKIPPED  ] the AVX-512 level: this CPU lacks it\n");
  return out;
}

TEST(Simd, EveryLevelAndTheScalarPathGiveTheSameFrame) {
  RestoreLevel restore;
  SceneFrames frames;
  const std::vector<SimdLevel> levels = vector_levels();
  if (levels.empty()) GTEST_SKIP() << "this CPU runs the baseline level only";
  for (const char* technique : {"flat", "normal", "relief", "pom"}) {
    set_simd_level(SimdLevel::kBaseline);
    const Framebuffer base = frames.frame(technique, false);
    const Framebuffer scalar = frames.frame(technique, true);
    EXPECT_TRUE(identical(base, scalar)) << technique << " scalar lanes";
    for (SimdLevel level : levels) {
      set_simd_level(level);
      for (bool scalar_lanes : {false, true}) {
        const Framebuffer f = frames.frame(technique, scalar_lanes);
        EXPECT_TRUE(identical(base, f))
            << technique << " " << simd_level_name(level) << (scalar_lanes ? " scalar" : " lanes");
        // and the frame is not trivially empty
        int covered = 0;
        for (float d : f.depth.values) covered += d > 0.0f;
        EXPECT_GT(covered, 240 * 136 / 2) << technique;
      }
    }
  }
}

// Every built-in technique on every level: on `room` (a shadow pass for the spot light, received
// shadows, self-shadow, depth writes) and on the curved scenes of the quadric and dual-depth
// plugins, all levels give the baseline's bits.
TEST(Simd, EveryTechniqueIsBitIdenticalAcrossLevels) {
  RestoreLevel restore;
  const std::vector<SimdLevel> levels = vector_levels();
  if (levels.empty()) GTEST_SKIP() << "this CPU runs the baseline level only";
  struct Case {
    const char* scene;
    std::vector<const char*> techniques;
  };
  const Case cases[] = {
      {"room",
       {"flat", "normal", "parallax", "steep_parallax", "pom", "relief", "cone", "cone_quad",
        "relaxed_cone", "exact", "relief_quadric", "shells"}},
      {"sphere", {"relief_quadric"}},
      {"impostor", {"relief_dual"}},
  };
  for (const Case& c : cases) {
    SceneFrames frames(c.scene);
    for (const char* technique : c.techniques) {
      set_simd_level(SimdLevel::kBaseline);
      const Framebuffer base = frames.frame(technique, false);
      // the cone family's lane loop shades two groups of lanes at a time (search_pair), the
      // scalar path one lane at a time: both in the shadow pass and the lit main pass
      if (std::string(technique).find("cone") != std::string::npos) {
        EXPECT_TRUE(identical(base, frames.frame(technique, true)))
            << c.scene << " " << technique << " scalar lanes";
      }
      for (SimdLevel level : levels) {
        set_simd_level(level);
        const Framebuffer f = frames.frame(technique, false);
        EXPECT_TRUE(identical(base, f))
            << c.scene << " " << technique << " " << simd_level_name(level);
        int covered = 0;
        for (float d : f.depth.values) covered += d > 0.0f;
        EXPECT_GT(covered, 240 * 136 / 10) << c.scene << " " << technique;
      }
    }
  }
}

}  // namespace
}  // namespace relief
