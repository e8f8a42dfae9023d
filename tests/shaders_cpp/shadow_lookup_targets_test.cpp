// Shadow-map lookups over the lanes (shaders_cpp/shadow_lookup.h shadow_map_visibility, whose
// lanes on one face of a map are looked up together by shadow_lookup_lanes) on every SIMD level
// this CPU runs, at that level's native lanes: each lane's visibility and taps are the scalar
// shadow_lookup's, bit for bit, for orthographic, perspective and cube maps, with and without
// percentage-closer filtering, for lanes in the map, outside it, behind the near plane and off.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/shaders_cpp/shadow_lookup_targets_test.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "shaders_cpp/shadow_lookup.h"

#include <hwy/highway.h>

#ifndef RELIEF_TESTS_SHADOW_LOOKUP_TARGETS_ONCE
#define RELIEF_TESTS_SHADOW_LOOKUP_TARGETS_ONCE
#include <gtest/gtest.h>

#include "tests/shaders_cpp/every_level.h"

namespace relief {
// What one level's check found (one type for every target's function).
struct ShadowLookupCheck {
  long checked = 0, mismatched = 0;
  long partly_lit = 0, shadowed = 0, left_lit = 0;  // lanes in the map, outcome; lanes never in it
  long one_face_packets = 0;                        // cube packets whose lanes share a face
  std::string first_mismatch;
};
}  // namespace relief
#endif

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

// A map of size x size texels per face, depths random in [0, 1] (0: nothing drawn), a tenth of
// the texels at the light's near plane (1) and a tenth empty.
struct TestMap {
  ShadowMapView view;
  std::vector<std::vector<float>> depth;
};
TestMap test_map(int kind, int size, int pcf_radius, std::mt19937& rng) {
  TestMap t;
  ShadowMapView& m = t.view;
  m.size = size;
  m.faces = kind == 2 ? kMaxShadowFaces : 1;
  m.orthographic = kind == 0;
  m.position = glm::vec3(0.5f, 2.0f, -0.25f);
  m.znear = 0.1f;
  m.zfar = 12.0f;
  m.texel = 2.0f / static_cast<float>(size);
  m.settings.depth_bias = 1.0f;
  m.settings.slope_bias = 1.5f;
  m.settings.pcf_radius = pcf_radius;
  const glm::vec3 axes[kMaxShadowFaces] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                           {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  const glm::vec3 ups[kMaxShadowFaces] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1},
                                          {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  t.depth.resize(m.faces);
  for (int f = 0; f < m.faces; ++f) {
    const glm::vec3 axis = m.faces == 1 ? glm::normalize(glm::vec3(0.2f, -1.0f, 0.1f)) : axes[f];
    const glm::vec3 up = m.faces == 1 ? glm::vec3(0, 0, 1) : ups[f];
    m.view[f] = glm::lookAt(m.position, m.position + axis, up);
    m.proj[f] = m.orthographic ? glm::ortho(-3.0f, 3.0f, -3.0f, 3.0f, m.znear, m.zfar)
                               : glm::perspective(glm::radians(90.0f), 1.0f, m.znear, m.zfar);
    t.depth[f].resize(static_cast<size_t>(size) * size);
    for (float& d : t.depth[f]) {
      const float r = u01(rng);
      d = r < 0.1f ? 0.0f : (r < 0.2f ? 1.0f : u01(rng));
    }
    m.depth[f] = t.depth[f].data();
  }
  return t;
}

ShadowLookupCheck check_shadow_lookups(uint32_t seed) {
  ShadowLookupCheck c;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> sym(-1.0f, 1.0f), spread(-4.0f, 4.0f);
  for (int kind = 0; kind < 3; ++kind)  // orthographic, perspective, cube
    for (int pcf = 0; pcf <= 2; ++pcf) {
      const TestMap t = test_map(kind, 48, pcf, rng);
      const ShadowMapView& m = t.view;
      for (int packet = 0; packet < 64; ++packet) {
        // every fourth packet of a cube: all lanes around one face's axis
        const bool one_face = kind == 2 && packet % 4 == 0;
        const glm::vec3 axis = glm::vec3(packet % 3 == 0, packet % 3 == 1, packet % 3 == 2) *
                               ((packet / 3) % 2 ? -1.0f : 1.0f);
        V3<FN> p, n, l;
        MN active = true_mask<FN>();
        glm::vec3 ps[kLanes], ns[kLanes], ls[kLanes];
        for (int i = 0; i < kLanes; ++i) {
          glm::vec3 q;
          if (one_face)
            q = m.position + axis * (1.0f + 3.0f * std::fabs(sym(rng))) +
                0.3f * glm::vec3(sym(rng), sym(rng), sym(rng));
          else if (kind == 2)
            q = m.position + glm::vec3(spread(rng), spread(rng), spread(rng));
          else  // below the light, some outside the map and some behind its near plane
            q = m.position + glm::vec3(spread(rng), -5.0f * sym(rng) - 4.0f, spread(rng));
          const glm::vec3 nn = glm::normalize(glm::vec3(sym(rng), 1.5f + sym(rng), sym(rng)));
          const glm::vec3 ll = glm::normalize(glm::vec3(sym(rng), 1.0f + sym(rng), sym(rng)));
          ps[i] = q;
          ns[i] = nn;
          ls[i] = ll;
          set_lane(p.x, i, q.x);
          set_lane(p.y, i, q.y);
          set_lane(p.z, i, q.z);
          set_lane(n.x, i, nn.x);
          set_lane(n.y, i, nn.y);
          set_lane(n.z, i, nn.z);
          set_lane(l.x, i, ll.x);
          set_lane(l.y, i, ll.y);
          set_lane(l.z, i, ll.z);
          if ((i * 7 + packet) % 11 == 3) set_lane(active, i, false);
        }
        if (packet == 5) active = false_mask<FN>();
        FN fetches(2.0f);
        const FN vis = shadow_map_visibility(m, p, n, l, active, fetches);
        int face = -1;
        bool shared = one_face;
        for (int i = 0; i < kLanes; ++i) {
          float taps = 0.0f;
          const float want =
              lane(active, i) ? relief::detail::shadow_lookup(m, ps[i], ns[i], ls[i], taps) : 1.0f;
          const float got = lane(vis, i), got_taps = lane(fetches, i) - 2.0f;
          ++c.checked;
          if ((std::memcmp(&got, &want, sizeof got) != 0 || got_taps != taps) &&
              c.mismatched++ == 0)
            c.first_mismatch = "kind " + std::to_string(kind) + " pcf " + std::to_string(pcf) +
                               " packet " + std::to_string(packet) + " lane " + std::to_string(i) +
                               ": " + std::to_string(got) + " (" + std::to_string(got_taps) +
                               " taps) against " + std::to_string(want) + " (" +
                               std::to_string(taps) + ")";
          if (taps == 0.0f)
            ++c.left_lit;
          else if (want == 0.0f)
            ++c.shadowed;
          else if (want < 1.0f)
            ++c.partly_lit;
          if (kind == 2 && lane(active, i)) {
            const int fi = relief::detail::cube_face(ps[i] - m.position);
            shared = shared && (face < 0 || fi == face);
            face = fi;
          }
        }
        if (kind == 2 && shared && face >= 0) ++c.one_face_packets;
      }
    }
  return c;
}

}  // namespace
}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

HWY_EXPORT(check_shadow_lookups);

TEST(ShadowLookupTargets, LanesGiveTheScalarLookupsBitsOnEveryLevel) {
  testing::on_every_level([](SimdLevel level) {
    const ShadowLookupCheck c = HWY_DYNAMIC_DISPATCH(check_shadow_lookups)(29);
    const std::string name = simd_level_name(level);
    EXPECT_EQ(c.mismatched, 0) << name << ": " << c.first_mismatch;
    EXPECT_GT(c.checked, 3 * 3 * 64 * 4) << name;
    // every outcome is compared, and cube packets take the one-face path
    EXPECT_GT(c.partly_lit, 100) << name;
    EXPECT_GT(c.shadowed, 100) << name;
    EXPECT_GT(c.left_lit, 100) << name;
    EXPECT_GE(c.one_face_packets, 3 * 16) << name;
  });
}

}  // namespace relief
#endif  // HWY_ONCE
