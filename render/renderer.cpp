// The frame API (render/renderer.h).
#include "render/renderer.h"

#include <utility>

namespace relief {

BakeStats BakeStats::since(const DerivedMapCounters& before) {
  const DerivedMapCounters now = derived_map_counters();
  BakeStats d;
  d.baked = now.baked - before.baked;
  d.memory_hits = now.memory_hits - before.memory_hits;
  d.disk_hits = now.disk_hits - before.disk_hits;
  d.bake_ms = now.bake_ms - before.bake_ms;
  d.cache_ms = now.cache_ms - before.cache_ms;
  return d;
}

Renderer::Renderer(std::unique_ptr<Backend> backend) : backend_(std::move(backend)) {}

Result<Plan> Renderer::plan(const Scene& scene, const RenderOptions& options, BakeStats* bake) {
  const DerivedMapCounters before = derived_map_counters();
  Result<Plan> plan = make_plan(scene, options);
  if (bake) *bake = BakeStats::since(before);
  return plan;
}

Result<RenderResult> Renderer::execute(const Scene& scene, const Plan& plan) {
  return backend_->render(scene, plan);
}

Result<Frame> Renderer::render(const Scene& scene, const RenderOptions& options) {
  Frame frame;
  Result<Plan> plan = this->plan(scene, options, &frame.bake);
  if (!plan.ok()) return plan.status();
  frame.plan = std::move(plan).value();
  Result<RenderResult> result = execute(scene, frame.plan);
  if (!result.ok()) return result.status();
  frame.result = std::move(result).value();
  return frame;
}

}  // namespace relief
