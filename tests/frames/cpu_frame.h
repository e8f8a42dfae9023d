// One frame rendered on the CPU backend from a test, shared by the render, scene and sweep tests.
#pragma once

#include <optional>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "render/renderer.h"

namespace relief::test {

// Options for a width x height frame on 2 threads with `technique` (empty: the scene's own).
inline RenderOptions cpu_options(int width, int height, const std::string& technique = "") {
  RenderOptions opt;
  opt.width = width;
  opt.height = height;
  opt.technique = technique;
  return opt;
}

// `scene` planned and rendered with `opt` on a 2-thread CPU backend; nullopt (and a test failure
// naming opt.technique) when planning or rendering fails.
inline std::optional<Framebuffer> render_frame(const Scene& scene, const RenderOptions& opt) {
  Renderer renderer(make_cpu_backend({.threads = 2}));
  Result<Frame> frame = renderer.render(scene, opt);
  EXPECT_TRUE(frame.ok()) << opt.technique << ": " << frame.status().message();
  if (!frame.ok()) return std::nullopt;
  return std::move(frame->result.framebuffer);
}

}  // namespace relief::test
