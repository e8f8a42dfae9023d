// The frame API: what the CLI, sweep, the benchmarks, the tests and the embed example render
// through (DESIGN.md, "One frame, as data").
//
//   Renderer renderer(make_cpu_backend({.threads = 0}));   // or make_backend("gl", config)
//   Result<Frame> frame = renderer.render(scene, options);  // plan, then the backend runs it
//   ... use frame->result.framebuffer, frame->plan.explain(), frame->bake ...
//   renderer.recycle(std::move(*frame));                    // the next frame reuses its buffers
//
// A frame is two steps, each callable on its own: plan() checks the options against the scene
// (techniques, parameters, camera, shadow settings: make_plan is the one validator), binds every
// material to its plugin and fetches the derived maps it needs from their cache; execute() hands
// the plan to the backend, which reads nothing else. Threads, tile size and device belong to the
// backend (BackendConfig, fixed when it is made); size, AOVs and passes to the plan.
#pragma once

#include <memory>
#include <string>

#include "base/status.h"
#include "render/derived_maps.h"
#include "render/render.h"
#include "scene/scene.h"

namespace relief {

// What the derived-map cache did during one plan (render/derived_maps.h).
struct BakeStats {
  int baked = 0, memory_hits = 0, disk_hits = 0;
  double bake_ms = 0.0, cache_ms = 0.0;
  int cached() const { return memory_hits + disk_hits; }
  // The counters' change since `before` was read.
  static BakeStats since(const DerivedMapCounters& before);
};

// One rendered frame: the plan it ran (for --explain and --stats), the backend's result and the
// derived maps its plan baked or found in the cache.
struct Frame {
  Plan plan;
  RenderResult result;
  BakeStats bake;
};

class Renderer {
 public:
  explicit Renderer(std::unique_ptr<Backend> backend);

  // The plan of a frame: make_plan(scene, options), with what the derived-map cache did for it.
  Result<Plan> plan(const Scene& scene, const RenderOptions& options, BakeStats* bake = nullptr);
  // Runs a plan made for `scene` (by plan() or make_plan, possibly edited by the caller).
  Result<RenderResult> execute(const Scene& scene, const Plan& plan);
  // plan() then execute().
  Result<Frame> render(const Scene& scene, const RenderOptions& options);

  // Hands a finished frame back, so that the next frame of the same size reuses its buffers.
  void recycle(Frame&& done) { recycle(std::move(done.result)); }
  void recycle(RenderResult&& done) { backend_->recycle(std::move(done)); }

  Backend& backend() { return *backend_; }
  std::string backend_name() const { return backend_->name(); }

 private:
  std::unique_ptr<Backend> backend_;
};

}  // namespace relief
