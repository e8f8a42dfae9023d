// The GL backend (DESIGN.md, "The GL backend"): executes a Plan with OpenGL 4.5 core through EGL
// (gl/context.h) and the GLSL twins of the plugins (gl/shaders/<plugin>.frag).
//
// Both backends see the same data: vertices come from prepare_frame (clip positions and the 16
// standard varyings, uploaded as vertex attributes behind a pass-through vertex shader), textures
// are uploaded from the same in-memory Texture levels (row 0 in memory is v = 0, sRGB colour as
// GL_SRGB8_ALPHA8), the plugin parameters arrive as the uniform array material.params[] in schema
// order, lights as frame.lights[] mirroring LightUniform, the frame's image-based light (if any)
// as SH uniforms and its specular chain and split-sum table, uploaded once per EnvironmentMaps
// (docs/environment.md, "On the GL backend").
//
// Target: an FBO with RGBA32F colour and GL_DEPTH_COMPONENT32F depth (plus two RGBA32F AOV
// targets when AOVs are asked for), glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), depth cleared to
// 0 and tested GREATER (reversed-Z, the CPU's projection), back faces culled unless the material
// is double-sided, counter-clockwise front faces. Colour and depth are read back with
// glReadPixels and flipped so pixel (0, 0) is the top-left (rasterizer/image.h).
//
// Timing, in RenderResult: passes[i].ms is the wall time of the pass up to glFinish,
// passes[i].gpu_ms its GL_TIME_ELAPSED query; compile_ms (programs built in this frame: the first
// frame of a variant), upload_ms and readback_ms are reported apart from the pass, frame_ms is the
// whole call.
#pragma once

#include <memory>

#include "base/status.h"
#include "render/render.h"

namespace relief {

// config.gpu: EGL device index (relief info lists them), or -1 to pick the first hardware device
// and fall back to Mesa's surfaceless platform; config.count_work: count fetches and steps.
// Threads and tile size are the CPU's and ignored here. Fails with one line when no context can be
// made.
Result<std::unique_ptr<Backend>> make_gl_backend(const BackendConfig& config = {});

// A backend by name ("cpu" or "gl"; anything else is a usage error naming --backend).
Result<std::unique_ptr<Backend>> make_backend(const std::string& name,
                                              const BackendConfig& config = {});

// The twin of a plugin: "<plugin>.frag" in gl/shaders, and whether it exists.
std::string gl_twin_file(const std::string& plugin_name);
bool gl_has_twin(const std::string& plugin_name);

}  // namespace relief
