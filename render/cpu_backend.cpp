// The CPU backend: executes a Plan with the tile rasterizer and the C++ plugins: the shadow passes
// (render/shadow_map.h; Williams 1978), each a depth-only pass per face from the light, then the
// main pass, whose receivers read the maps through LightUniform::shadow.
#include <chrono>
#include <memory>
#include <string_view>

#include "plugins/surface.h"
#include "rasterizer/pipeline.h"
#include "render/render.h"

namespace relief {
namespace {

using Clock = std::chrono::steady_clock;

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// What the packet shader receives as its `user` pointer: the plugin's shade entry and context.
struct DrawBinding {
  ShadeFn fn;
  ShadeContext ctx;
};

void call_plugin(const void* user, const FragmentPacket& in, FragmentOutput& out,
                 WorkCounters& counters) {
  const auto* b = static_cast<const DrawBinding*>(user);
  b->fn(b->ctx, in, out, counters);
}

// Casters without a shadow-pass variant: polygon depth only, nothing to shade.
void depth_only(const void*, const FragmentPacket&, FragmentOutput&, WorkCounters&) {}

// MASK casters without a shadow-pass variant: polygon depth, cut out where the base colour's
// alpha at uv is below the cutoff (shade_packet's resolve_alpha discards). The material it gets
// has the plugin's base_color texture, if any, in slot 0.
struct MaskCasterKernel {
  template <class F>
  static ShadeOut<F> shade(const ShadeContext& ctx, const FragIn<F>& in) {
    ShadeOut<F> o;
    o.alpha = sample_alpha(*ctx.material, 0, in.uv, in, o.fetches);
    return o;
  }
};

// `b`'s uniforms for MaskCasterKernel: its base_color texture (when its plugin has the slot)
// moved to slot 0.
MaterialUniforms mask_caster_uniforms(const BoundMaterial& b) {
  MaterialUniforms u = b.uniforms;
  for (int s = 0; s < kMaxTextureSlots; ++s) u.textures[s] = nullptr;
  for (int s = 0; s < b.plugin->num_textures && s < kMaxTextureSlots; ++s)
    if (std::string_view(b.plugin->textures[s].name) == "base_color") {
      u.textures[0] = b.uniforms.textures[s];
      u.samplers[0] = b.uniforms.samplers[s];
      u.uv_maps[0] = b.uniforms.uv_maps[s];
    }
  return u;
}

DepthTest depth_test_for(DepthOutput d) {
  switch (d) {
    case DepthOutput::kNone:
      return DepthTest::kEarly;
    case DepthOutput::kFarther:
      return DepthTest::kConservative;
    default:
      return DepthTest::kLate;
  }
}

// An instance's draw from a view: its world positions, which the rasterizer's setup takes to
// clip space by `view_proj` (kept alive until the draw is done).
DrawCall make_draw(const PreparedInstance& p, const BoundMaterial& b, const glm::mat4& view_proj) {
  DrawCall dc;
  dc.clip = p.world;
  dc.transform = &view_proj;
  dc.varyings = p.varyings;
  dc.num_varyings = p.num_varyings;
  dc.indices = *p.indices;
  dc.cull = b.double_sided ? CullMode::kNone : CullMode::kBack;
  return dc;
}

void add_raster(RasterStats& sum, const RasterStats& s) {
  sum.triangles_in += s.triangles_in;
  sum.triangles_culled += s.triangles_culled;
  sum.triangles_clipped += s.triangles_clipped;
  sum.triangles_binned += s.triangles_binned;
  sum.quads += s.quads;
  sum.work += s.work;
  sum.setup_ms += s.setup_ms;
  sum.raster_ms += s.raster_ms;
}

class CpuBackend final : public Backend {
 public:
  explicit CpuBackend(const BackendConfig& config)
      : pool_(config.threads), tile_size_(config.tile_size) {}
  std::string name() const override { return "cpu"; }

  Result<RenderResult> render(const Scene& scene, const Plan& plan) override {
    const auto t0 = Clock::now();
    RenderResult result;
    result.device = "cpu (" + std::to_string(pool_.size()) + " threads)";
    // The main target: a recycled one of the same shape, else a new one; the rasterizer clears it
    // tile by tile.
    const int width = plan.frame.width, height = plan.frame.height;
    const AovMask aovs = plan.frame.aovs;
    if (spare_.width == width && spare_.height == height && spare_.aov_mask == aovs)
      result.framebuffer = std::move(spare_);
    else
      result.framebuffer = Framebuffer(width, height, aovs);
    spare_ = Framebuffer();
    result.target_ms = ms_between(t0, Clock::now());

    // The prepare stage: world-space vertices (kept from the last frame where an instance did
    // not change) and plugin state, shared by every pass.
    PreparedFrame prep = prepare_frame(scene, plan, &prepared_);
    result.geometry_ms = prepared_.key_ms;
    result.prepare_ms = prep.ms - prepared_.key_ms;
    result.geometry_reused = prepared_.reused;
    result.geometry_prepared = prepared_.prepared;
    if (!rasterizer_) rasterizer_ = std::make_unique<Rasterizer>(pool_, RasterConfig{tile_size_});

    // Shadow passes: one depth map per face, kept until the main pass has read them.
    FrameUniforms frame = plan.frame;
    std::vector<std::vector<Plane>> maps;
    std::vector<ShadowMapView> views;
    maps.reserve(plan.passes.size());
    views.reserve(plan.passes.size());
    for (const PassPlan& pass : plan.passes) {
      if (pass.kind != PassPlan::Kind::kShadow) continue;
      maps.push_back(shadow_pass(plan, prep, pass, result));
      views.push_back(make_shadow_view(pass.shadow, maps.back(), plan.shadow));
      frame.lights[pass.light].shadow = &views.back();
    }

    // The main pass, timed from its clip positions and draws to its last tile.
    const auto t1 = Clock::now();
    std::vector<DrawBinding> bindings(plan.materials.size());
    std::vector<DepthTest> tests(plan.materials.size());
    for (size_t m = 0; m < plan.materials.size(); ++m) {
      const BoundMaterial& b = plan.materials[m];
      bindings[m].fn = b.plugin->select(b.effects);
      bindings[m].ctx = ShadeContext{&frame, &b.uniforms, prep.state(m), b.effects};
      tests[m] = depth_test_for(b.plugin->depth_output(b.effects));
    }
    std::vector<DrawCall> draws;
    draws.reserve(prep.instances.size());
    // Plan::draw_order: opaque and MASK draws, then BLEND ones back to front (composited over
    // the opaque image, depth tested against it, not written; no AOVs).
    for (int i : main_draw_order(plan, prep.instances.size())) {
      const PreparedInstance& p = prep.instances[i];
      const BoundMaterial& b = plan.materials[p.material];
      DrawCall dc = make_draw(p, b, frame.view_proj);
      dc.depth_test = tests[p.material];
      dc.shader = &call_plugin;
      dc.user = &bindings[p.material];
      dc.blend = b.uniforms.alpha_mode == AlphaMode::kBlend;
      dc.depth_write = !dc.blend;
      dc.aov_write = aovs != 0 && !dc.blend;
      draws.push_back(dc);
    }
    PassStats main;
    main.name = "main";
    const ClearValues clear{clear_color(scene), 0.0f};
    main.raster = rasterizer_->draw(result.framebuffer, draws, &clear);
    const auto t2 = Clock::now();
    main.ms = ms_between(t1, t2);
    result.passes.push_back(main);
    shadow_planes_.clear();  // keep this frame's maps only
    for (std::vector<Plane>& faces : maps)
      for (Plane& face : faces) shadow_planes_.push_back(std::move(face));
    keep_prepared(std::move(prep), prepared_);  // frees what the last frame kept and this one left
    result.frame_ms = ms_between(t0, Clock::now());
    return result;
  }

  void recycle(RenderResult&& done) override { spare_ = std::move(done.framebuffer); }

 private:
  // Renders the depth maps of one shadow pass: every caster from each face of the light's view,
  // depth only (no colour, no AOVs); relief casters with their shadow-pass variant.
  std::vector<Plane> shadow_pass(const Plan& plan, const PreparedFrame& prep, const PassPlan& pass,
                                 RenderResult& result) {
    const auto t0 = Clock::now();
    const ShadowPassSetup& s = pass.shadow;
    PassStats stats = shadow_pass_stats(pass);
    std::vector<Plane> faces;
    std::vector<DrawBinding> bindings(plan.materials.size());
    std::vector<MaterialUniforms> mask_uniforms(plan.materials.size());
    for (int f = 0; f < s.faces; ++f) {
      const FrameUniforms frame = shadow_face_frame(s, f);
      for (size_t m = 0; m < plan.materials.size(); ++m) {
        const BoundMaterial& b = plan.materials[m];
        bindings[m].fn = b.shadow_effects ? b.plugin->select(b.shadow_effects) : nullptr;
        bindings[m].ctx = ShadeContext{&frame, &b.uniforms, prep.state(m), b.shadow_effects};
        if (!bindings[m].fn && b.uniforms.alpha_mode == AlphaMode::kMask) {
          mask_uniforms[m] = mask_caster_uniforms(b);
          bindings[m].fn = &shade_packet<MaskCasterKernel>;
          bindings[m].ctx = ShadeContext{&frame, &mask_uniforms[m], nullptr, 0};
        }
      }
      // The casters only, seen from this face.
      std::vector<DrawCall> draws;
      draws.reserve(pass.instances.size());
      for (int i : pass.instances) {
        const PreparedInstance& p = prep.instances[i];
        const BoundMaterial& b = plan.materials[p.material];
        if (!b.shadow_caster) continue;
        DrawCall dc = make_draw(p, b, frame.view_proj);
        dc.color_write = false;
        if (bindings[p.material].fn) {
          dc.depth_test = b.shadow_effects
                              ? depth_test_for(b.plugin->depth_output(b.shadow_effects))
                              : DepthTest::kEarly;  // MaskCasterKernel: polygon depth
          dc.shader = &call_plugin;
          dc.user = &bindings[p.material];
        } else {
          dc.depth_test = DepthTest::kEarly;
          dc.shader = &depth_only;
        }
        draws.push_back(dc);
      }
      // Depth only: no colour image; the depth plane comes from the previous frames' maps.
      Framebuffer fb;
      fb.width = fb.height = s.size;
      fb.depth = take_shadow_plane(s.size);
      const ClearValues far_plane{glm::vec4(0.0f), 0.0f};
      add_raster(stats.raster, rasterizer_->draw(fb, draws, &far_plane));
      faces.push_back(std::move(fb.depth));
    }
    stats.ms = ms_between(t0, Clock::now());
    result.passes.push_back(stats);
    return faces;
  }

  // A shadow-map plane of size x size: one kept from an earlier frame when there is one.
  Plane take_shadow_plane(int size) {
    for (size_t i = 0; i < shadow_planes_.size(); ++i)
      if (shadow_planes_[i].width == size && shadow_planes_[i].height == size) {
        Plane p = std::move(shadow_planes_[i]);
        shadow_planes_.erase(shadow_planes_.begin() + static_cast<std::ptrdiff_t>(i));
        return p;
      }
    return Plane(size, size);
  }

  ThreadPool pool_;
  int tile_size_ = 64;
  std::unique_ptr<Rasterizer> rasterizer_;
  Framebuffer spare_;                 // from recycle(): the next frame's main target
  std::vector<Plane> shadow_planes_;  // the last frame's shadow maps, reused by the next
  PreparedCache prepared_;            // the last frame's prepared instances
};

}  // namespace

std::unique_ptr<Backend> make_cpu_backend(const BackendConfig& config) {
  return std::make_unique<CpuBackend>(config);
}

}  // namespace relief
