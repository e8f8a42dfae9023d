// The AVX2 and baseline code paths (rasterizer/simd.h) give bit-identical frames: traversal,
// interpolation, sampling and lighting do the same IEEE operations in both, with no FMA
// contraction (-ffp-contract=off).
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "rasterizer/simd.h"
#include "render/render.h"
#include "scene/builtin.h"

namespace relief {
namespace {

// One small frame of a built-in scene per technique, rendered at the SIMD level in use.
class SceneFrames {
 public:
  explicit SceneFrames(const char* scene = "plane")
      : scene_(make_builtin_scene(scene)), backend_(make_cpu_backend(2)) {
    opt_.width = 240;
    opt_.height = 136;
    opt_.threads = 2;
    opt_.aovs = aov_bit(Aov::kHitUv) | aov_bit(Aov::kNormal);
  }
  Framebuffer frame(const char* technique, bool scalar_lanes) {
    opt_.technique = technique;
    opt_.scalar_lanes = scalar_lanes;
    Result<Plan> plan = make_plan(*scene_, opt_);
    EXPECT_TRUE(plan.ok()) << plan.status().message();
    Result<RenderResult> r = backend_->render(*scene_, *plan, opt_);
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
  EXPECT_FALSE(simd_avx2());
  EXPECT_EQ(set_simd_level(SimdLevel::kAvx2), simd_supported());
  EXPECT_EQ(simd_avx2(), simd_supported() == SimdLevel::kAvx2);
  EXPECT_STREQ(simd_level_name(SimdLevel::kAvx2), "avx2");
}

TEST(Simd, Avx2AndBaselineFramesAreBitIdentical) {
  if (simd_supported() != SimdLevel::kAvx2) GTEST_SKIP() << "no AVX2 on this CPU";
  RestoreLevel restore;
  SceneFrames frames;
  for (const char* technique : {"flat", "normal", "relief", "pom"}) {
    for (bool scalar : {false, true}) {
      set_simd_level(SimdLevel::kBaseline);
      const Framebuffer base = frames.frame(technique, scalar);
      set_simd_level(SimdLevel::kAvx2);
      const Framebuffer avx2 = frames.frame(technique, scalar);
      EXPECT_TRUE(identical(base, avx2)) << technique << (scalar ? " scalar" : " F8");
      // and the frame is not trivially empty
      int covered = 0;
      for (float d : avx2.depth.values) covered += d > 0.0f;
      EXPECT_GT(covered, 240 * 136 / 2) << technique;
    }
  }
}

// Every built-in technique has an AVX2 clone of its 8-lane packet loop: on `room` (a shadow pass
// for the spot light, received shadows, self-shadow, depth writes) and on the curved scenes of
// the quadric and dual-depth plugins, the two levels give the same bits.
TEST(Simd, EveryTechniqueIsBitIdenticalAcrossLevels) {
  if (simd_supported() != SimdLevel::kAvx2) GTEST_SKIP() << "no AVX2 on this CPU";
  RestoreLevel restore;
  struct Case {
    const char* scene;
    std::vector<const char*> techniques;
  };
  const Case cases[] = {
      {"room",
       {"flat", "normal", "parallax", "steep_parallax", "pom", "relief", "cone", "cone_quad",
        "relaxed_cone", "exact", "relief_quadric"}},
      {"sphere", {"relief_quadric"}},
      {"impostor", {"relief_dual"}},
  };
  for (const Case& c : cases) {
    SceneFrames frames(c.scene);
    for (const char* technique : c.techniques) {
      set_simd_level(SimdLevel::kBaseline);
      const Framebuffer base = frames.frame(technique, false);
      set_simd_level(SimdLevel::kAvx2);
      const Framebuffer avx2 = frames.frame(technique, false);
      EXPECT_TRUE(identical(base, avx2)) << c.scene << " " << technique;
      int covered = 0;
      for (float d : avx2.depth.values) covered += d > 0.0f;
      EXPECT_GT(covered, 240 * 136 / 10) << c.scene << " " << technique;
    }
  }
}

}  // namespace
}  // namespace relief
