// Numerical-stability properties of every registered technique (issue 10, item 1), swept over
// fixed-seed random cases for the scalar and the 8-lane path: rays from grazing (0.01 degrees) to
// exactly along the normal, exactly along a texture axis; depth scale 0, default and the schema's
// maximum; tiling 1e-3 .. 1e3; depth maps from 1x1 to 4096x4096 and non-square, all 0, all 1,
// one-texel spikes and walls, noise; degenerate tangent frames and uv; positions at 1e5;
// quadrics flat, convex, concave, saddle, huge and tiny, seen from the front and the back; the
// nearest fragment on the near plane, or the farthest on a finite far plane (so displaced hits
// lie beyond it).
//   (steep parallax alternates its self-shadow between the ray and shadow=depth at full strength)
//   - colour, depth and every AOV are finite; hit depth in [0, 1]; a written depth lies in
//     [0, the fragment's depth] (reversed-Z: never nearer than the surface, 0 beyond the far
//     plane);
//   - the hit lies on the view ray: hit uv = uv + hit_depth * ds, ds = V.xy * scale / -V.z (the
//     texture-space ray of shaders_cpp/ray.h), for every technique that searches along the ray
//     (parallax's single offset only has to point along it, and so does relief_quadric's hit on a
//     curved quadric: its ray bends in depth, not in uv);
//   - the cone techniques (cone, cone_quad, relaxed_cone) never hit earlier than `exact`: before
//     exact's first hit the ray is in the air, and their hits are samples at or under the surface
//     (issue 22; until then conservative cones were never *later* than exact, and stopped in the
//     air where they ran out of steps; their fallback may now reach a later layer, docs/cones.md).
// A failure prints the case (seed, plugin, lanes, ray, texture, parameters) to rerun it alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "bake/cone_map.h"
#include "plugins/plugin.h"
#include "plugins/registry.h"
#include "render/derived_maps.h"

namespace relief {
namespace {

constexpr double kPi = 3.14159265358979323846;

enum class Content { kZero, kOne, kSpike, kWall, kNoise };
const char* const kContentName[] = {"all0", "all1", "spike", "wall", "noise"};

// Per-vertex quadric coefficients (a, b) of the surface (varying::kQuadric; relief_quadric's).
const float kQuadrics[][2] = {{0.0f, 0.0f}, {0.5f, 0.5f},  {-0.5f, -0.5f}, {0.5f, -0.5f},
                              {1e4f, 1e4f}, {-1e4f, 1e4f}, {1e-7f, 1e-7f}, {0.0f, 2.0f}};
const char* const kClipName[] = {"inside", "near plane", "far plane"};

struct TexCase {
  int w, h;
  Content content;
};

// Depth maps, built once per (size, content).
const Texture& depth_map(const TexCase& c) {
  static std::map<std::tuple<int, int, int>, std::unique_ptr<Texture>> cache;
  auto& slot = cache[{c.w, c.h, static_cast<int>(c.content)}];
  if (!slot) {
    std::vector<float> d(static_cast<size_t>(c.w) * c.h, c.content == Content::kOne ? 1.0f : 0.0f);
    std::mt19937 rng(c.w * 7919 + c.h);
    for (int y = 0; y < c.h; ++y)
      for (int x = 0; x < c.w; ++x) {
        float& v = d[static_cast<size_t>(y) * c.w + x];
        if (c.content == Content::kSpike) v = (x == c.w / 2 && y == c.h / 2) ? 1.0f : 0.0f;
        if (c.content == Content::kWall) v = x == c.w / 2 ? 0.0f : 1.0f;  // one-texel wall
        if (c.content == Content::kNoise) v = std::uniform_real_distribution<float>(0, 1)(rng);
      }
    slot = std::make_unique<Texture>(Texture::from_floats(TexFormat::kR32F, c.w, c.h, d.data()));
    slot->generate_mips(MipReduce::kAverage);
  }
  return *slot;
}

// The map a derived slot holds, baked from the depth map (constant maps: the exact constant).
const Texture* derived_map(const std::string& slot, const TexCase& c) {
  static std::map<std::tuple<std::string, int, int, int>, std::unique_ptr<Texture>> cache;
  auto& out = cache[{slot, c.w, c.h, static_cast<int>(c.content)}];
  if (!out && slot == kMaxMipSlotName) {  // lod=max-mip's chain (render/derived_maps.h)
    out = std::make_unique<Texture>(max_mip_chain(depth_map(c), Wrap::kRepeat, Wrap::kRepeat));
  }
  if (!out) {
    ConeBakeOptions o;
    o.wrap = true;
    o.kind = slot == "cone_quad"           ? ConeKind::kQuad
             : slot == "cone_conservative" ? ConeKind::kConservative
                                           : ConeKind::kRelaxed;
    o.bilinear = true;
    if (c.w * c.h > 256 * 256) {  // flat maps only at this size: every cone is as wide as allowed
      ConeRatios r;
      r.width = c.w;
      r.height = c.h;
      r.channels = o.kind == ConeKind::kQuad ? 4 : 1;
      r.values.assign(static_cast<size_t>(c.w) * c.h * r.channels, o.max_ratio);
      out = std::make_unique<Texture>(cone_ratios_to_texture(r));
    } else {
      out = std::make_unique<Texture>(bake_cone_map(depth_map(c), o));
    }
  }
  return out.get();
}

struct Case {
  uint32_t seed;
  double elevation_deg;  // angle between the view ray and the surface
  double azimuth_deg;    // direction of the ray in the tangent plane (0 = +u)
  double tiling;         // uv per world unit
  glm::dvec3 origin;     // world position of the patch
  TexCase tex;
  int scale_choice;  // 0: depth scale 0, 1: default, 2: the schema maximum
  int frame_kind;    // 0: regular, 1: tangent along the normal, 2: zero tangent, 3: zero normal
  bool constant_uv;  // every lane at the same uv (zero derivatives)
  int quadric;       // index into kQuadrics
  bool back_facing;  // the eye below the surface, the packet back-facing
  int clip;  // 0: eye 2 units away, 1: nearest lane on the near plane, 2: farthest on the far

  std::string describe() const {
    std::ostringstream os;
    os << "seed " << seed << ": elevation " << elevation_deg << " deg, azimuth " << azimuth_deg
       << " deg, tiling " << tiling << ", origin (" << origin.x << ", " << origin.y << ", "
       << origin.z << "), depth " << tex.w << "x" << tex.h << " " << kContentName[int(tex.content)]
       << ", scale choice " << scale_choice << ", frame " << frame_kind << ", constant uv "
       << constant_uv << ", quadric (" << kQuadrics[quadric][0] << ", " << kQuadrics[quadric][1]
       << ")" << (back_facing ? " from the back" : "") << ", " << kClipName[clip];
    return os.str();
  }
};

Case make_case(uint32_t seed) {
  std::mt19937 rng(seed);
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<uint32_t>(n)); };
  auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  Case c{};
  c.seed = seed;
  const double elevations[] = {0.01, 0.1, 1.0, 10.0, 45.0, 89.99, 90.0, uni(0.01, 90.0)};
  c.elevation_deg = elevations[pick(8)];
  const double azimuths[] = {0.0, 90.0, 180.0, 270.0, uni(0.0, 360.0)};
  c.azimuth_deg = azimuths[pick(5)];
  const double tilings[] = {1e-3, 0.1, 1.0, 10.0, 1e3};
  c.tiling = tilings[pick(5)];
  c.origin = pick(4) == 0 ? glm::dvec3(1e5, -1e5, 1e5) : glm::dvec3(uni(-2, 2), uni(-2, 2), 0.0);
  const TexCase texes[] = {
      {1, 1, Content::kZero},      {1, 1, Content::kOne},      {2, 2, Content::kSpike},
      {3, 1, Content::kNoise},     {1, 5, Content::kWall},     {16, 16, Content::kSpike},
      {32, 16, Content::kWall},    {16, 64, Content::kNoise},  {64, 64, Content::kWall},
      {4096, 4096, Content::kOne}, {2, 4096, Content::kSpike}, {4096, 2, Content::kOne}};
  c.tex = texes[pick(12)];
  c.scale_choice = pick(3);
  c.frame_kind = pick(8) < 5 ? 0 : 1 + pick(3);
  c.constant_uv = pick(6) == 0;
  // drawn after the rest, so the earlier fields of every seed are what they were before these
  c.quadric = pick(2) == 0 ? 0 : pick(8);
  c.back_facing = pick(4) == 0;
  c.clip = pick(3);
  return c;
}

// One packet of 8 x 8 fragments of the plane through `origin` with normal +z, seen along the
// case's ray; the textures each slot of `p` names.
struct PacketCase {
  FrameUniforms frame;
  MaterialUniforms material;
  FragmentPacket packet;
  glm::dvec3 ray;  // unit view direction, world = tangent space for the regular frame
  float uv0[kPacketLanes][2];

  PacketCase(const PluginDescriptor& p, const Case& c) : plugin(&p) {
    const double el = c.elevation_deg * kPi / 180.0, az = c.azimuth_deg * kPi / 180.0;
    ray = glm::dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el));
    if (c.elevation_deg == 90.0) ray = glm::dvec3(0, 0, -1);  // exactly along the normal
    if (c.back_facing) ray.z = -ray.z;  // seen from below: the back of a two-sided surface
    const bool constant_uv = c.constant_uv;
    auto lane_offset = [constant_uv](int ln) {  // lane ln's offset from origin in the plane
      const int q = ln / 4, l = ln % 4;
      const double spacing = 0.004;
      if (constant_uv) return glm::dvec3(0.0);
      return glm::dvec3(spacing * ((q % 4) * 2 + (l & 1)), spacing * ((q / 4) * 2 + (l >> 1)), 0.0);
    };
    // the lanes' view depths are eye_distance + dot(offset, ray)
    double nearest = 0.0, farthest = 0.0;
    for (int ln = 0; ln < kPacketLanes; ++ln) {
      nearest = std::min(nearest, glm::dot(lane_offset(ln), ray));
      farthest = std::max(farthest, glm::dot(lane_offset(ln), ray));
    }
    const double near = 0.1;
    const double eye_distance = c.clip == 1 ? near * (1.0 + 1e-6) - nearest : 2.0;
    const glm::dvec3 eye = c.origin - ray * eye_distance;
    frame.eye = glm::vec3(eye);
    glm::mat4 proj(0.0f);  // reversed-Z, near 0.1: infinite, or finite (far = 0 depth)
    proj[0][0] = proj[1][1] = 1.0f;
    proj[2][3] = -1.0f;
    proj[3][2] = static_cast<float>(near);
    if (c.clip == 2) {
      const double far = (eye_distance + farthest) * (1.0 + 1e-6);
      proj[2][2] = static_cast<float>(near / (far - near));
      proj[3][2] = static_cast<float>(far * near / (far - near));
    }
    const glm::dvec3 up = std::abs(ray.z) > 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
    const glm::dmat4 view = glm::lookAt(eye, c.origin, up);
    frame.view = glm::mat4(view);
    frame.view_proj = proj * frame.view;
    frame.num_lights = 1;
    frame.lights[0].direction = glm::normalize(glm::vec3(0.6f, 0.2f, -0.5f));
    frame.aovs = 0xF;

    for (int i = 0; i < p.num_params; ++i) {
      const ParamSpec& s = p.params[i];
      material.params[i] = s.default_value;
      if (std::strcmp(s.name, "depth_scale") == 0)
        material.params[i] = c.scale_choice == 0   ? s.min_value
                             : c.scale_choice == 1 ? s.default_value
                                                   : s.max_value;
      if (std::strcmp(s.name, "lod") == 0)  // the searches' LOD modes, one per case in turn
        material.params[i] = static_cast<float>(c.seed % 3);
      if (std::strcmp(s.name, "shadow") == 0)  // steep parallax: the ray, then shadow=depth
        material.params[i] = static_cast<float>(c.seed % 2);
      if (std::strcmp(s.name, "shadow_strength") == 0) material.params[i] = s.max_value;
    }
    const Texture& depth = depth_map(c.tex);
    for (int s = 0; s < p.num_textures; ++s) {
      const std::string name = p.textures[s].name;
      material.samplers[s].filter = Filter::kBilinear;
      if (name == "depth")
        material.textures[s] = &depth;
      else if (is_derived_slot(name))
        material.textures[s] = derived_map(name, c.tex);
      else if (p.textures[s].required)
        material.textures[s] = &depth;  // an unknown map
    }

    packet.num_quads = kPacketQuads;
    packet.num_varyings = varying::kCount;
    packet.front_facing = !c.back_facing;
    glm::vec3 n(0, 0, 1), t(1, 0, 0);
    if (c.frame_kind == 1) t = n;
    if (c.frame_kind == 2) t = glm::vec3(0);
    if (c.frame_kind == 3) n = glm::vec3(0);
    const float tile = static_cast<float>(1.0 / c.tiling);
    for (int q = 0; q < kPacketQuads; ++q) {
      packet.coverage[q] = 0xF;
      for (int l = 0; l < 4; ++l) {
        const int ln = q * 4 + l;
        const glm::dvec3 pos = c.origin + lane_offset(ln);
        const float u = static_cast<float>(pos.x * c.tiling),
                    v = static_cast<float>(pos.y * c.tiling);
        uv0[ln][0] = u;
        uv0[ln][1] = v;
        const float vals[varying::kCount] = {float(pos.x),
                                             float(pos.y),
                                             float(pos.z),
                                             n.x,
                                             n.y,
                                             n.z,
                                             t.x,
                                             t.y,
                                             t.z,
                                             1.0f,
                                             u,
                                             v,
                                             kQuadrics[c.quadric][0],
                                             kQuadrics[c.quadric][1],
                                             tile,
                                             tile};
        for (int k = 0; k < varying::kCount; ++k) packet.varyings[k][ln] = vals[k];
        const glm::dvec4 clip = glm::dmat4(frame.view_proj) * glm::dvec4(pos, 1.0);
        packet.frag_x[ln] = static_cast<float>(ln % 8);
        packet.frag_y[ln] = static_cast<float>(ln / 8);
        // clamped to [0, 1] as the rasterizer does (at 1e5 from the origin float rounding can put
        // the far-plane case's surface a little beyond the far plane)
        packet.frag_z[ln] = static_cast<float>(std::clamp(clip.z / clip.w, 0.0, 1.0));
        packet.inv_w[ln] = static_cast<float>(1.0 / clip.w);
      }
    }
  }

  PacketCase(const PacketCase&) = delete;
  ~PacketCase() {
    if (state) plugin->destroy_state(state);
  }

  std::unique_ptr<FragmentOutput> shade(EffectMask e, bool scalar) {
    frame.scalar_lanes = scalar;
    if (!state && plugin->create_state) state = plugin->create_state(material);
    ShadeContext ctx{&frame, &material, state, e};
    auto out = std::make_unique<FragmentOutput>();
    std::memset(out.get(), 0, sizeof(FragmentOutput));
    WorkCounters wc;
    plugin->select(e)(ctx, packet, *out, wc);
    return out;
  }

  const PluginDescriptor* plugin;
  void* state = nullptr;  // derived data, made once per case
};

// The techniques that search along the view ray (all but parallax's one offset and the
// surface-only shaders, whose hit is the fragment itself).
// shells: the hit is the fragment's own point on its shell polygon (uv unmoved, depth the
// shell's), not a point along this polygon's eye ray
bool hit_on_ray(const std::string& name, const Case& c) {
  return name != "parallax" && name != "shells" && (name != "relief_quadric" || c.quadric == 0);
}
bool cone_family(const std::string& name) {
  return name == "cone" || name == "cone_quad" || name == "relaxed_cone";
}

constexpr int kCases = 48;

TEST(Properties, EveryTechniqueFiniteOnTheRayAndConesNeverInTheAir) {
  const PluginDescriptor* exact = PluginRegistry::global().find("exact");
  ASSERT_NE(exact, nullptr);
  int checked_on_ray = 0, checked_conservative = 0;
  for (uint32_t seed = 1; seed <= kCases; ++seed) {
    const Case c = make_case(seed);
    // the ray checks below assume the tangent frame is the world frame: front-facing only
    const bool regular = c.frame_kind == 0 && !c.constant_uv && !c.back_facing;
    PacketCase exact_case(*exact, c);
    std::unique_ptr<FragmentOutput> exact_out[2];  // 8-lane, scalar; made when first needed
    for (const PluginDescriptor* p : PluginRegistry::global().all()) {
      PacketCase s(*p, c);
      const EffectMask e = p->supported_effects & (kEffectSelfShadow | kEffectDepthWrite);
      for (bool scalar : {false, true}) {
        const std::string where =
            std::string(p->name) + (scalar ? " scalar" : " 8-lane") + ", " + c.describe();
        auto o = s.shade(e, scalar);
        const FragmentOutput* ex = nullptr;
        if (cone_family(p->name) && regular) {
          if (!exact_out[scalar]) exact_out[scalar] = exact_case.shade(0, scalar);
          ex = exact_out[scalar].get();
        }
        for (int ln = 0; ln < kPacketLanes; ++ln) {
          for (int k = 0; k < 4; ++k)
            ASSERT_TRUE(std::isfinite(o->color[k][ln])) << where << " lane " << ln;
          for (int k = 0; k < kAovTotalChannels; ++k)
            ASSERT_TRUE(std::isfinite(o->aov[k][ln])) << where << " lane " << ln << " aov " << k;
          if (e & kEffectDepthWrite) {
            ASSERT_TRUE(std::isfinite(o->depth[ln])) << where << " lane " << ln;
            ASSERT_GE(o->depth[ln], 0.0f) << where << " lane " << ln;
            ASSERT_LE(o->depth[ln], s.packet.frag_z[ln]) << where << " lane " << ln;
          }
          const float hd = o->aov[kAovOffset[1]][ln];
          ASSERT_GE(hd, 0.0f) << where << " lane " << ln;
          ASSERT_LE(hd, 1.0f) << where << " lane " << ln;
          // on the ray: only where uv and the frame are well defined and float uv is precise
          const double u0 = s.uv0[ln][0], w0 = s.uv0[ln][1];
          if (!regular || std::abs(u0) + std::abs(w0) > 1e3) continue;
          const int scale_index = param_index(*p, "depth_scale");
          if (scale_index < 0) continue;
          const double scale = s.material.params[scale_index];
          const glm::dvec3 pos(s.packet.varyings[0][ln], s.packet.varyings[1][ln],
                               s.packet.varyings[2][ln]);
          const glm::dvec3 v = glm::normalize(pos - glm::dvec3(s.frame.eye));
          const double k = scale / std::max(-v.z, 1e-4);
          const double ou = o->aov[kAovOffset[0]][ln] - u0;
          const double ov = o->aov[kAovOffset[0] + 1][ln] - w0;
          const double tol = 1e-5 * (std::abs(u0) + std::abs(w0) + k + 1.0) * 8.0;
          if (hit_on_ray(p->name, c)) {
            EXPECT_NEAR(ou, hd * v.x * k, tol) << where << " lane " << ln;
            EXPECT_NEAR(ov, hd * v.y * k, tol) << where << " lane " << ln;
            ++checked_on_ray;
          } else {
            EXPECT_NEAR(ou * v.y - ov * v.x, 0.0, tol * (1.0 + k)) << where << " lane " << ln;
            EXPECT_GE(ou * v.x + ov * v.y, -tol) << where << " lane " << ln;
          }
          if (ex) {
            // never earlier than exact: nothing but air lies before its first hit
            EXPECT_GE(hd, ex->aov[kAovOffset[1]][ln] - 1e-4f) << where << " lane " << ln;
            ++checked_conservative;
          }
        }
      }
    }
  }
  EXPECT_GT(checked_on_ray, 1000);
  EXPECT_GT(checked_conservative, 100);
}

}  // namespace
}  // namespace relief
