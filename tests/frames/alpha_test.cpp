// glTF alpha modes (docs/scene-format.md, "Alpha"): MASK discards below alphaCutoff in the main
// pass and in the shadow passes (cut-outs cast cut-out shadows, with the plugin's own shadow-pass
// variant or polygon depth), BLEND is composited src-over after the opaque draws, back to front
// per draw whatever the submission order, and bit-identical for any thread count; `relief render
// --alpha` chooses the PNG's channels by the flag, not by content.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include <OpenImageIO/imageio.h>
#include <glm/geometric.hpp>

#include "builtin/builtin_room.h"
#include "render/render.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "scene/image_io.h"
#include "scene/mesh_prep.h"
#include "tests/apps/cli_run.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

constexpr int kW = 96, kH = 72;
const glm::vec4 kBackground{0.1f, 0.2f, 0.3f, 1.0f};

int add_rect_instance(Scene& s, glm::vec3 corner, glm::vec3 eu, glm::vec3 ev, int material) {
  Mesh m;
  add_rect(m, corner, eu, ev, glm::vec2(1.0f));
  prepare_mesh(m);
  s.meshes.push_back(std::move(m));
  s.instances.push_back({static_cast<int>(s.meshes.size()) - 1, material, glm::mat4(1.0f)});
  return static_cast<int>(s.instances.size()) - 1;
}

// 8x8 white RGBA8, alpha 0 where u < 0.5 and 1 elsewhere; nearest, clamped.
TexturePtr half_transparent_texture() {
  std::vector<uint8_t> texels(8 * 8 * 4, 255);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 4; ++x) texels[(y * 8 + x) * 4 + 3] = 0;
  auto t = std::make_shared<Texture>(TexFormat::kRGBA8, 8, 8, texels.data(), ColorSpace::kSRGB);
  t->generate_mips();
  return t;
}

Material flat_material(const std::string& name, glm::vec4 color) {
  Material m;
  m.name = name;
  m.technique = "flat";
  m.base_color = color;
  m.double_sided = true;
  return m;
}

Camera camera(glm::vec3 from, glm::vec3 to) {
  Camera c;
  c.name = "test";
  c.position = from;
  c.target = to;
  c.yfov_deg = 50.0f;
  c.znear = 0.05f;
  c.zfar = 30.0f;
  return c;
}

Light sun(glm::vec3 travel, bool shadows) {
  Light l;
  l.name = "sun";
  l.direction = glm::normalize(travel);
  l.intensity = 2.0f;
  l.casts_shadows = shadows;
  l.shadow_resolution = 512;
  return l;
}

RenderResult render(const Scene& scene, int threads = 2, int tile = 64, int w = kW, int h = kH) {
  RenderOptions opt;
  opt.width = w;
  opt.height = h;
  Result<Plan> plan = make_plan(scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  Result<RenderResult> r =
      make_cpu_backend({.threads = threads, .tile_size = tile})->render(scene, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return std::move(r).value();
}

glm::ivec2 project(const Scene& s, glm::vec3 p) {
  const Camera& c = s.cameras[0];
  const glm::vec4 q = c.projection(float(kW) / kH) * c.view() * glm::vec4(p, 1.0f);
  return {static_cast<int>(std::floor((q.x / q.w * 0.5f + 0.5f) * kW)),
          static_cast<int>(std::floor((0.5f - q.y / q.w * 0.5f) * kH))};
}

float luminance(glm::vec4 c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

// ---- MASK ---------------------------------------------------------------------------------------

// A quad facing the camera, x in [-1, 1], whose texture is transparent for x < 0.
Scene facing_quad(AlphaMode mode) {
  Scene s;
  s.name = "mask";
  s.background = kBackground;
  Material m = flat_material("cutout", glm::vec4(1.0f));
  m.textures["base_color"] = half_transparent_texture();
  m.sampler.filter = Filter::kNearest;
  m.sampler.wrap_u = m.sampler.wrap_v = Wrap::kClamp;
  m.alpha_mode = mode;
  s.materials.push_back(m);
  add_rect_instance(s, {-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, 0);
  s.lights.push_back(sun({0, 0, -1}, false));
  s.cameras.push_back(camera({0, 0, 3}, {0, 0, 0}));
  return s;
}

TEST(AlphaMask, TransparentTexelsShowTheBackground) {
  const Scene mask = facing_quad(AlphaMode::kMask);
  const Scene opaque = facing_quad(AlphaMode::kOpaque);
  const RenderResult r = render(mask);
  const RenderResult o = render(opaque);
  const glm::ivec2 left = project(mask, {-0.5f, 0, 0}), right = project(mask, {0.5f, 0, 0});
  // MASK: the transparent half is the background, colour and depth; the other half is drawn
  // with alpha 1.
  EXPECT_EQ(r.framebuffer.color.at(left.x, left.y), kBackground);
  EXPECT_EQ(r.framebuffer.depth.at(left.x, left.y), 0.0f);
  EXPECT_NE(r.framebuffer.color.at(right.x, right.y), kBackground);
  EXPECT_EQ(r.framebuffer.color.at(right.x, right.y).a, 1.0f);
  EXPECT_GT(r.framebuffer.depth.at(right.x, right.y), 0.0f);
  // OPAQUE ignores the texture's alpha: both halves are drawn, alpha 1.
  EXPECT_NE(o.framebuffer.color.at(left.x, left.y), kBackground);
  EXPECT_EQ(o.framebuffer.color.at(left.x, left.y).a, 1.0f);
  EXPECT_GT(r.passes.back().raster.work.discarded, 0u);
  EXPECT_EQ(o.passes.back().raster.work.discarded, 0u);
}

// A cut-out quad at height 1 over a floor, the sun straight down: the floor under the quad's
// transparent half is lit, under the other half shadowed. The camera, at height 0.5, sees the
// floor under the quad.
Scene cutout_over_floor(AlphaMode mode, const std::string& caster_technique) {
  Scene s;
  s.name = "mask_shadow";
  s.background = kBackground;
  s.materials.push_back(flat_material("floor", glm::vec4(0.8f, 0.8f, 0.8f, 1.0f)));
  Material quad;
  if (caster_technique == "flat") {
    quad = flat_material("cutout", glm::vec4(1.0f));
  } else {  // a relief caster (shadow-pass variant) with a flat depth map
    quad = procedural_relief_material(
        "cutout",
        [](float, float) {
          return ReliefTexel{0.0f, glm::vec3(1.0f)};
        },
        8, 0.05f);
    quad.technique = caster_technique;
    quad.double_sided = true;
  }
  quad.textures["base_color"] = half_transparent_texture();
  quad.sampler.filter = Filter::kNearest;
  quad.sampler.wrap_u = quad.sampler.wrap_v = Wrap::kClamp;
  quad.alpha_mode = mode;
  s.materials.push_back(quad);
  add_rect_instance(s, {-3, 0, 3}, {6, 0, 0}, {0, 0, -6}, 0);
  // facing +y, u along +x: transparent for x < 0
  add_rect_instance(s, {-0.5f, 1, 0.5f}, {1, 0, 0}, {0, 0, -1}, 1);
  s.lights.push_back(sun({0.0f, -1.0f, 0.0f}, true));
  s.cameras.push_back(camera({0, 0.5f, 3}, {0, 0, 0}));
  s.ambient = glm::vec3(0.05f);
  return s;
}

TEST(AlphaMask, CutoutCastsACutoutShadow) {
  for (const std::string technique : {"flat", "relief"}) {
    SCOPED_TRACE(technique);
    const Scene mask = cutout_over_floor(AlphaMode::kMask, technique);
    const Scene opaque = cutout_over_floor(AlphaMode::kOpaque, technique);
    Scene lit = mask;
    lit.instances.pop_back();  // no caster: the floor unshadowed
    const RenderResult rm = render(mask), ro = render(opaque), rl = render(lit);
    const glm::ivec2 hole = project(mask, {-0.25f, 0, 0}), solid = project(mask, {0.25f, 0, 0});
    const float lit_hole = luminance(rl.framebuffer.color.at(hole.x, hole.y));
    const float lit_solid = luminance(rl.framebuffer.color.at(solid.x, solid.y));
    ASSERT_GT(lit_hole, 0.3f);
    // MASK: light through the hole, shadow under the solid half
    EXPECT_NEAR(luminance(rm.framebuffer.color.at(hole.x, hole.y)), lit_hole, 1e-4f);
    EXPECT_LT(luminance(rm.framebuffer.color.at(solid.x, solid.y)), 0.3f * lit_solid);
    // OPAQUE: shadow under both halves
    EXPECT_LT(luminance(ro.framebuffer.color.at(hole.x, hole.y)), 0.3f * lit_hole);
    EXPECT_LT(luminance(ro.framebuffer.color.at(solid.x, solid.y)), 0.3f * lit_solid);
  }
}

// ---- BLEND --------------------------------------------------------------------------------------

// An opaque quad at z = 0 filling the view and blended quads in front of it, each at its z, in
// the order given.
struct Layer {
  glm::vec4 color;
  float z;
};
Scene layered(const std::vector<Layer>& blended, AlphaMode mode = AlphaMode::kBlend) {
  Scene s;
  s.name = "blend";
  s.background = kBackground;
  s.materials.push_back(flat_material("back", glm::vec4(0.2f, 0.3f, 0.9f, 1.0f)));
  add_rect_instance(s, {-4, -4, 0}, {8, 0, 0}, {0, 8, 0}, 0);
  for (const Layer& l : blended) {
    Material m = flat_material("layer", l.color);
    m.alpha_mode = mode;
    s.materials.push_back(m);
    add_rect_instance(s, {-1, -1, l.z}, {2, 0, 0}, {0, 2, 0},
                      static_cast<int>(s.materials.size()) - 1);
  }
  s.lights.push_back(sun({0.2f, -0.3f, -1.0f}, false));
  s.cameras.push_back(camera({0, 0, 4}, {0, 0, 0}));
  return s;
}

glm::vec4 centre(const RenderResult& r) {
  return r.framebuffer.color.at(kW / 2, kH / 2);
}

// src-over of straight colour c (alpha a) onto premultiplied d
glm::vec4 over(glm::vec3 c, float a, glm::vec4 d) {
  return glm::vec4(c * a + glm::vec3(d) * (1.0f - a), a + d.a * (1.0f - a));
}

void expect_near(glm::vec4 a, glm::vec4 b, float tol) {
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(a[k], b[k], tol) << "channel " << k;
}

TEST(AlphaBlend, IsSourceOverTheOpaqueQuad) {
  const Layer red{{1.0f, 0.1f, 0.1f, 0.4f}, 0.5f};
  const RenderResult back = render(layered({}));
  const RenderResult red_opaque = render(layered({red}, AlphaMode::kOpaque));
  const RenderResult blended = render(layered({red}));
  const glm::vec4 expect = over(glm::vec3(centre(red_opaque)), 0.4f, centre(back));
  expect_near(centre(blended), expect, 1e-5f);
  EXPECT_NE(centre(blended), centre(back));
  EXPECT_NE(centre(blended), centre(red_opaque));
  // the blended quad writes no depth: the opaque quad's depth is kept
  EXPECT_EQ(blended.framebuffer.depth.at(kW / 2, kH / 2),
            back.framebuffer.depth.at(kW / 2, kH / 2));
  // behind the opaque quad, a blended quad is not seen
  const RenderResult hidden = render(layered({{red.color, -0.5f}}));
  EXPECT_EQ(centre(hidden), centre(back));
}

TEST(AlphaBlend, TwoBlendedQuadsAreSortedBackToFront) {
  const Layer red{{1.0f, 0.1f, 0.1f, 0.5f}, 0.5f}, green{{0.1f, 1.0f, 0.1f, 0.5f}, 1.0f};
  const RenderResult back = render(layered({}));
  const glm::vec3 r = glm::vec3(centre(render(layered({red}, AlphaMode::kOpaque))));
  const glm::vec3 g = glm::vec3(centre(render(layered({green}, AlphaMode::kOpaque))));
  const glm::vec4 right = over(g, 0.5f, over(r, 0.5f, centre(back)));  // red is farther
  const glm::vec4 wrong = over(r, 0.5f, over(g, 0.5f, centre(back)));
  ASSERT_GT(glm::length(right - wrong), 0.05f);
  const RenderResult near_last = render(layered({red, green}));
  const RenderResult near_first = render(layered({green, red}));
  expect_near(centre(near_last), right, 1e-5f);
  expect_near(centre(near_first), right, 1e-5f);
  EXPECT_EQ(centre(near_last), centre(near_first));
}

TEST(AlphaBlend, BitIdenticalForAnyThreadCount) {
  // overlapping blended quads of several depths, partly outside each other, small tiles
  Scene s = layered({{{1.0f, 0.1f, 0.1f, 0.5f}, 0.3f},
                     {{0.1f, 1.0f, 0.1f, 0.35f}, 0.9f},
                     {{0.9f, 0.9f, 0.1f, 0.6f}, 0.6f}});
  s.instances[2].transform = glm::mat4(1.0f);
  s.instances[2].transform[3] = glm::vec4(0.4f, 0.3f, 0.0f, 1.0f);
  s.instances[3].transform[3] = glm::vec4(-0.3f, -0.2f, 0.0f, 1.0f);
  const RenderResult one = render(s, 1, 16, 160, 120);
  for (int threads : {2, 3}) {
    const RenderResult many = render(s, threads, 16, 160, 120);
    ASSERT_EQ(one.framebuffer.color.pixels.size(), many.framebuffer.color.pixels.size());
    EXPECT_EQ(std::memcmp(one.framebuffer.color.pixels.data(), many.framebuffer.color.pixels.data(),
                          one.framebuffer.color.pixels.size() * sizeof(glm::vec4)),
              0)
        << threads << " threads";
  }
}

TEST(AlphaBlend, BlendedSurfacesCastNoShadow) {
  Scene s = cutout_over_floor(AlphaMode::kBlend, "flat");
  RenderOptions opt;
  opt.width = kW;
  opt.height = kH;
  Result<Plan> plan = make_plan(s, opt);
  ASSERT_TRUE(plan.ok());
  EXPECT_FALSE(plan->materials[1].shadow_caster);
  EXPECT_NE(plan->explain().find("BLEND"), std::string::npos) << plan->explain();
}

// ---- glTF and the CLI's --alpha -----------------------------------------------------------------

// `relief ARGS` under a 20 s timeout (a hang fails instead of blocking the run)
CliRun relief_cli(const std::string& args) {
  return run_shell("timeout 20 " + std::string(RELIEF_CLI) + " " + args);
}

int png_channels(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return -1;
  const int n = in->spec().nchannels;
  in->close();
  return n;
}

// A blended quad (alpha 0.5) over a transparent background, saved as glTF.
std::string blended_quad_gltf(const std::filesystem::path& dir, AlphaMode mode) {
  Scene s = layered({{{1.0f, 0.2f, 0.2f, 0.5f}, 0.5f}}, mode);
  s.instances.erase(s.instances.begin());  // no opaque quad: the background shows through
  s.background = glm::vec4(0.0f, 0.0f, 0.0f, 0.0f);
  s.materials[1].alpha_cutoff = 0.25f;
  const std::string path = (dir / "quad.gltf").string();
  EXPECT_TRUE(save_gltf(s, path).ok());
  return path;
}

TEST(AlphaGltf, ModeAndCutoffRoundTrip) {
  const std::filesystem::path dir = test::fresh_test_dir("alpha_gltf");
  for (AlphaMode mode : {AlphaMode::kOpaque, AlphaMode::kMask, AlphaMode::kBlend}) {
    Result<Scene> s = load_scene(blended_quad_gltf(dir, mode));
    ASSERT_TRUE(s.ok()) << s.status().message();
    const Material* layer = nullptr;
    for (const Material& m : s->materials) {
      if (m.name == "layer") {
        layer = &m;
      } else {
        EXPECT_EQ(m.alpha_mode, AlphaMode::kOpaque) << m.name;
      }
    }
    ASSERT_NE(layer, nullptr);
    EXPECT_EQ(layer->alpha_mode, mode);
    if (mode == AlphaMode::kMask) {
      EXPECT_EQ(layer->alpha_cutoff, 0.25f);
    }
  }
}

// The MASK shadow scene and the two blended quads through save_gltf and load_gltf render as
// before (alphaMode and alphaCutoff are written and read back).
TEST(AlphaGltf, CutoutAndBlendScenesRenderTheSameAfterARoundTrip) {
  const std::filesystem::path dir = test::fresh_test_dir("alpha_round_trip");
  Scene mask = cutout_over_floor(AlphaMode::kMask, "flat");
  mask.materials[1].alpha_cutoff = 0.3f;
  const Scene blend = layered({{{1.0f, 0.1f, 0.1f, 0.5f}, 0.5f}, {{0.1f, 1.0f, 0.1f, 0.5f}, 1.0f}});
  for (const auto& [name, scene] : {std::pair{"mask", mask}, std::pair{"blend", blend}}) {
    SCOPED_TRACE(name);
    const std::string path = (dir / (std::string(name) + ".gltf")).string();
    ASSERT_TRUE(save_gltf(scene, path).ok());
    Result<Scene> back = load_scene(path);
    ASSERT_TRUE(back.ok()) << back.status().message();
    const RenderResult a = render(scene), b = render(*back);
    float worst = 0.0f;
    for (size_t i = 0; i < a.framebuffer.color.pixels.size(); ++i)
      for (int k = 0; k < 4; ++k)
        worst = std::max(
            worst, std::fabs(a.framebuffer.color.pixels[i][k] - b.framebuffer.color.pixels[i][k]));
    EXPECT_LE(worst, 1e-6f);
  }
}

TEST(AlphaCli, OutputAlphaFlagChoosesTheChannels) {
  const std::filesystem::path dir = test::fresh_test_dir("alpha_cli");
  const std::string scene = blended_quad_gltf(dir, AlphaMode::kBlend);
  struct Case {
    const char* mode;
    int channels;
  };
  for (const Case c : {Case{"none", 3}, Case{"straight", 4}, Case{"premultiplied", 4}}) {
    SCOPED_TRACE(c.mode);
    for (const char* ext : {".png", ".exr"}) {
      const std::string out = (dir / (std::string(c.mode) + ext)).string();
      const CliRun r = relief_cli("render '" + scene + "' --size 32x24 --alpha " + c.mode +
                                  " -o '" + out + "' -q");
      ASSERT_EQ(r.code, 0) << r.out;
      EXPECT_EQ(png_channels(out), c.channels) << out;
    }
    Result<Image> im = read_image((dir / (std::string(c.mode) + ".exr")).string());
    ASSERT_TRUE(im.ok());
    const glm::vec4 mid = im->pixels[12 * 32 + 16], corner = im->pixels[0];
    if (c.channels == 4) {
      EXPECT_FLOAT_EQ(mid.a, 0.5f);  // the quad's alpha over a transparent background
      EXPECT_EQ(corner.a, 0.0f);
    }
  }
  // premultiplied = straight x alpha (both files now written)
  Result<Image> st = read_image((dir / "straight.exr").string());
  Result<Image> pm = read_image((dir / "premultiplied.exr").string());
  Result<Image> no = read_image((dir / "none.exr").string());
  ASSERT_TRUE(st.ok() && pm.ok() && no.ok());
  const size_t mid = 12 * 32 + 16;
  EXPECT_GT(st->pixels[mid].r, 0.0f);
  EXPECT_NEAR(pm->pixels[mid].r, st->pixels[mid].r * 0.5f, 1e-5f);
  EXPECT_NEAR(no->pixels[mid].r, pm->pixels[mid].r, 1e-6f);  // none: over black
  // PNG: straight alpha 128 of 255 in the middle, 0 in the corner
  Result<Image> png = read_image((dir / "straight.png").string());
  ASSERT_TRUE(png.ok());
  EXPECT_NEAR(png->pixels[mid].a, 0.5f, 1.0f / 255);
  EXPECT_EQ(png->pixels[0].a, 0.0f);
  // a bad value is a usage error naming the option
  const CliRun bad = relief_cli("render '" + scene + "' --size 8x8 --alpha half -o '" +
                                (dir / "x.png").string() + "'");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("--alpha"), std::string::npos) << bad.out;
}

}  // namespace
}  // namespace relief
