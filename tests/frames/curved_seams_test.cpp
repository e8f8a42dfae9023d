// Issue 23: "the built-in sphere and torus show hard brightness seams along mesh edges between the
// bumps with plain --technique normal". The seams were a tone step of the bumps' colour texture
// (alternate cells 0.85 times as bright, floor included) on the cell borders, which are mesh
// edges of the built-in meshes (sphere: a cell every 4 mesh columns; torus: every 3). Measured
// here on the render: between horizontally adjacent pixels that both see the flat floor between
// the bumps (from the hit-uv AOV), the median relative brightness jump of pairs that straddle a
// cell border against that of pairs inside one cell (figures in the test's output).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "builtin/builtin.h"
#include "render/render.h"
#include "tests/frames/cpu_frame.h"

namespace relief {
namespace {

// The bumps pattern of builtin/builtin_curved.cpp: 4 x 4 cells per uv unit, a dome of radius 0.4
// cell in each; the floor is where r^2 / 0.16 > 1.3 (beyond the dome and its rim ramp).
bool on_floor(float u, float v) {
  const float fu = u * 4.0f - std::floor(u * 4.0f) - 0.5f;
  const float fv = v * 4.0f - std::floor(v * 4.0f) - 0.5f;
  return (fu * fu + fv * fv) / 0.16f > 1.6f;
}

struct SeamStats {
  double across = 0.0, inside = 0.0;  // median relative jumps
  int n_across = 0, n_inside = 0;
};

double median(std::vector<double>& v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

SeamStats measure(const std::string& scene_name) {
  Result<Scene> s = make_builtin_scene(scene_name);
  EXPECT_TRUE(s.ok()) << s.status().message();
  SeamStats r;
  if (!s.ok()) return r;
  RenderOptions opt = test::cpu_options(480, 360, "normal");
  opt.aovs = aov_bit(Aov::kHitUv);
  const std::optional<Framebuffer> fb = test::render_frame(*s, opt);
  if (!fb) return r;
  const int uv = kAovOffset[static_cast<int>(Aov::kHitUv)];
  std::vector<double> across, inside;
  for (int y = 0; y < fb->color.height; ++y)
    for (int x = 0; x + 1 < fb->color.width; ++x) {
      if (!(fb->depth.at(x, y) > 0.0f && fb->depth.at(x + 1, y) > 0.0f)) continue;
      const float* a = fb->aov_at(x, y);
      const float* b = fb->aov_at(x + 1, y);
      if (!on_floor(a[uv], a[uv + 1]) || !on_floor(b[uv], b[uv + 1])) continue;
      const bool straddles = std::floor(a[uv] * 4.0f) != std::floor(b[uv] * 4.0f) ||
                             std::floor(a[uv + 1] * 4.0f) != std::floor(b[uv + 1] * 4.0f);
      const double la = fb->color.at(x, y).x, lb = fb->color.at(x + 1, y).x;
      const double m = std::max(la, lb);
      if (!(m > 0.02)) continue;  // unlit
      const double j = std::fabs(la - lb) / m;
      (straddles ? across : inside).push_back(j);
    }
  r.n_across = static_cast<int>(across.size());
  r.n_inside = static_cast<int>(inside.size());
  r.across = median(across);
  r.inside = median(inside);
  return r;
}

TEST(CurvedSeams, NoBrightnessStepAcrossCellBordersOnSphereTorusTeapot) {
  for (const char* name : {"sphere", "torus", "teapot"}) {
    const SeamStats st = measure(name);
    SCOPED_TRACE(name);
    ASSERT_GT(st.n_across, 50);
    ASSERT_GT(st.n_inside, 500);
    std::printf(
        "[   info   ] %s: median jump across cell borders %.4f (%d pairs), inside %.4f (%d)\n",
        name, st.across, st.n_across, st.inside, st.n_inside);
    EXPECT_LT(st.across, 2.0 * st.inside + 0.01);
  }
}

}  // namespace
}  // namespace relief
