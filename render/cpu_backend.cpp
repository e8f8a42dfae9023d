// The CPU backend: executes a Plan with the tile rasterizer and the C++ plugins.
#include <chrono>
#include <memory>

#include "rasterizer/pipeline.h"
#include "render/render.h"

namespace relief {
namespace {

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

DepthTest depth_test_for(DepthOutput d) {
  switch (d) {
    case DepthOutput::kNone: return DepthTest::kEarly;
    case DepthOutput::kFarther: return DepthTest::kConservative;
    default: return DepthTest::kLate;
  }
}

class CpuBackend final : public Backend {
 public:
  explicit CpuBackend(int threads) : pool_(threads) {}
  std::string name() const override { return "cpu"; }

  Result<RenderResult> render(const Scene& scene, const Plan& plan,
                              const RenderOptions& opt) override {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    RenderResult result;
    result.device = "cpu (" + std::to_string(pool_.size()) + " threads)";
    result.framebuffer = Framebuffer(opt.width, opt.height, opt.aovs);
    result.framebuffer.clear(scene.background, 0.0f);

    // Plugin state (derived maps) per material, built once per frame here.
    std::vector<std::unique_ptr<void, void (*)(void*)>> states;
    std::vector<DrawBinding> bindings(plan.materials.size());
    std::vector<DepthTest> tests(plan.materials.size());
    for (size_t m = 0; m < plan.materials.size(); ++m) {
      const BoundMaterial& b = plan.materials[m];
      void* state = b.plugin->create_state ? b.plugin->create_state(b.uniforms) : nullptr;
      if (state) states.emplace_back(state, b.plugin->destroy_state);
      bindings[m].fn = b.plugin->select(b.effects);
      bindings[m].ctx = ShadeContext{&plan.frame, &b.uniforms, state, b.effects};
      tests[m] = depth_test_for(b.plugin->depth_output(b.effects));
    }

    const std::vector<PreparedDraw> prepared = prepare_draws(scene, plan.frame.view_proj);
    std::vector<DrawCall> draws;
    draws.reserve(prepared.size());
    for (const PreparedDraw& p : prepared) {
      const BoundMaterial& b = plan.materials[p.material];
      DrawCall dc;
      dc.clip = p.clip;
      dc.varyings = p.varyings;
      dc.num_varyings = varying::kCount;
      dc.indices = *p.indices;
      dc.cull = b.double_sided ? CullMode::kNone : CullMode::kBack;
      dc.depth_test = tests[p.material];
      dc.aov_write = opt.aovs != 0;
      dc.shader = &call_plugin;
      dc.user = &bindings[p.material];
      draws.push_back(dc);
    }
    if (!rasterizer_ || rasterizer_->config().tile_size != opt.tile_size)
      rasterizer_ = std::make_unique<Rasterizer>(pool_, RasterConfig{opt.tile_size});
    const auto t1 = Clock::now();
    PassStats main;
    main.name = "main";
    main.raster = rasterizer_->draw(result.framebuffer, draws);
    const auto t2 = Clock::now();
    main.ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
    result.passes.push_back(main);
    result.frame_ms = std::chrono::duration<double, std::milli>(t2 - t0).count();
    return result;
  }

 private:
  ThreadPool pool_;
  std::unique_ptr<Rasterizer> rasterizer_;
};

}  // namespace

std::unique_ptr<Backend> make_cpu_backend(int threads) {
  return std::make_unique<CpuBackend>(threads);
}

}  // namespace relief
