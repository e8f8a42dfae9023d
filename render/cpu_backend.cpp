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
  sum.tiles += s.tiles;
  sum.tiles_drawn += s.tiles_drawn;
  sum.work += s.work;
  sum.setup_ms += s.setup_ms;
  sum.raster_ms += s.raster_ms;
}

// One face of a shadow pass: its uniforms, bindings, draws and target, which live until the main
// pass has read the face (its tiles may be drawn on demand, during the main pass).
struct ShadowFace {
  FrameUniforms frame;
  std::vector<DrawBinding> bindings;
  std::vector<MaterialUniforms> mask_uniforms;
  std::vector<DrawCall> draws;
  Framebuffer fb;
  Rasterizer* raster = nullptr;
};

// A shadow pass in flight: its faces, the tiles the main pass's lookups draw on demand
// (ShadowTiles, shaders_cpp/shadow_lookup.h), and where its stats go.
struct ShadowJob {
  std::vector<std::unique_ptr<ShadowFace>> faces;
  ShadowTiles tiles;
  size_t stats_index = 0;  // into RenderResult::passes
  double setup_ms = 0.0;   // wall time of its faces' setup (and, drawn whole, their tiles)
};

// What a shadow map's tiles are cleared to: the far plane (reversed-Z 0).
const ClearValues kFarPlane{glm::vec4(0.0f), 0.0f};

void draw_shadow_tile(const void* owner, int face, int t) {
  static_cast<const ShadowJob*>(owner)->faces[static_cast<size_t>(face)]->raster->draw_tile(t);
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

    // Shadow passes: one depth map per face, kept until the main pass has read them. On demand
    // (Plan::shadow_on_demand), a face is only set up here, and the main pass's lookups draw the
    // tiles their taps reach (ShadowTiles); else every tile is drawn here.
    FrameUniforms frame = plan.frame;
    std::vector<std::unique_ptr<ShadowJob>> jobs;
    std::vector<ShadowMapView> views;
    views.reserve(plan.passes.size());
    size_t rasters = 0;
    for (const PassPlan& pass : plan.passes) {
      if (pass.kind != PassPlan::Kind::kShadow) continue;
      jobs.push_back(shadow_pass(plan, prep, pass, result, rasters));
      const ShadowJob& job = *jobs.back();
      const float* depth[kMaxShadowFaces] = {};
      for (size_t f = 0; f < job.faces.size(); ++f) depth[f] = job.faces[f]->fb.depth.values.data();
      views.push_back(make_shadow_view(
          pass.shadow, std::span<const float* const>(depth, job.faces.size()), plan.shadow));
      if (plan.shadow_on_demand) views.back().tiles = &job.tiles;
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
    // Each shadow pass's counters, and its time: its setup, plus the thread time of the tiles
    // drawn (during the main pass when on demand) over the thread count, taken out of the main
    // pass's time.
    shadow_planes_.clear();  // keep this frame's maps only
    const double threads = static_cast<double>(pool_.size());
    for (const std::unique_ptr<ShadowJob>& job : jobs) {
      PassStats& stats = result.passes[job->stats_index];
      double tiles_ms = 0.0;
      for (const std::unique_ptr<ShadowFace>& face : job->faces) {
        const RasterStats r = face->raster->finish();
        tiles_ms += r.raster_ms;
        add_raster(stats.raster, r);
        shadow_planes_.push_back(std::move(face->fb.depth));
      }
      stats.raster.raster_ms = tiles_ms / threads;
      stats.ms = job->setup_ms + (plan.shadow_on_demand ? tiles_ms / threads : 0.0);
      if (plan.shadow_on_demand) main.ms -= tiles_ms / threads;
    }
    result.passes.push_back(main);
    keep_prepared(std::move(prep), prepared_);  // frees what the last frame kept and this one left
    result.frame_ms = ms_between(t0, Clock::now());
    return result;
  }

  void recycle(RenderResult&& done) override { spare_ = std::move(done.framebuffer); }

 private:
  // Sets up the depth maps of one shadow pass: every caster from each face of the light's view,
  // depth only (no colour, no AOVs); relief casters with their shadow-pass variant. Each face gets
  // its own rasterizer (shadow_rasters_[rasters++]), which draws its tiles on demand; unless the
  // plan asks for them on demand, every tile is drawn here.
  std::unique_ptr<ShadowJob> shadow_pass(const Plan& plan, const PreparedFrame& prep,
                                         const PassPlan& pass, RenderResult& result,
                                         size_t& rasters) {
    const auto t0 = Clock::now();
    const ShadowPassSetup& s = pass.shadow;
    auto job = std::make_unique<ShadowJob>();
    for (int f = 0; f < s.faces; ++f) {
      job->faces.push_back(std::make_unique<ShadowFace>());
      ShadowFace& face = *job->faces.back();
      face.frame = shadow_face_frame(s, f);
      face.bindings.resize(plan.materials.size());
      face.mask_uniforms.resize(plan.materials.size());
      for (size_t m = 0; m < plan.materials.size(); ++m) {
        const BoundMaterial& b = plan.materials[m];
        DrawBinding& binding = face.bindings[m];
        binding.fn = b.shadow_effects ? b.plugin->select(b.shadow_effects) : nullptr;
        binding.ctx = ShadeContext{&face.frame, &b.uniforms, prep.state(m), b.shadow_effects};
        if (!binding.fn && b.uniforms.alpha_mode == AlphaMode::kMask) {
          face.mask_uniforms[m] = mask_caster_uniforms(b);
          binding.fn = &shade_packet<MaskCasterKernel>;
          binding.ctx = ShadeContext{&face.frame, &face.mask_uniforms[m], nullptr, 0};
        }
      }
      // The casters only, seen from this face.
      face.draws.reserve(pass.instances.size());
      for (int i : pass.instances) {
        const PreparedInstance& p = prep.instances[i];
        const BoundMaterial& b = plan.materials[p.material];
        if (!b.shadow_caster) continue;
        DrawCall dc = make_draw(p, b, face.frame.view_proj);
        dc.color_write = false;
        if (face.bindings[p.material].fn) {
          dc.depth_test = b.shadow_effects
                              ? depth_test_for(b.plugin->depth_output(b.shadow_effects))
                              : DepthTest::kEarly;  // MaskCasterKernel: polygon depth
          dc.shader = &call_plugin;
          dc.user = &face.bindings[p.material];
        } else {
          dc.depth_test = DepthTest::kEarly;
          dc.shader = &depth_only;
        }
        face.draws.push_back(dc);
      }
      // Depth only: no colour image; the depth plane comes from the previous frames' maps.
      face.fb.width = face.fb.height = s.size;
      face.fb.depth = take_shadow_plane(s.size);
      if (rasters == shadow_rasters_.size())
        shadow_rasters_.push_back(
            std::make_unique<Rasterizer>(pool_, RasterConfig{kShadowTileSize}));
      face.raster = shadow_rasters_[rasters++].get();
      face.raster->prepare(face.fb, face.draws, &kFarPlane);
      if (!plan.shadow_on_demand) {
        Rasterizer& r = *face.raster;
        pool_.run(r.tiles_x() * r.tiles_y(), [&r](int tile, int) { r.draw_tile(tile); });
      }
      job->tiles.drawn[f] = face.raster->drawn();
    }
    job->tiles.shift = kShadowTileShift;
    job->tiles.per_row = job->faces.front()->raster->tiles_x();
    job->tiles.draw = &draw_shadow_tile;
    job->tiles.owner = job.get();
    job->setup_ms = ms_between(t0, Clock::now());
    job->stats_index = result.passes.size();
    result.passes.push_back(shadow_pass_stats(pass));
    return job;
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

  // Tiles of the shadow maps, in texels: the unit the main pass's lookups draw on demand.
  static constexpr int kShadowTileShift = 5;
  static constexpr int kShadowTileSize = 1 << kShadowTileShift;

  ThreadPool pool_;
  int tile_size_ = 64;
  std::unique_ptr<Rasterizer> rasterizer_;
  std::vector<std::unique_ptr<Rasterizer>> shadow_rasters_;  // one per shadow-map face in a frame
  Framebuffer spare_;                 // from recycle(): the next frame's main target
  std::vector<Plane> shadow_planes_;  // the last frame's shadow maps, reused by the next
  PreparedCache prepared_;            // the last frame's prepared instances
};

}  // namespace

std::unique_ptr<Backend> make_cpu_backend(const BackendConfig& config) {
  return std::make_unique<CpuBackend>(config);
}

}  // namespace relief
