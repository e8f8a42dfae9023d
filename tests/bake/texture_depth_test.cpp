// The kernels on a real depth texture (rasterizer/texture.h sample_r_lod through TextureDepth)
// agree with the test's own float sampler and with the exact reference built from the texture.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "shaders_cpp/exact_trace.h"
#include "shaders_cpp/search.h"
#include "tests/bake/field_fixture.h"

namespace relief {
namespace {

TEST(TextureDepth, MatchesFloatSamplerAndExact) {
  for (Wrap wrap : {Wrap::kRepeat, Wrap::kClamp}) {
    testing::FloatField f = testing::thin_walls(32, 7, 41);
    f.wrap_u = f.wrap_v = wrap;
    Texture tex = Texture::from_floats(TexFormat::kR32F, f.w, f.h, f.d.data());
    tex.generate_mips(MipReduce::kAverage);
    SamplerState s;
    s.filter = Filter::kTrilinear;
    s.wrap_u = s.wrap_v = wrap;
    TextureDepth depth;
    depth.texture = &tex;
    depth.sampler = &s;
    HeightField hf = HeightField::from_texture(tex, s);
    std::mt19937 rng(42);
    std::uniform_real_distribution<float> uv(-1.0f, 2.0f);
    for (int k = 0; k < 2000; ++k) {
      float u = uv(rng), v = uv(rng);
      ASSERT_NEAR(depth(0, u, v), f(0, u, v), 1e-5f) << u << " " << v;
      ASSERT_NEAR(hf.depth_at(u, v), f(0, u, v), 1e-5f);
    }
    double sum = 0.0;
    for (int k = 0; k < 500; ++k) {
      testing::RandomRay r = testing::random_ray(rng, 70.0f, 0.02f, 0.1f);
      SearchHit<float> h =
          relief_search(depth, V2<float>(r.u, r.v), V2<float>(r.dsx, r.dsy), 128.0f, 8, true);
      ExactHit e = hf.intersect(r.u, r.v, r.dsx, r.dsy);
      EXPECT_GE(h.depth, e.t - 1e-5);
      sum += std::hypot((h.uv.x - e.u) * f.w, (h.uv.y - e.v) * f.h);
    }
    EXPECT_LT(sum / 500, 0.05);
  }
}

}  // namespace
}  // namespace relief
