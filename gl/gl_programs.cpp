// The twins' program variants (gl/gl_backend_internal.h): compile and link on first use, the
// cache, uniform locations and the frame and material uniforms.
#include <algorithm>
#include <string>
#include <vector>

#include <epoxy/gl.h>

#include "gl/gl_backend.h"
#include "gl/gl_backend_internal.h"
#include "gl/height_field.h"
#include "gl/shader.h"

namespace relief {

std::string gl_twin_file(const std::string& plugin_name) {
  return plugin_name + ".frag";
}
bool gl_has_twin(const std::string& plugin_name) {
  return gl::shader_file_exists(gl_twin_file(plugin_name));
}

namespace gl_detail {
namespace {

// The uniforms Locations holds one location of, by name (the lights apart).
struct NamedLocation {
  GLint Locations::*field;
  const char* name;
};
constexpr NamedLocation kNamedLocations[] = {
    {&Locations::view, "frame.view"},
    {&Locations::view_proj, "frame.view_proj"},
    {&Locations::eye, "frame.eye"},
    {&Locations::orthographic, "frame.orthographic"},
    {&Locations::view_dir, "frame.view_dir"},
    {&Locations::ambient, "frame.ambient"},
    {&Locations::num_lights, "frame.num_lights"},
    {&Locations::width, "frame.width"},
    {&Locations::height, "frame.height"},
    {&Locations::has_environment, "frame.has_environment"},
    {&Locations::env_sh, "frame.env_sh[0]"},
    {&Locations::env_rotation, "frame.env_rotation"},
    {&Locations::env_intensity, "frame.env_intensity"},
    {&Locations::env_max_lod, "frame.env_max_lod"},
    {&Locations::params, "material.params[0]"},
    {&Locations::base_color, "material.base_color"},
    {&Locations::specular, "material.specular"},
    {&Locations::shininess, "material.shininess"},
    {&Locations::alpha_mode, "material.alpha_mode"},
    {&Locations::alpha_cutoff, "material.alpha_cutoff"},
    {&Locations::has_texture, "has_texture[0]"},
    {&Locations::texture_sampler, "texture_sampler[0]"},
    {&Locations::tri_base, "tri_base"},
    {&Locations::clip_from_input, "clip_from_input"},
    {&Locations::snap_like_cpu, "snap_like_cpu"},
};

Locations find_locations(GLuint p) {
  Locations l;
  auto loc = [p](const std::string& n) { return glGetUniformLocation(p, n.c_str()); };
  for (const NamedLocation& n : kNamedLocations) l.*n.field = loc(n.name);
  for (int i = 0; i < kMaxLights; ++i) {
    const std::string b = "frame.lights[" + std::to_string(i) + "].";
    l.lights[i] = {loc(b + "type"),          loc(b + "position"), loc(b + "direction"),
                   loc(b + "color"),         loc(b + "range"),    loc(b + "inner_cone_cos"),
                   loc(b + "outer_cone_cos")};
  }
  return l;
}

// The cache key of a variant.
std::string variant_key(const Variant& v) {
  return v.plugin + "/" + std::to_string(v.effects) + "/" + std::to_string(int(v.depth_output)) +
         (v.aovs ? "a" : "") + (v.count ? "c" : "") + (v.alpha_test ? "m" : "");
}

// The preprocessor switches a variant compiles its twin with.
std::vector<std::string> variant_defines(const Variant& v) {
  auto flag = [&](const char* name, bool on) { return std::string(name) + (on ? " 1" : " 0"); };
  return {
      flag("EFFECT_SELF_SHADOW", v.effects & kEffectSelfShadow),
      flag("EFFECT_DEPTH_WRITE", v.effects & kEffectDepthWrite),
      flag("EFFECT_SILHOUETTE", v.effects & kEffectSilhouette),
      flag("EFFECT_SHADOW_PASS", v.effects & kEffectShadowPass),
      flag("EFFECT_RECEIVE_SHADOW", v.effects & kEffectReceiveShadow),
      flag("EFFECT_HEIGHT_AO", v.effects & kEffectHeightAo),
      flag("RELIEF_WRITES_DEPTH", v.depth_output != DepthOutput::kNone),
      flag("RELIEF_AOVS", v.aovs),
      flag("RELIEF_DEPTH_FARTHER", v.depth_output == DepthOutput::kFarther),
      flag("RELIEF_COUNT", v.count),
      flag("RELIEF_ALPHA_TEST", v.alpha_test),
  };
}

// The packer writes std430 with hf_data right after the header; check the driver agrees.
Status check_height_field_layout(GLuint program, const std::string& frag) {
  const GLuint var = glGetProgramResourceIndex(program, GL_BUFFER_VARIABLE, "hf_data[0]");
  const GLenum prop = GL_OFFSET;
  GLint offset = -1;
  if (var != GL_INVALID_INDEX)
    glGetProgramResourceiv(program, GL_BUFFER_VARIABLE, var, 1, &prop, 1, nullptr, &offset);
  if (offset == gl::PackedHeightField::kHeaderWords * 4) return {};
  return Status::error("gl: " + frag + ": HeightFieldBuffer.hf_data at byte " +
                       std::to_string(offset) + ", gl/height_field.h packs it at " +
                       std::to_string(gl::PackedHeightField::kHeaderWords * 4));
}

// glTF material terms (common.glsl finish_surface, sample_slot); unused ones have no location.
void set_uv_map(GLuint p, const std::string& name, const UvMap& u) {
  glProgramUniform2fv(p, glGetUniformLocation(p, (name + ".col0").c_str()), 1, &u.col0[0]);
  glProgramUniform2fv(p, glGetUniformLocation(p, (name + ".col1").c_str()), 1, &u.col1[0]);
  glProgramUniform2fv(p, glGetUniformLocation(p, (name + ".offset").c_str()), 1, &u.offset[0]);
  glProgramUniform1i(p, glGetUniformLocation(p, (name + ".set").c_str()), u.set);
  glProgramUniform1i(p, glGetUniformLocation(p, (name + ".identity").c_str()), u.identity ? 1 : 0);
}

void set_gltf_material_terms(GLuint p, const MaterialUniforms& m) {
  for (int i = 0; i < kMaxTextureSlots; ++i)
    set_uv_map(p, "material.uv_maps[" + std::to_string(i) + "]", m.uv_maps[i]);
  set_uv_map(p, "material.emissive_uv", m.emissive_uv);
  set_uv_map(p, "material.occlusion_uv", m.occlusion_uv);
  set_uv_map(p, "material.metallic_roughness_uv", m.metallic_roughness_uv);
  glProgramUniform1i(p, glGetUniformLocation(p, "material.shading"), static_cast<GLint>(m.shading));
  glProgramUniform1f(p, glGetUniformLocation(p, "material.metallic"), m.metallic);
  glProgramUniform1f(p, glGetUniformLocation(p, "material.roughness"), m.roughness);
  glProgramUniform1i(p, glGetUniformLocation(p, "material.has_metallic_roughness_texture"),
                     m.metallic_roughness_texture ? 1 : 0);
  glProgramUniform3fv(p, glGetUniformLocation(p, "material.emissive"), 1, &m.emissive[0]);
  glProgramUniform1i(p, glGetUniformLocation(p, "material.has_emissive_texture"),
                     m.emissive_texture ? 1 : 0);
  glProgramUniform1i(p, glGetUniformLocation(p, "material.has_occlusion_texture"),
                     m.occlusion_texture ? 1 : 0);
  glProgramUniform1f(p, glGetUniformLocation(p, "material.occlusion_strength"),
                     m.occlusion_strength);
  glProgramUniform1f(p, glGetUniformLocation(p, "material.normal_scale"), m.normal_scale);
  glProgramUniform1i(p, glGetUniformLocation(p, "material.unlit"), m.unlit ? 1 : 0);
}

// The image-based light's uniforms (common.glsl FrameUniforms): has_environment false and nothing
// else without one.
void set_environment_uniforms(const Program& program, const FrameUniforms& f) {
  const GLuint p = program.id;
  const Locations& l = program.loc;
  glProgramUniform1i(p, l.has_environment, f.environment ? 1 : 0);
  if (!f.environment) return;
  const EnvironmentMaps& env = *f.environment;
  glProgramUniform3fv(p, l.env_sh, kEnvShCount, &env.sh[0][0]);
  glProgramUniform2f(p, l.env_rotation, f.env_view.cos_rotation, f.env_view.sin_rotation);
  glProgramUniform1f(p, l.env_intensity, f.env_view.intensity);
  const int levels = env.specular.empty() ? 1 : env.specular.levels();
  glProgramUniform1f(p, l.env_max_lod, static_cast<float>(levels - 1));
}

// Height-field AO (relief_shell.glsl height_field_ao); only EFFECT_HEIGHT_AO twins have them.
void set_height_ao(GLuint p, const MaterialUniforms& m) {
  glProgramUniform1i(p, glGetUniformLocation(p, "height_ao_rays"), m.height_ao.rays);
  glProgramUniform1f(p, glGetUniformLocation(p, "height_ao_radius"), m.height_ao.radius);
  glProgramUniform1f(p, glGetUniformLocation(p, "height_ao_strength"), m.height_ao.strength);
}

}  // namespace

Result<const Program*> GlBackend::program_for(const Variant& v, double* compile_ms) {
  const std::string key = variant_key(v);
  if (auto it = programs_.find(key); it != programs_.end()) return &it->second;
  const std::string frag = gl_twin_file(v.plugin);
  if (!gl::shader_file_exists(frag))
    return Status::error("gl: technique \"" + v.plugin + "\" has no GLSL twin (gl/shaders/" + frag +
                         ")");
  const auto t0 = Clock::now();
  Result<unsigned> id = gl::build_program("relief.vert", frag, variant_defines(v));
  if (!id.ok()) return id.status();
  Program p;
  p.id = *id;
  p.loc = find_locations(p.id);
  p.height_field = glGetProgramResourceIndex(p.id, GL_SHADER_STORAGE_BLOCK, "HeightFieldBuffer") !=
                   GL_INVALID_INDEX;
  if (p.height_field) {
    if (Status s = check_height_field_layout(p.id, frag); !s.ok()) {
      glDeleteProgram(p.id);
      return s;
    }
  }
  *compile_ms += ms_since(t0);
  return &programs_.emplace(key, p).first->second;
}

Status GlBackend::use_program(const Variant& v, const Program** slot, FramePrograms& frame,
                              double* compile_ms) {
  const size_t before = programs_.size();
  Result<const Program*> p = program_for(v, compile_ms);
  if (!p.ok()) return p.status();
  *slot = *p;
  if (programs_.size() != before) frame.fresh.push_back(*p);
  return {};
}

Status GlBackend::select_programs(const Scene& scene, const Plan& plan, FramePrograms& frame,
                                  double* compile_ms) {
  const size_t nm = plan.materials.size();
  frame.main.assign(nm, nullptr);
  frame.shadow.assign(nm, nullptr);
  const bool aovs = plan.frame.aovs != 0;
  RELIEF_RETURN_IF_ERROR(select_main_programs(scene, plan, aovs, count_work_, frame, compile_ms));
  const bool has_shadow_pass =
      std::any_of(plan.passes.begin(), plan.passes.end(),
                  [](const PassPlan& p) { return p.kind == PassPlan::Kind::kShadow; });
  if (!has_shadow_pass) return {};
  return select_shadow_programs(plan, count_work_, frame, compile_ms);
}

Status GlBackend::select_main_programs(const Scene& scene, const Plan& plan, bool aovs, bool count,
                                       FramePrograms& frame, double* compile_ms) {
  const int nm = static_cast<int>(plan.materials.size());
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& d = scene.instances[i];
    if (d.material < 0 || d.material >= nm)
      return Status::error("gl: instance " + std::to_string(i) + " has no material");
    if (frame.main[d.material]) continue;
    const BoundMaterial& m = plan.materials[d.material];
    if (!m.plugin) return Status::error("gl: material " + std::to_string(d.material) + " unbound");
    const Variant v{m.plugin->name, m.effects, m.plugin->depth_output(m.effects),
                    aovs,           count,     m.uniforms.alpha_mode == AlphaMode::kMask};
    RELIEF_RETURN_IF_ERROR(use_program(v, &frame.main[d.material], frame, compile_ms));
  }
  return {};
}

Status GlBackend::select_shadow_programs(const Plan& plan, bool count, FramePrograms& frame,
                                         double* compile_ms) {
  for (size_t mi = 0; mi < plan.materials.size(); ++mi) {
    const BoundMaterial& m = plan.materials[mi];
    if (!m.plugin || !m.shadow_caster) continue;
    const bool mask = m.uniforms.alpha_mode == AlphaMode::kMask;
    Variant v;
    if (m.shadow_effects)
      v = {m.plugin->name,
           m.shadow_effects,
           m.plugin->depth_output(m.shadow_effects),
           false,
           count,
           mask};
    else if (mask)  // cut out: the twin's own discard (the CPU's MaskCasterKernel)
      v = {m.plugin->name, 0, m.plugin->depth_output(0), false, count, true};
    else
      v = {"depth_only", 0, DepthOutput::kNone, false, count, false};
    RELIEF_RETURN_IF_ERROR(use_program(v, &frame.shadow[mi], frame, compile_ms));
  }
  return {};
}

void set_frame_uniforms(const Program& program, const FrameUniforms& f) {
  const GLuint p = program.id;
  const Locations& l = program.loc;
  glProgramUniformMatrix4fv(p, l.view, 1, GL_FALSE, &f.view[0][0]);
  glProgramUniformMatrix4fv(p, l.view_proj, 1, GL_FALSE, &f.view_proj[0][0]);
  glProgramUniform3fv(p, l.eye, 1, &f.eye[0]);
  glProgramUniform1i(p, l.orthographic, f.orthographic ? 1 : 0);
  glProgramUniform3fv(p, l.view_dir, 1, &f.view_dir[0]);
  glProgramUniform3fv(p, l.ambient, 1, &f.ambient[0]);
  const int n = std::clamp(f.num_lights, 0, kMaxLights);
  glProgramUniform1i(p, l.num_lights, n);
  glProgramUniform1i(p, l.width, f.width);
  glProgramUniform1i(p, l.height, f.height);
  set_environment_uniforms(program, f);
  for (int i = 0; i < n; ++i) {
    const LightUniform& s = f.lights[i];
    const Locations::Light& d = l.lights[i];
    glProgramUniform1i(p, d.type, static_cast<int>(s.type));
    glProgramUniform3fv(p, d.position, 1, &s.position[0]);
    glProgramUniform3fv(p, d.direction, 1, &s.direction[0]);
    glProgramUniform3fv(p, d.color, 1, &s.color[0]);
    glProgramUniform1f(p, d.range, s.range);
    glProgramUniform1f(p, d.inner, s.inner_cone_cos);
    glProgramUniform1f(p, d.outer, s.outer_cone_cos);
  }
}

void set_material_uniforms(const Program& program, const MaterialUniforms& m) {
  const GLuint p = program.id;
  const Locations& l = program.loc;
  glProgramUniform1fv(p, l.params, kMaxParams, m.params);
  glProgramUniform4fv(p, l.base_color, 1, &m.base_color[0]);
  glProgramUniform1f(p, l.specular, m.specular);
  glProgramUniform1f(p, l.shininess, m.shininess);
  glProgramUniform1i(p, l.alpha_mode, static_cast<GLint>(m.alpha_mode));
  glProgramUniform1f(p, l.alpha_cutoff, m.alpha_cutoff);
  GLint has[kMaxTextureSlots];
  for (int i = 0; i < kMaxTextureSlots; ++i) has[i] = m.textures[i] != nullptr ? 1 : 0;
  glProgramUniform1iv(p, l.has_texture, kMaxTextureSlots, has);
  GLint samplers[kMaxTextureSlots * 3];
  for (int i = 0; i < kMaxTextureSlots; ++i) {
    samplers[3 * i] = static_cast<GLint>(m.samplers[i].filter);
    samplers[3 * i + 1] = static_cast<GLint>(m.samplers[i].wrap_u);
    samplers[3 * i + 2] = static_cast<GLint>(m.samplers[i].wrap_v);
  }
  if (l.texture_sampler >= 0) glProgramUniform3iv(p, l.texture_sampler, kMaxTextureSlots, samplers);
  set_gltf_material_terms(p, m);
  set_height_ao(p, m);
}

}  // namespace gl_detail
}  // namespace relief
