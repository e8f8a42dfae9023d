// Tests for scene/animation (glTF sampling, skinning, morph targets) and the `bending` scene:
// hand-computed samples, the bind pose is the rest mesh bit for bit, tangent frames stay
// orthonormal and attached under a bend, morph weights 0 give the base mesh.
#include "scene/animation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>

#include "builtin/builtin_bending.h"
#include "render/render.h"
#include "scene/mesh_prep.h"
#include "tests/frames/cpu_frame.h"

namespace relief {
namespace {

AnimationSampler sampler(Interpolation i, std::vector<float> times, std::vector<float> values,
                         int width) {
  AnimationSampler s;
  s.interpolation = i;
  s.times = std::move(times);
  s.values = std::move(values);
  s.width = width;
  return s;
}

TEST(Animation, StepAndLinearSamplesWithClamping) {
  const AnimationSampler lin =
      sampler(Interpolation::kLinear, {1.0f, 2.0f, 4.0f}, {0, 0, 0, 10, 20, 30, 30, 20, 10}, 3);
  double v[3];
  sample_animation(lin, 1.5, false, v);
  EXPECT_DOUBLE_EQ(v[0], 5.0);
  EXPECT_DOUBLE_EQ(v[2], 15.0);
  sample_animation(lin, 3.0, false, v);  // halfway from key 1 to key 2
  EXPECT_DOUBLE_EQ(v[0], 20.0);
  EXPECT_DOUBLE_EQ(v[1], 20.0);
  EXPECT_DOUBLE_EQ(v[2], 20.0);
  sample_animation(lin, 0.0, false, v);  // before the first key
  EXPECT_EQ(v[1], 0.0);
  sample_animation(lin, 9.0, false, v);  // after the last
  EXPECT_EQ(v[0], 30.0);
  AnimationSampler step = lin;
  step.interpolation = Interpolation::kStep;
  sample_animation(step, 3.9, false, v);
  EXPECT_EQ(v[0], 10.0);
  sample_animation(step, 2.0, false, v);  // at a key: that key
  EXPECT_EQ(v[2], 30.0);
}

TEST(Animation, RotationSlerpsAlongTheShorterArc) {
  // 0 to 90 degrees about z; a third of the way is 30 degrees.
  const float s45 = static_cast<float>(std::sin(M_PI / 4)),
              c45 = static_cast<float>(std::cos(M_PI / 4));
  const AnimationSampler rot =
      sampler(Interpolation::kLinear, {0.0f, 3.0f}, {0, 0, 0, 1, 0, 0, s45, c45}, 4);
  double q[4];
  sample_animation(rot, 1.0, true, q);
  EXPECT_NEAR(q[0], 0.0, 1e-12);
  EXPECT_NEAR(q[2], std::sin(M_PI / 12), 1e-7);  // half of 30 degrees
  EXPECT_NEAR(q[3], std::cos(M_PI / 12), 1e-7);
  // The same end rotation written as -q: slerp still takes the 90-degree arc, not the 270.
  const AnimationSampler neg =
      sampler(Interpolation::kLinear, {0.0f, 3.0f}, {0, 0, 0, 1, 0, 0, -s45, -c45}, 4);
  double p[4];
  sample_animation(neg, 1.0, true, p);
  const double d = p[0] * q[0] + p[1] * q[1] + p[2] * q[2] + p[3] * q[3];
  EXPECT_NEAR(std::abs(d), 1.0, 1e-7);  // the keys are float quaternions
  // Linear interpolation of the components would not be unit length; slerp is.
  EXPECT_NEAR(std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]), 1.0, 1e-7);
  double l[4];
  const AnimationSampler far =
      sampler(Interpolation::kLinear, {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0, 1, 0}, 4);  // 180 degrees
  sample_animation(far, 0.5, true, l);
  EXPECT_NEAR(std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2] + l[3] * l[3]), 1.0, 1e-12);
  EXPECT_NEAR(l[2], std::sqrt(0.5), 1e-12);  // 90 degrees, where lerp would give length 0.71
}

TEST(Animation, CubicSplineIsTheHermiteOfAppendixC) {
  // Keys at t = 1 and 3: (in-tangent, value, out-tangent) per key, one component.
  const AnimationSampler cub =
      sampler(Interpolation::kCubicSpline, {1.0f, 3.0f}, {9.0f, 2.0f, 0.5f, -1.0f, 6.0f, 7.0f}, 1);
  // t = 1.5: u = 0.25, td = 2; p = h00 2 + h10 2 0.5 + h01 6 + h11 2 (-1).
  const double u = 0.25, td = 2.0;
  const double h00 = 2 * u * u * u - 3 * u * u + 1, h10 = u * u * u - 2 * u * u + u,
               h01 = -2 * u * u * u + 3 * u * u, h11 = u * u * u - u * u;
  const double expected = h00 * 2.0 + h10 * td * 0.5 + h01 * 6.0 + h11 * td * -1.0;
  double v;
  sample_animation(cub, 1.5, false, &v);
  EXPECT_NEAR(v, expected, 1e-12);
  EXPECT_NEAR(v, 2.859375, 1e-12);        // 0.84375 2 + 0.140625 2 0.5 + 0.15625 6 + 0.046875 2
  sample_animation(cub, 3.0, false, &v);  // at the last key: its value, not a tangent
  EXPECT_EQ(v, 6.0);
  sample_animation(cub, 0.0, false, &v);
  EXPECT_EQ(v, 2.0);
}

// A small mesh with a -0 coordinate, for exact comparisons.
Mesh small_mesh() {
  Mesh m;
  m.positions = {{-0.0f, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.25f}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.indices = {0, 1, 2, 0, 2, 3};
  prepare_mesh(m);
  return m;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(Morph, ZeroWeightsGiveTheBaseMeshExactly) {
  const Mesh rest = small_mesh();
  MorphTarget t;
  t.positions.assign(4, glm::vec3(0.0f, 0.0f, 0.5f));
  t.normals.assign(4, glm::vec3(0.5f, 0.0f, 0.0f));
  Mesh out;
  morph_mesh(rest, {t, t}, {0.0f, 0.0f}, out);
  EXPECT_TRUE(same_bits(out.positions, rest.positions));
  EXPECT_TRUE(same_bits(out.normals, rest.normals));
  EXPECT_TRUE(same_bits(out.tangents, rest.tangents));
  EXPECT_TRUE(std::signbit(out.positions[0].x));
  // Weight 1 on the first target moves every vertex by its delta, normals renormalised.
  morph_mesh(rest, {t, t}, {1.0f, 0.0f}, out);
  for (size_t v = 0; v < 4; ++v) {
    EXPECT_EQ(out.positions[v], rest.positions[v] + glm::vec3(0, 0, 0.5f));
    EXPECT_NEAR(glm::length(out.normals[v]), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(out.normals[v], glm::vec3(out.tangents[v])), 0.0f, 1e-6f);
  }
}

// The bending scene posed at `time`.
Scene bending_at(double time, PoseStats* stats = nullptr) {
  Result<Scene> s = make_bending_scene();
  EXPECT_TRUE(s.ok());
  const PoseStats ps = pose_scene(*s->animation, PoseOptions{}, time, *s);
  if (stats) *stats = ps;
  return std::move(*s);
}

Framebuffer render(const Scene& scene, int w, int h, AovMask aovs = 0) {
  RenderOptions opt;
  opt.width = w;
  opt.height = h;
  opt.aovs = aovs;
  return test::render_frame(scene, opt).value_or(Framebuffer{});
}

TEST(Skin, BindPoseRendersBitIdenticallyToTheUnskinnedMesh) {
  const Scene posed = bending_at(0.0);
  const Mesh& rest = posed.animation->deformers[0].rest;
  const Mesh& mesh = posed.meshes[0];
  EXPECT_TRUE(same_bits(mesh.positions, rest.positions));
  EXPECT_TRUE(same_bits(mesh.normals, rest.normals));
  EXPECT_TRUE(same_bits(mesh.tangents, rest.tangents));
  // The unskinned mesh: the rest data in a static scene.
  Scene still = posed;
  still.animation = nullptr;
  still.meshes[0] = rest;
  const Framebuffer a = render(posed, 160, 120), b = render(still, 160, 120);
  EXPECT_TRUE(same_bits(a.color.pixels, b.color.pixels));
  EXPECT_TRUE(same_bits(a.depth.values, b.depth.values));
  // The bend moves the picture (so the comparison can fail).
  const Framebuffer c = render(bending_at(1.0), 160, 120);
  EXPECT_FALSE(same_bits(a.color.pixels, c.color.pixels));
}

TEST(Skin, TangentFramesStayOrthonormalAndFollowTheSurface) {
  for (double t : {0.25, 0.6, 1.0}) {
    PoseStats ps;
    const Scene s = bending_at(t, &ps);
    EXPECT_EQ(ps.vertices, static_cast<long long>(s.meshes[0].positions.size()));
    const Mesh& m = s.meshes[0];
    const Mesh& rest = s.animation->deformers[0].rest;
    // Frames rebuilt from the deformed positions and uvs agree with the skinned ones where a
    // vertex moves rigidly with one joint (in the blend zone linear blend skinning's frames are
    // the usual approximation: it ignores the weights' gradient).
    Mesh rebuilt = m;
    compute_normals(rebuilt);
    compute_tangents(rebuilt);
    size_t moved = 0;
    const size_t side = static_cast<size_t>(kBendRings + 1) * (kBendSegments + 1);
    for (size_t v = 0; v < m.positions.size(); ++v) {
      const glm::vec3 n = m.normals[v], tan = glm::vec3(m.tangents[v]);
      EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f) << v;
      EXPECT_NEAR(glm::length(tan), 1.0f, 1e-5f) << v;
      EXPECT_NEAR(glm::dot(n, tan), 0.0f, 1e-5f) << v;
      EXPECT_EQ(m.tangents[v].w, rest.tangents[v].w) << v;
      moved += glm::length(m.positions[v] - rest.positions[v]) > 0.05f;
      const int seg = static_cast<int>(v % (kBendSegments + 1));
      const float wb = s.animation->deformers[0].weights[v].y;
      if (v < side && seg != 0 && seg != kBendSegments && (wb == 0.0f || wb == 1.0f)) {
        EXPECT_GT(glm::dot(n, rebuilt.normals[v]), 0.995f) << v << " at t " << t;
        EXPECT_GT(glm::dot(tan, glm::vec3(rebuilt.tangents[v])), 0.995f) << v << " at t " << t;
      }
    }
    EXPECT_GT(moved, m.positions.size() / 4) << t;
  }
}

TEST(Skin, TheReliefTexelUnderATrackedVertexStaysUnderIt) {
  const int w = 320, h = 240;
  const double t = 1.0;  // the full 75-degree bend
  const Scene s = bending_at(t);
  const Framebuffer fb = render(s, w, h, aov_bit(Aov::kHitUv));
  const Camera& cam = s.cameras[0];
  const glm::mat4 vp = cam.projection(static_cast<float>(w) / h) * cam.view();
  auto pixel_of = [&](glm::vec3 p) {
    const glm::vec4 c = vp * glm::vec4(p, 1.0f);
    return glm::ivec2(static_cast<int>((c.x / c.w * 0.5f + 0.5f) * w),
                      static_cast<int>((0.5f - c.y / c.w * 0.5f) * h));
  };
  auto uv_at = [&](glm::ivec2 px) {
    const float* a = fb.aov_at(px.x, px.y);
    return glm::vec2(a[0], a[1]);
  };
  const Mesh& m = s.meshes[0];
  const Mesh& rest = s.animation->deformers[0].rest;
  int checked = 0;
  // Vertices facing the camera (segment 0 faces +z) on rings in the bent upper half.
  for (int ring = 30; ring <= 44; ring += 2) {
    const size_t v = static_cast<size_t>(ring) * (kBendSegments + 1) + 1;
    const glm::ivec2 px = pixel_of(m.positions[v]);
    ASSERT_TRUE(px.x > 1 && px.y > 1 && px.x < w - 2 && px.y < h - 2) << ring;
    // One pixel's uv footprint (from the neighbours), plus the relief offset at a near-normal
    // view (depth_scale 0.06 times tan 20 degrees).
    float footprint = 0.0f;
    for (glm::ivec2 d : {glm::ivec2(1, 0), glm::ivec2(0, 1)})
      footprint = std::max(footprint, glm::length(uv_at(px + d) - uv_at(px - d)) * 0.5f);
    const float tolerance = 1.5f * footprint + 0.06f * 0.37f;
    const glm::vec2 uv = uv_at(px);
    EXPECT_LT(glm::length(uv - m.uvs[v]), tolerance)
        << "ring " << ring << ": uv " << uv.x << "," << uv.y << " vertex " << m.uvs[v].x << ","
        << m.uvs[v].y;
    // Where the undeformed vertex would project, the texel is another one: the test can fail.
    const glm::ivec2 old_px = pixel_of(rest.positions[v]);
    if (old_px.x >= 0 && old_px.y >= 0 && old_px.x < w && old_px.y < h) {
      EXPECT_GT(glm::length(uv_at(old_px) - m.uvs[v]), 3.0f * tolerance) << ring;
    }
    ++checked;
  }
  EXPECT_EQ(checked, 8);
}

}  // namespace
}  // namespace relief

namespace relief {
namespace {

TEST(Skin, ReliefQuadricMaterialsGetTheirQuadricsRefittedPerFrame) {
  Result<Scene> s = make_bending_scene();
  ASSERT_TRUE(s.ok());
  PoseOptions plain;
  EXPECT_EQ(pose_scene(*s->animation, plain, 1.0, *s).refitted_meshes, 0);
  PoseOptions quadric;
  quadric.technique = "relief_quadric";
  const PoseStats ps = pose_scene(*s->animation, quadric, 1.0, *s);
  EXPECT_EQ(ps.refitted_meshes, 1);
  EXPECT_GE(ps.refit_ms, 0.0);
  const Mesh& bent = s->meshes[0];
  Mesh expected = bent;
  compute_quadrics(expected);
  compute_tile_scale(expected);
  EXPECT_TRUE(same_bits(bent.quadric, expected.quadric));
  EXPECT_TRUE(same_bits(bent.tile_scale, expected.tile_scale));
  // The bend changes the fitted curvature somewhere (the rest data keeps the straight fit).
  Mesh rest = s->animation->deformers[0].rest;
  compute_quadrics(rest);
  EXPECT_FALSE(same_bits(bent.quadric, rest.quadric));
}

}  // namespace
}  // namespace relief
