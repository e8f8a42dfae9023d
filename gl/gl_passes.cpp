// The GL backend's passes (gl/gl_backend_internal.h): binding a material for a draw, the shadow
// passes (one depth layer per face) with the receivers' view of their maps, and the main pass.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <epoxy/gl.h>

#include "gl/gl_backend_internal.h"

namespace relief::gl_detail {
namespace {

// shadow_map.glsl: floats per light (the header, then the view and projection matrices).
constexpr int kShadowViewFloats = kShadowViewHeader + 2 * kMaxShadowFaces * 16;

// One light's ShadowMapView as shadow_map.glsl reads it (make_shadow_view's fields).
void pack_shadow_view(const ShadowPassSetup& s, const ShadowSettings& settings, float* out) {
  const float header[kShadowViewHeader] = {static_cast<float>(s.size),
                                           static_cast<float>(s.faces),
                                           s.orthographic ? 1.0f : 0.0f,
                                           s.position.x,
                                           s.position.y,
                                           s.position.z,
                                           s.znear,
                                           s.zfar,
                                           s.texel,
                                           settings.depth_bias,
                                           settings.slope_bias,
                                           static_cast<float>(settings.pcf_radius),
                                           0.0f,
                                           0.0f,
                                           0.0f,
                                           0.0f};
  std::copy(header, header + kShadowViewHeader, out);
  for (int f = 0; f < kMaxShadowFaces; ++f) {
    const glm::mat4 v = f < s.faces ? s.view[f] : glm::mat4(1.0f);
    const glm::mat4 p = f < s.faces ? s.proj[f] : glm::mat4(1.0f);
    std::copy(&v[0][0], &v[0][0] + 16, out + kShadowViewHeader + f * 16);
    std::copy(&p[0][0], &p[0][0] + 16, out + kShadowViewHeader + (kMaxShadowFaces + f) * 16);
  }
}

// An index's place in the bound element buffer, as glDrawElements* take it.
const void* index_pointer(size_t first_index) {
  return reinterpret_cast<const void*>(static_cast<uintptr_t>(first_index * sizeof(uint32_t)));
}

// Draws a degenerate triangle with each program built in this frame, in the pass's state: drivers
// may finish compiling at the first draw (llvmpipe JITs its fragment code there).
void warm_up(const std::vector<const Program*>& fresh, const std::vector<const Program*>& programs,
             GLuint vao, size_t warmup_offset, const BindFn& bind, double* compile_ms) {
  const auto t = Clock::now();
  bool drew = false;
  glBindVertexArray(vao);
  for (size_t mi = 0; mi < programs.size(); ++mi) {
    if (!programs[mi] || std::find(fresh.begin(), fresh.end(), programs[mi]) == fresh.end())
      continue;
    bind(*programs[mi], static_cast<int>(mi));
    glProgramUniform1i(programs[mi]->id, programs[mi]->loc.tri_base, -1);  // no planes
    glDrawElementsBaseVertex(GL_TRIANGLES, 3, GL_UNSIGNED_INT, index_pointer(warmup_offset), 0);
    drew = true;
  }
  if (!drew) return;
  glFinish();
  *compile_ms += ms_since(t);
}

void draw_ranges(const std::vector<DrawRange>& ranges, const std::vector<const Program*>& programs,
                 const BindFn& bind) {
  GLuint vao = 0;
  for (const DrawRange& r : ranges) {
    if (r.vao != vao) glBindVertexArray(vao = r.vao);
    const Program& p = *programs[r.material];
    bind(p, r.material);
    glProgramUniform1i(p.id, p.loc.tri_base, r.first_triangle);
    glDrawElementsBaseVertex(GL_TRIANGLES, r.count, GL_UNSIGNED_INT, index_pointer(r.index_offset),
                             r.base_vertex);
  }
}

// The main pass's draw state of a material: BLEND draws are blended, depth tested but not
// written, and write no AOVs.
void set_blend_state(bool blend, bool aovs) {
  if (blend) {
    glEnablei(GL_BLEND, 0);
  } else {
    glDisablei(GL_BLEND, 0);
  }
  glDepthMask(blend ? GL_FALSE : GL_TRUE);
  if (aovs)
    for (GLuint a = 1; a <= 2; ++a) glColorMaski(a, !blend, !blend, !blend, !blend);
}

// Clears the target: premultiplied background as the CPU's, AOVs to 0, depth to 0 (reversed-Z).
// Warm-up draws may have left a BLEND draw's state.
void clear_main_target(GLuint fbo, const Scene& scene, bool aovs) {
  const glm::vec4 bg = clear_color(scene);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &bg[0]);
  if (aovs) {
    const float zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(fbo, GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(fbo, GL_COLOR, 2, zero);
  }
  const float depth_clear = 0.0f;
  glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &depth_clear);
}

// The casters of a shadow pass (CPU: pass.instances with shadow_caster materials), in scene
// order.
std::vector<int> shadow_casters(const FrameGeometry& geometry, const Plan& plan,
                                const PassPlan& pass) {
  std::vector<bool> drawn(geometry.materials.size(), false);
  for (int i : pass.instances)
    if (i >= 0 && static_cast<size_t>(i) < drawn.size()) drawn[i] = true;
  std::vector<int> casters;
  for (size_t i = 0; i < drawn.size(); ++i)
    if (drawn[i] && plan.materials[geometry.materials[i]].shadow_caster)
      casters.push_back(static_cast<int>(i));
  return casters;
}

}  // namespace

void GlBackend::bind_material(const Program& p, int mi, const Plan& plan,
                              const FrameUniforms& frame, const DrawTextures& textures,
                              BindCache& cache) {
  const BoundMaterial& m = plan.materials[mi];
  glUseProgram(p.id);
  auto [it, first_use] = cache.material_of.emplace(p.id, -1);
  if (first_use) {
    set_frame_uniforms(p, frame);
    glProgramUniform2f(p.id, glGetUniformLocation(p.id, "viewport_size"),
                       static_cast<float>(frame.width), static_cast<float>(frame.height));
    // relief.vert: CPU clip positions as they are, or world positions through the view.
    const bool planes = interpolation_ == GlInterpolation::kCpuPlanes;
    const glm::mat4 clip_from_input = planes ? glm::mat4(1.0f) : frame.view_proj;
    glProgramUniformMatrix4fv(p.id, p.loc.clip_from_input, 1, GL_FALSE, &clip_from_input[0][0]);
    glProgramUniform1i(p.id, p.loc.snap_like_cpu, planes ? 1 : 0);
  }
  if (it->second != mi) {
    set_material_uniforms(p, m.uniforms);
    it->second = mi;
  }
  for (int s = 0; s < kMaxTextureSlots; ++s) {
    glBindTextureUnit(s, textures.tex[mi][s]);
    glBindSampler(s, textures.samplers[mi][s]);
  }
  glBindTextureUnit(kEmissiveUnit, textures.extra[mi][0]);
  glBindSampler(kEmissiveUnit, textures.extra[mi][1]);
  glBindTextureUnit(kOcclusionUnit, textures.extra[mi][2]);
  glBindSampler(kOcclusionUnit, textures.extra[mi][3]);
  glBindTextureUnit(kMetallicRoughnessUnit, textures.extra[mi][4]);
  glBindSampler(kMetallicRoughnessUnit, textures.extra[mi][5]);
  if (p.height_field)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kHeightFieldBinding, textures.fields[mi]);
  if (m.double_sided)
    glDisable(GL_CULL_FACE);
  else
    glEnable(GL_CULL_FACE);
}

void GlBackend::reset_counters() {
  const uint32_t zero = 0;
  glClearNamedBufferData(counters_, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kCountersBinding, counters_);
}

void GlBackend::end_pass(PassStats& stats, Clock::time_point t_pass) {
  glEndQuery(GL_TIME_ELAPSED);
  glFinish();
  stats.ms = ms_since(t_pass);
  GLuint64 ns = 0;
  glGetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);
  // A pass cannot take longer on the device than between its begin and glFinish; llvmpipe returns
  // such values (threads that rasterised no bin report no start time), so they are dropped.
  const double gpu_ms = static_cast<double>(ns) * 1e-6;
  stats.gpu_ms = gpu_ms > 0.0 && gpu_ms <= stats.ms * 1.05 + 0.05 ? gpu_ms : -1.0;
}

Status GlBackend::shadow_passes(const FrameGeometry& geometry, const Plan& plan,
                                const FramePrograms& programs, const DrawTextures& textures,
                                bool count, RenderResult& result) {
  std::vector<float> views(static_cast<size_t>(kMaxLights) * kShadowViewFloats, 0.0f);
  for (const PassPlan& pass : plan.passes) {
    if (pass.kind != PassPlan::Kind::kShadow) continue;
    if (pass.light < 0 || pass.light >= kMaxLights)
      return Status::error("gl: shadow pass \"" + pass.name + "\" has no light uniform");
    RELIEF_RETURN_IF_ERROR(shadow_pass(geometry, plan, pass, programs, textures, count, result));
    pack_shadow_view(pass.shadow, plan.shadow,
                     &views[static_cast<size_t>(pass.light) * kShadowViewFloats]);
  }
  bind_shadow_maps(views);
  return {};
}

void GlBackend::bind_shadow_maps(const std::vector<float>& views) {
  if (!shadow_views_) {
    glCreateBuffers(1, &shadow_views_);
    glNamedBufferStorage(shadow_views_, static_cast<GLsizeiptr>(views.size() * sizeof(float)),
                         nullptr, GL_DYNAMIC_STORAGE_BIT);
  }
  glNamedBufferSubData(shadow_views_, 0, static_cast<GLsizeiptr>(views.size() * sizeof(float)),
                       views.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kShadowViewsBinding, shadow_views_);
  for (int l = 0; l < kMaxLights; ++l) {
    auto it = shadow_textures_.find(l);
    const bool mapped = it != shadow_textures_.end() &&
                        views[static_cast<size_t>(l) * kShadowViewFloats + 1] > 0.0f;
    glBindTextureUnit(kShadowUnit + l, mapped ? it->second.id : 0);
    glBindSampler(kShadowUnit + l, 0);
  }
}

Status GlBackend::shadow_pass(const FrameGeometry& geometry, const Plan& plan, const PassPlan& pass,
                              const FramePrograms& programs, const DrawTextures& textures,
                              bool count, RenderResult& result) {
  PassStats stats = shadow_pass_stats(pass);
  const GLuint depth = shadow_texture(pass.light, pass.shadow);
  if (!shadow_fbo_) glCreateFramebuffers(1, &shadow_fbo_);
  glNamedFramebufferDrawBuffer(shadow_fbo_, GL_NONE);
  glNamedFramebufferReadBuffer(shadow_fbo_, GL_NONE);
  double pass_ms = 0.0, gpu_ms = 0.0;
  bool gpu_valid = true;
  for (int f = 0; f < pass.shadow.faces; ++f) {
    PassStats face;
    RELIEF_RETURN_IF_ERROR(shadow_face(geometry, plan, pass, f, depth, programs, textures, count,
                                       face, &result.compile_ms));
    pass_ms += face.ms;
    gpu_valid = gpu_valid && face.gpu_ms >= 0.0;
    gpu_ms += face.gpu_ms;
    if (count) stats.raster.work += face.raster.work;
  }
  stats.ms = pass_ms;
  stats.gpu_ms = gpu_valid ? gpu_ms : -1.0;
  result.passes.push_back(stats);
  return {};
}

Status GlBackend::shadow_face(const FrameGeometry& geometry, const Plan& plan, const PassPlan& pass,
                              int face, GLuint depth, const FramePrograms& programs,
                              const DrawTextures& textures, bool count, PassStats& stats,
                              double* compile_ms) {
  const ShadowPassSetup& s = pass.shadow;
  const FrameUniforms frame = shadow_face_frame(s, face);
  size_t warmup_offset = 0;
  const std::vector<DrawRange> ranges =
      view_ranges(geometry, shadow_casters(geometry, plan, pass), programs.shadow, frame.view_proj,
                  s.size, s.size, &warmup_offset);
  glNamedFramebufferTextureLayer(shadow_fbo_, GL_DEPTH_ATTACHMENT, depth, 0, face);
  const GLenum status = glCheckNamedFramebufferStatus(shadow_fbo_, GL_DRAW_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    return Status::error("gl: shadow framebuffer incomplete (" + pass.name + ")");
  glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
  glViewport(0, 0, s.size, s.size);
  BindCache cache;
  auto bind = [&](const Program& p, int mi) { bind_material(p, mi, plan, frame, textures, cache); };
  if (face == 0) warm_up(programs.fresh, programs.shadow, vao_, warmup_offset, bind, compile_ms);
  if (count) reset_counters();
  const auto t_pass = Clock::now();
  glBeginQuery(GL_TIME_ELAPSED, query_);
  const float depth_clear = 0.0f;
  glClearNamedFramebufferfv(shadow_fbo_, GL_DEPTH, 0, &depth_clear);
  draw_ranges(ranges, programs.shadow, bind);
  end_pass(stats, t_pass);
  if (count) RELIEF_RETURN_IF_ERROR(read_counters(stats.raster.work));
  return gl_check("shadow pass");
}

Status GlBackend::main_pass(const Scene& scene, const Plan& plan, const FrameGeometry& geometry,
                            const FramePrograms& programs, const DrawTextures& textures,
                            RenderResult& result) {
  const bool aovs = plan.frame.aovs != 0;
  const int w = plan.frame.width, h = plan.frame.height;
  FrameUniforms frame = plan.frame;
  frame.width = w;
  frame.height = h;
  size_t warmup_offset = 0;
  // Plan::draw_order: opaque and MASK draws, then BLEND ones back to front (as the CPU).
  const std::vector<DrawRange> ranges =
      view_ranges(geometry, main_draw_order(plan, geometry.materials.size()), programs.main,
                  frame.view_proj, w, h, &warmup_offset);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, w, h);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  BindCache cache;
  // The environment (common.glsl env_specular_map, env_brdf_lut): 0 without one (not read then).
  glBindTextureUnit(kEnvSpecularUnit, textures.env_specular);
  glBindSampler(kEnvSpecularUnit, textures.env_specular_sampler);
  glBindTextureUnit(kEnvBrdfUnit, textures.env_brdf);
  glBindSampler(kEnvBrdfUnit, textures.env_brdf_sampler);
  // BLEND draws: src-over of the straight-alpha colour onto the premultiplied target (the CPU's
  // DrawCall::blend), depth tested but not written, no AOVs.
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  auto bind = [&](const Program& p, int mi) {
    bind_material(p, mi, plan, frame, textures, cache);
    set_blend_state(plan.materials[mi].uniforms.alpha_mode == AlphaMode::kBlend, aovs);
  };
  warm_up(programs.fresh, programs.main, vao_, warmup_offset, bind, &result.compile_ms);
  if (count_work_) reset_counters();
  const auto t_pass = Clock::now();
  // Begun after binding the target: llvmpipe attributes a query to the framebuffer's scene.
  glBeginQuery(GL_TIME_ELAPSED, query_);
  clear_main_target(fbo_, scene, aovs);
  draw_ranges(ranges, programs.main, bind);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  PassStats main;
  main.name = "main";
  end_pass(main, t_pass);
  RELIEF_RETURN_IF_ERROR(gl_check("main pass"));
  if (count_work_) RELIEF_RETURN_IF_ERROR(read_counters(main.raster.work));
  result.passes.push_back(main);
  return {};
}

}  // namespace relief::gl_detail
