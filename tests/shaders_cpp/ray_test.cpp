// Tangent-space rays and depth correction (shaders_cpp/ray.h).
#include "shaders_cpp/ray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace relief {
namespace {

bool finite3(V3<float> v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void expect_orthonormal(const TangentFrame<float>& f) {
  ASSERT_TRUE(finite3(f.t) && finite3(f.b) && finite3(f.n));
  EXPECT_NEAR(dot(f.t, f.t), 1.0f, 1e-5f);
  EXPECT_NEAR(dot(f.b, f.b), 1.0f, 1e-5f);
  EXPECT_NEAR(dot(f.n, f.n), 1.0f, 1e-5f);
  EXPECT_NEAR(dot(f.t, f.b), 0.0f, 1e-5f);
  EXPECT_NEAR(dot(f.t, f.n), 0.0f, 1e-5f);
  EXPECT_NEAR(dot(f.b, f.n), 0.0f, 1e-5f);
}

TEST(Ray, GramSchmidtFrame) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> c(-2.0f, 2.0f);
  for (int k = 0; k < 1000; ++k) {
    V3<float> N(c(rng), c(rng), c(rng)), T(c(rng), c(rng), c(rng)), B(c(rng), c(rng), c(rng));
    TangentFrame<float> f = orthonormal_frame(N, T, B);
    expect_orthonormal(f);
    EXPECT_GT(dot(f.n, N), 0.0f);
    EXPECT_GE(dot(f.b, B), -1e-5f * length(B));  // b keeps B's side
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const V3<float> zero(0.0f, 0.0f, 0.0f), z(0.0f, 0.0f, 1.0f), x(1.0f, 0.0f, 0.0f);
  expect_orthonormal(orthonormal_frame(zero, zero, zero));
  expect_orthonormal(orthonormal_frame(z, z, z));  // T parallel to N
  expect_orthonormal(orthonormal_frame(z, V3<float>(nan, 0.0f, 0.0f), x));
  expect_orthonormal(orthonormal_frame(V3<float>(nan, nan, nan), x, z));
  expect_orthonormal(orthonormal_frame(V3<float>(1e-30f, 0.0f, 0.0f), x, z));
}

TEST(Ray, TangentViewAndStep) {
  // surface z = 0, T = +x, B = +y, N = +z
  TangentFrame<float> f = orthonormal_frame(V3<float>(0.f, 0.f, 1.f), V3<float>(1.f, 0.f, 0.f),
                                            V3<float>(0.f, 1.f, 0.f));
  V3<float> p(0.0f, 0.0f, 0.0f);
  V3<float> V = tangent_view_dir(f, p, glm::vec3(0, 0, 3));
  EXPECT_NEAR(V.z, -1.0f, 1e-6f);
  EXPECT_NEAR(V.x, 0.0f, 1e-6f);
  // eye at 45 degrees on the -x side: the ray travels +x into the surface
  V = tangent_view_dir(f, p, glm::vec3(-2, 0, 2));
  EXPECT_NEAR(V.x, std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(V.z, -std::sqrt(0.5f), 1e-6f);
  V2<float> ds = texture_step(V, 0.1f);
  EXPECT_NEAR(ds.x, 0.1f, 1e-6f);
  EXPECT_NEAR(ds.y, 0.0f, 1e-6f);
  // orthographic uses the view direction
  V = tangent_view_dir(f, p, glm::vec3(5, 5, 5), true, glm::vec3(0, -0.6f, -0.8f));
  EXPECT_NEAR(V.y, -0.6f, 1e-6f);
  // grazing, along the normal, behind, zero scale: finite
  for (V3<float> W : {V3<float>(1.0f, 0.0f, -1.745e-4f), V3<float>(0.0f, 0.0f, -1.0f),
                      V3<float>(0.6f, 0.0f, 0.8f), V3<float>(0.0f, 0.0f, 0.0f)}) {
    for (float scale : {0.0f, 0.1f}) {
      V2<float> s = texture_step(W, scale);
      EXPECT_TRUE(std::isfinite(s.x) && std::isfinite(s.y));
      if (scale == 0.0f) {
        EXPECT_EQ(s.x, 0.0f);
      }
    }
  }
  // at the eye: falls back to looking along -n
  V = tangent_view_dir(f, p, glm::vec3(0, 0, 0));
  EXPECT_EQ(V.z, -1.0f);
}

TEST(Ray, ReversedZDepthCorrection) {
  // infinite reversed-Z perspective, near 0.5: depth = near / distance along -z
  glm::mat4 proj(0.0f);
  proj[0][0] = 1.0f;
  proj[1][1] = 1.0f;
  proj[2][3] = -1.0f;
  proj[3][2] = 0.5f;
  EXPECT_FLOAT_EQ(reversed_z_depth(proj, V3<float>(0.f, 0.f, -0.5f), 0.0f), 1.0f);
  EXPECT_FLOAT_EQ(reversed_z_depth(proj, V3<float>(0.f, 0.f, -2.0f), 0.0f), 0.25f);
  EXPECT_FLOAT_EQ(reversed_z_depth(proj, V3<float>(0.f, 0.f, -0.1f), 0.0f), 1.0f);  // clamped
  EXPECT_EQ(reversed_z_depth(proj, V3<float>(0.f, 0.f, 1.0f), 0.7f), 0.7f);         // behind eye
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(reversed_z_depth(proj, V3<float>(nan, 0.f, -1.0f), 0.3f), 0.3f);
  EXPECT_EQ(reversed_z_depth(proj, V3<float>(0.f, 0.f, nan), nan), 0.0f);
  // a relief hit lies farther along the view ray than the polygon: smaller depth
  TangentFrame<float> f = orthonormal_frame(V3<float>(0.f, 1.f, 0.f), V3<float>(1.f, 0.f, 0.f),
                                            V3<float>(0.f, 0.f, -1.f));
  V3<float> pos(0.3f, -1.0f, -2.0f);
  V3<float> w = world_view_dir(pos, glm::vec3(0.0f), false, glm::vec3(0, 0, -1), -f.n);
  V3<float> V = f.to_tangent(w);
  ASSERT_LT(V.z, 0.0f);
  V3<float> hit = hit_world_position(pos, w, V.z, 0.5f, 0.2f);
  EXPECT_NEAR(hit.y, -1.0f - 0.1f, 1e-5f);  // half of the 0.2 relief height below the surface
  EXPECT_LT(reversed_z_depth(proj, hit, 0.0f), reversed_z_depth(proj, pos, 0.0f));
}

}  // namespace
}  // namespace relief
