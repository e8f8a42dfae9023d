// The relief paper's own fragment shader as a bench-only GL program: the second yardstick of
// `relief bench --backend cpu,gl` (issue 26, docs/accuracy.md "The appendix yardstick").
//
// Our GLSL twins evaluate the CPU's attribute planes and the whole shared shading per fragment,
// so the CPU backend's lead over them says little about a lean GPU shader. This program is the
// appendix of Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on Arbitrary Polygonal
// Surfaces" (I3D 2005), as the issue restates it (gl/shaders/appendix_relief_fs.glsl): its linear
// search of n - 1 samples and m halvings with no early exit, one RGBA8 texture holding the normal
// (rgb) and depth (a) read with textureLod 0, one directional light, diffuse only, no self-shadow,
// no depth write; its own vertex stage (world position, normal, tangent and uv from the mesh).
// The target is RGBA8 colour with a 32-bit float depth buffer, reversed-Z as the backends'.
//
// It draws the first instance of a scene (the sweep's view: one quad) from camera 0, lit by the
// first light (its direction; a point or spot light's from the light to the instance's centre),
// with the instance material's depth map (level 0) and normal map (level 0, resampled to the
// depth map's size when they differ; flat without one), depth_scale (0.05 unset), base colour and
// uv transform.
#pragma once

#include <memory>
#include <string>

#include "base/status.h"
#include "rasterizer/image.h"
#include "scene/scene.h"

namespace relief::gl {

class Context;

class AppendixRelief {
 public:
  // Its own context (gl/context.h: EGL device `gpu`, or -1 to pick); fails with one line when
  // none can be made.
  static Result<std::unique_ptr<AppendixRelief>> create(int gpu = -1);
  ~AppendixRelief();
  AppendixRelief(const AppendixRelief&) = delete;
  AppendixRelief& operator=(const AppendixRelief&) = delete;

  // Uploads the scene's first instance, texture and light and builds the program for
  // `linear_steps` (>= 2) + `binary_steps` (>= 0); a width x height target. Errors: no instance,
  // camera or depth map; steps out of range; a GL error.
  Status prepare(const Scene& scene, int width, int height, int linear_steps, int binary_steps);
  // One frame: clear, draw, glFinish. Returns its wall time in ms.
  Result<double> draw();
  // One frame with the hit output: colour and, per pixel, (u, v, depth, 1) of the hit ((0, 0, 0,
  // 0) where nothing is drawn); row 0 is the top, as rasterizer/image.h.
  Status draw_hits(Image& color, Image& hits);
  // GL_RENDERER of the context.
  std::string device() const;

  struct State;  // GL objects and the frame's fixed values (gl/appendix_relief.cpp)

 private:
  AppendixRelief() = default;
  std::unique_ptr<Context> ctx_;
  std::unique_ptr<State> s_;
};

}  // namespace relief::gl
