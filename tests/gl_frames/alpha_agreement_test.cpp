// Alpha modes on the GL backend against the CPU's (docs/scene-format.md, "Alpha"): one tiny scene
// (64x64) with a MASK cut-out quad casting a cut-out shadow onto a floor (once with `flat`, once
// with `relief`'s shadow-pass variant), and two BLEND quads over an opaque one submitted far-last
// (the sort must reorder them). Same metric as the agreement test (PSNR >= 35 dB, at most 0.5% of
// pixels more than 8/255 off) plus the alpha channel within 1/255, and the cut-out pixels must be
// the background on both.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "builtin/builtin_room.h"
#include "gl/gl_backend.h"
#include "render/compare.h"
#include "render/render.h"
#include "scene/mesh_prep.h"
#include "tests/gl/gl_test_util.h"

namespace relief {
namespace {

constexpr int kSize = 64;

void add_quad(Scene& s, glm::vec3 corner, glm::vec3 eu, glm::vec3 ev, int material) {
  Mesh m;
  add_rect(m, corner, eu, ev, glm::vec2(1.0f));
  prepare_mesh(m);
  s.meshes.push_back(std::move(m));
  s.instances.push_back({static_cast<int>(s.meshes.size()) - 1, material, glm::mat4(1.0f)});
}

TexturePtr half_transparent() {
  std::vector<uint8_t> texels(8 * 8 * 4, 255);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 4; ++x) texels[(y * 8 + x) * 4 + 3] = 0;
  auto t = std::make_shared<Texture>(TexFormat::kRGBA8, 8, 8, texels.data(), ColorSpace::kSRGB);
  t->generate_mips();
  return t;
}

Material flat(glm::vec4 c, AlphaMode mode = AlphaMode::kOpaque) {
  Material m;
  m.name = "flat";
  m.technique = "flat";
  m.base_color = c;
  m.double_sided = true;
  m.alpha_mode = mode;
  return m;
}

// Floor y = 0; a MASK quad at height 1 (transparent for x < 0) with `technique`; an opaque wall
// at z = -1.5 (1.5 high, the transparent background above) behind two BLEND quads (red farther,
// green nearer, submitted green first); the sun straight down with a shadow map; camera at height
// 0.6.
Scene alpha_scene(const std::string& technique) {
  Scene s;
  s.name = "alpha";
  s.background = glm::vec4(0.1f, 0.2f, 0.3f, 0.0f);  // transparent: alpha is tested
  s.materials.push_back(flat({0.8f, 0.8f, 0.8f, 1.0f}));
  Material cut = technique == "flat" ? flat(glm::vec4(1.0f))
                                     : procedural_relief_material(
                                           "cut",
                                           [](float, float) {
                                             return ReliefTexel{0.0f, glm::vec3(1.0f)};
                                           },
                                           8, 0.05f);
  cut.technique = technique;
  cut.double_sided = true;
  cut.self_shadow = false;
  cut.textures["base_color"] = half_transparent();
  cut.sampler.filter = Filter::kNearest;
  cut.sampler.wrap_u = cut.sampler.wrap_v = Wrap::kClamp;
  cut.alpha_mode = AlphaMode::kMask;
  s.materials.push_back(cut);
  s.materials.push_back(flat({0.9f, 0.9f, 0.2f, 1.0f}));
  s.materials.push_back(flat({0.1f, 1.0f, 0.1f, 0.5f}, AlphaMode::kBlend));
  s.materials.push_back(flat({1.0f, 0.1f, 0.1f, 0.5f}, AlphaMode::kBlend));
  add_quad(s, {-3, 0, 3}, {6, 0, 0}, {0, 0, -6}, 0);
  add_quad(s, {-0.5f, 1, 0.5f}, {1, 0, 0}, {0, 0, -1}, 1);
  add_quad(s, {-3, 0, -1.5f}, {6, 0, 0}, {0, 1.5f, 0}, 2);
  add_quad(s, {-1.2f, 0.3f, -0.8f}, {1, 0, 0}, {0, 1, 0}, 3);  // green, nearer
  add_quad(s, {-1.5f, 1.0f, -1.2f}, {1, 0, 0}, {0, 1, 0}, 4);  // red, farther, over the sky
  Light sun;
  sun.name = "sun";
  sun.direction = glm::vec3(0, -1, 0);
  sun.intensity = 2.0f;
  sun.casts_shadows = true;
  sun.shadow_resolution = 256;
  s.lights.push_back(sun);
  Camera c;
  c.name = "cam";
  c.position = {0, 0.6f, 3};
  c.target = {-0.2f, 0.3f, 0};
  c.yfov_deg = 55.0f;
  s.cameras.push_back(c);
  s.ambient = glm::vec3(0.05f);
  return s;
}

TEST(GlAlpha, MaskShadowAndBlendAgreeWithCpu) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl =
      make_gl_backend({.gl_interpolation = GlInterpolation::kCpuPlanes});
  ASSERT_TRUE(gl.ok()) << gl.status().message();
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 2});
  for (const std::string technique : {"flat", "relief"}) {
    SCOPED_TRACE(technique);
    const Scene s = alpha_scene(technique);
    RenderOptions opt;
    opt.width = opt.height = kSize;
    Result<Plan> plan = make_plan(s, opt);
    ASSERT_TRUE(plan.ok()) << plan.status().message();
    Result<RenderResult> rc = cpu->render(s, *plan);
    Result<RenderResult> rg = (*gl)->render(s, *plan);
    ASSERT_TRUE(rc.ok() && rg.ok());
    const ImageDiff d = compare_images(rc->framebuffer.color, rg->framebuffer.color);
    EXPECT_GE(d.psnr_db, 35.0);
    EXPECT_LE(d.over_fraction, 0.005)
        << "max " << d.max_error << " at " << d.max_x << "," << d.max_y;
    float alpha_error = 0.0f;
    for (size_t i = 0; i < rc->framebuffer.color.pixels.size(); ++i)
      alpha_error = std::max(alpha_error, std::fabs(rc->framebuffer.color.pixels[i].a -
                                                    rg->framebuffer.color.pixels[i].a));
    EXPECT_LE(alpha_error, 1.0f / 255);
  }
}

}  // namespace
}  // namespace relief
