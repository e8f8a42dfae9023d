// One frame rendered on the CPU backend from a test, shared by the render, scene and sweep tests.
#pragma once

#include <optional>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "render/render.h"

namespace relief::test {

// Options for a width x height frame on 2 threads with `technique` (empty: the scene's own).
inline RenderOptions cpu_options(int width, int height, const std::string& technique = "") {
  RenderOptions opt;
  opt.width = width;
  opt.height = height;
  opt.threads = 2;
  opt.technique = technique;
  return opt;
}

// `scene` planned and rendered with `opt` on a 2-thread CPU backend; nullopt (and a test failure
// naming opt.technique) when planning or rendering fails.
inline std::optional<Framebuffer> render_frame(const Scene& scene, const RenderOptions& opt) {
  Result<Plan> plan = make_plan(scene, opt);
  EXPECT_TRUE(plan.ok()) << opt.technique << ": " << plan.status().message();
  if (!plan.ok()) return std::nullopt;
  Result<RenderResult> r = make_cpu_backend(2)->render(scene, *plan, opt);
  EXPECT_TRUE(r.ok()) << opt.technique;
  if (!r.ok()) return std::nullopt;
  return std::move(r->framebuffer);
}

}  // namespace relief::test
