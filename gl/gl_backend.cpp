// The GL backend's frame (gl/gl_backend.h): GlBackend::render runs the frame's steps, each
// defined in the file of its kind (gl/gl_backend_internal.h lists them).
#include "gl/gl_backend.h"

#include <cstdio>
#include <memory>
#include <utility>
#include <vector>

#include <epoxy/gl.h>

#include "gl/context.h"
#include "gl/gl_backend_internal.h"

namespace relief {
namespace gl_detail {
namespace {

const char* gl_error_name(GLenum e) {
  switch (e) {
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    default:
      return "GL error";
  }
}

void drain_gl_errors() {
  while (glGetError() != GL_NO_ERROR) {
  }
}

// Fixed state of every pass: reversed-Z, no blending, CCW front faces.
void set_fixed_state(GLuint vao) {
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glDepthMask(GL_TRUE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glFrontFace(GL_CCW);
  glCullFace(GL_BACK);
  glBindVertexArray(vao);
}

}  // namespace

Status gl_check(const char* where) {
  GLenum e = glGetError();
  if (e == GL_NO_ERROR) return {};
  char buf[160];
  std::snprintf(buf, sizeof(buf), "gl: %s (0x%04x) during %s", gl_error_name(e), e, where);
  drain_gl_errors();
  return Status::error(buf);
}

GlBackend::~GlBackend() {
  if (!ctx_ || !ctx_->make_current().ok()) return;
  for (auto& [k, p] : programs_) glDeleteProgram(p.id);
  for (auto& [k, t] : textures_) glDeleteTextures(1, &t.id);
  for (auto& [k, b] : height_fields_) glDeleteBuffers(1, &b.id);
  for (auto& [k, e] : environments_) glDeleteTextures(2, e.ids);
  GLuint ssbos[] = {empty_field_, counters_};
  glDeleteBuffers(2, ssbos);
  for (auto& [k, s] : samplers_) glDeleteSamplers(1, &s);
  release_target();
  if (vao_) glDeleteVertexArrays(1, &vao_);
  GLuint bufs[] = {vbo_clip_, vbo_vary_, ebo_};
  glDeleteBuffers(3, bufs);
  for (auto& [k, g] : geometry_) {
    glDeleteVertexArrays(1, &g.vao);
    glDeleteBuffers(3, g.buffers);
  }
  if (query_) glDeleteQueries(1, &query_);
  for (auto& [k, t] : shadow_textures_) glDeleteTextures(1, &t.id);
  if (shadow_fbo_) glDeleteFramebuffers(1, &shadow_fbo_);
  if (shadow_views_) glDeleteBuffers(1, &shadow_views_);
  if (triangle_planes_) glDeleteBuffers(1, &triangle_planes_);
}

Result<RenderResult> GlBackend::render(const Scene& scene, const Plan& plan) {
  const auto t_frame = Clock::now();
  RELIEF_RETURN_IF_ERROR(ctx_->make_current());
  drain_gl_errors();
  RenderResult result;
  result.device = ctx_->info().renderer;
  drop_unowned_textures();

  geometry_ms_ = 0.0;
  if (interpolation_ == GlInterpolation::kGpu) drop_unused_geometry();

  // Programs of the frame's variants (the first frame of a variant compiles it).
  FramePrograms programs;
  RELIEF_RETURN_IF_ERROR(select_programs(scene, plan, programs, &result.compile_ms));

  // The frame's geometry (BackendConfig::gl_interpolation): world-space vertices found in the
  // cache or prepared and uploaded, or the prepare stage's instances for per-pass planes.
  ensure_vertex_array();
  FrameGeometry geometry;
  RELIEF_RETURN_IF_ERROR(frame_geometry(scene, plan, geometry, result));

  // Uploads: textures (cached while the scene holds them), buffers and the target.
  FrameTransients transients;  // what nothing caches dies with the frame, on every return path
  DrawTextures textures;
  RELIEF_RETURN_IF_ERROR(upload_textures(plan, programs, transients, textures));
  upload_environment(plan, transients, textures);
  if (count_work_) ensure_counters();
  RELIEF_RETURN_IF_ERROR(ensure_target(plan.frame.width, plan.frame.height, plan.frame.aovs != 0));
  glFinish();
  // Everything before the passes that is not compile, prepare or geometry: making the context
  // current, textures, counters and the target.
  result.upload_ms = ms_since(t_frame) - result.compile_ms - result.prepare_ms - result.geometry_ms;
  RELIEF_RETURN_IF_ERROR(gl_check("upload"));

  // The passes: shadow maps (plan order), then the main pass.
  set_fixed_state(vao_);
  RELIEF_RETURN_IF_ERROR(shadow_passes(geometry, plan, programs, textures, count_work_, result));
  RELIEF_RETURN_IF_ERROR(main_pass(scene, plan, geometry, programs, textures, result));
  result.geometry_ms += geometry_ms_;  // each pass's view of the geometry (view_ranges)

  // Read back.
  const auto t_read = Clock::now();
  Framebuffer fb(plan.frame.width, plan.frame.height, plan.frame.aovs);
  RELIEF_RETURN_IF_ERROR(read_back(fb));
  result.readback_ms = ms_since(t_read);
  result.framebuffer = std::move(fb);
  result.frame_ms = ms_since(t_frame);
  return result;
}

}  // namespace gl_detail

Result<std::unique_ptr<Backend>> make_gl_backend(const BackendConfig& config) {
  Result<std::unique_ptr<gl::Context>> ctx = gl::Context::create(config.gpu);
  if (!ctx.ok()) return ctx.status();
  return std::unique_ptr<Backend>(std::make_unique<gl_detail::GlBackend>(std::move(*ctx), config));
}

}  // namespace relief
