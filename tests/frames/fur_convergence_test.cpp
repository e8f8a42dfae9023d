// Fur and grass converge (issue 27, docs/fur.md "The claim, measured"): on the built-in `fur` and
// `grass` scenes, steep parallax at 16, 32 and 64 planes and `shells` at 16, 32, 64 and 128 layers
// against `exact` on the same field, its depth map at level 0 (self-shadow off for all, so the
// comparison is of what each finds visible, not of how it darkens): the image's PSNR rises and the
// mean hit-depth error (hit_depth AOV, pixels covered in both) falls as the count grows, for both
// families. The figures print as "[ measure ]" lines; docs/fur.md records them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "builtin/builtin.h"
#include "render/compare.h"
#include "render/render.h"
#include "tests/frames/cpu_frame.h"
#include "tests/frames/depth_fixture.h"

namespace relief {
namespace {

constexpr int kW = 320, kH = 240;

struct Quality {
  double psnr_db = 0.0, depth_err = 0.0;
};

Framebuffer render(const Scene& scene, const std::string& technique,
                   std::map<std::string, std::string> params) {
  RenderOptions opt = test::cpu_options(kW, kH, technique);
  opt.params = std::move(params);
  opt.self_shadow = false;
  opt.aovs = aov_bit(Aov::kHitDepth);
  std::optional<Framebuffer> f = test::render_frame(scene, opt);
  return f ? std::move(*f) : Framebuffer{};
}

// PSNR of the colour and mean |hit depth - reference hit depth| over pixels both cover.
Quality quality(const Framebuffer& f, const Framebuffer& ref) {
  Quality q;
  q.psnr_db = compare_images(f.color, ref.color, 8.0f / 255.0f).psnr_db;
  double sum = 0.0;
  long n = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const size_t i = static_cast<size_t>(y) * kW + x;
      if (!(f.depth.values[i] > 0.0f && ref.depth.values[i] > 0.0f)) continue;
      sum += std::abs(f.aov_at(x, y)[kAovOffset[1]] - ref.aov_at(x, y)[kAovOffset[1]]);
      ++n;
    }
  q.depth_err = n ? sum / static_cast<double>(n) : 1.0;
  EXPECT_GT(n, kW * kH / 4);
  return q;
}

// The qualities of `technique` at each count of `param` against `ref`, printed.
std::vector<Quality> sweep(const char* scene_name, const Scene& scene, const Framebuffer& ref,
                           const std::string& technique, const char* param,
                           const std::vector<int>& counts) {
  std::vector<Quality> out;
  for (int n : counts) {
    const Quality q = quality(render(scene, technique, {{param, std::to_string(n)}}), ref);
    std::printf("[ measure  ] %s %s %s=%d: %.2f dB, mean hit-depth error %.4f\n", scene_name,
                technique.c_str(), param, n, q.psnr_db, q.depth_err);
    out.push_back(q);
  }
  return out;
}

class FurConvergence : public testing::TestWithParam<const char*> {};

TEST_P(FurConvergence, BothFamiliesConvergeToExactAsTheirCountGrows) {
  // depth maps at level 0: every technique then samples the surface exact intersects
  Result<Scene> scene = make_builtin_scene(GetParam());
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  scene = level0_depth(std::move(scene).value());
  const Framebuffer ref = render(*scene, "exact", {});
  const std::vector<Quality> steep =
      sweep(GetParam(), *scene, ref, "steep_parallax", "steps", {16, 32, 64});
  const std::vector<Quality> shells =
      sweep(GetParam(), *scene, ref, "shells", "layers", {16, 32, 64, 128});
  for (const std::vector<Quality>* family : {&steep, &shells}) {
    for (size_t k = 1; k < family->size(); ++k) {
      EXPECT_LT((*family)[k].depth_err, (*family)[k - 1].depth_err) << "count index " << k;
      EXPECT_GT((*family)[k].psnr_db, (*family)[k - 1].psnr_db) << "count index " << k;
    }
    EXPECT_GT(family->back().psnr_db, family->front().psnr_db + 1.0);
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, FurConvergence, testing::Values("fur", "grass"));

}  // namespace
}  // namespace relief
