// The AVX2 and baseline code paths (rasterizer/simd.h) give bit-identical frames: traversal,
// interpolation, sampling and lighting do the same IEEE operations in both, with no FMA
// contraction (-ffp-contract=off).
#include <gtest/gtest.h>

#include <memory>

#include "rasterizer/simd.h"
#include "render/render.h"
#include "scene/builtin.h"

namespace relief {
namespace {

// One small frame of `plane` per technique, rendered at the SIMD level in use.
class PlaneFrames {
 public:
  PlaneFrames() : scene_(make_builtin_scene("plane")), backend_(make_cpu_backend(2)) {
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
  PlaneFrames frames;
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

}  // namespace
}  // namespace relief
