#include "gl/gl_backend.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <epoxy/gl.h>

#include "gl/context.h"
#include "gl/height_field.h"
#include "gl/shader.h"
#include "plugins/registry.h"
#include "render/derived_maps.h"

#ifndef GL_TEXTURE_MAX_ANISOTROPY
#define GL_TEXTURE_MAX_ANISOTROPY 0x84FE
#endif

namespace relief {

std::string gl_twin_file(const std::string& plugin_name) {
  return plugin_name + ".frag";
}
bool gl_has_twin(const std::string& plugin_name) {
  return gl::shader_file_exists(gl_twin_file(plugin_name));
}

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

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

// First pending GL error as a Status (and drains the rest).
Status gl_check(const char* where) {
  GLenum e = glGetError();
  if (e == GL_NO_ERROR) return {};
  char buf[160];
  std::snprintf(buf, sizeof(buf), "gl: %s (0x%04x) during %s", gl_error_name(e), e, where);
  while (glGetError() != GL_NO_ERROR) {
  }
  return Status::error(buf);
}

struct FormatGl {
  GLenum internal, format, type;
};
FormatGl format_gl(TexFormat f, ColorSpace cs) {
  switch (f) {
    case TexFormat::kR8:
      return {GL_R8, GL_RED, GL_UNSIGNED_BYTE};
    case TexFormat::kRG8:
      return {GL_RG8, GL_RG, GL_UNSIGNED_BYTE};
    case TexFormat::kRGBA8:
      return {cs == ColorSpace::kSRGB ? GLenum(GL_SRGB8_ALPHA8) : GLenum(GL_RGBA8), GL_RGBA,
              GL_UNSIGNED_BYTE};
    case TexFormat::kR16:
      return {GL_R16, GL_RED, GL_UNSIGNED_SHORT};
    case TexFormat::kR16F:
      return {GL_R16F, GL_RED, GL_HALF_FLOAT};
    case TexFormat::kRGBA16F:
      return {GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT};
    case TexFormat::kR32F:
      return {GL_R32F, GL_RED, GL_FLOAT};
  }
  return {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};
}

GLenum wrap_gl(Wrap w) {
  switch (w) {
    case Wrap::kRepeat:
      return GL_REPEAT;
    case Wrap::kClamp:
      return GL_CLAMP_TO_EDGE;
    case Wrap::kMirror:
      return GL_MIRRORED_REPEAT;
  }
  return GL_REPEAT;
}

// Uniform locations of one program (-1 where the compiler removed the uniform).
struct Locations {
  GLint view = -1, view_proj = -1, eye = -1, orthographic = -1, view_dir = -1, ambient = -1;
  GLint num_lights = -1, width = -1, height = -1;
  struct Light {
    GLint type = -1, position = -1, direction = -1, color = -1, range = -1, inner = -1, outer = -1;
  } lights[kMaxLights];
  GLint params = -1, base_color = -1, specular = -1, shininess = -1, has_texture = -1;
  GLint alpha_mode = -1, alpha_cutoff = -1;
  GLint texture_sampler = -1;  // cone.glsl: (filter, wrap_u, wrap_v) per slot, for texelFetch
  GLint tri_base = -1;         // common.glsl: the draw's first triangle in TrianglePlanesBuffer
};

Locations find_locations(GLuint p) {
  Locations l;
  auto loc = [p](const std::string& n) { return glGetUniformLocation(p, n.c_str()); };
  l.view = loc("frame.view");
  l.view_proj = loc("frame.view_proj");
  l.eye = loc("frame.eye");
  l.orthographic = loc("frame.orthographic");
  l.view_dir = loc("frame.view_dir");
  l.ambient = loc("frame.ambient");
  l.num_lights = loc("frame.num_lights");
  l.width = loc("frame.width");
  l.height = loc("frame.height");
  for (int i = 0; i < kMaxLights; ++i) {
    const std::string b = "frame.lights[" + std::to_string(i) + "].";
    l.lights[i] = {loc(b + "type"),          loc(b + "position"), loc(b + "direction"),
                   loc(b + "color"),         loc(b + "range"),    loc(b + "inner_cone_cos"),
                   loc(b + "outer_cone_cos")};
  }
  l.params = loc("material.params[0]");
  l.base_color = loc("material.base_color");
  l.specular = loc("material.specular");
  l.shininess = loc("material.shininess");
  l.alpha_mode = loc("material.alpha_mode");
  l.alpha_cutoff = loc("material.alpha_cutoff");
  l.has_texture = loc("has_texture[0]");
  l.texture_sampler = loc("texture_sampler[0]");
  l.tri_base = loc("tri_base");
  return l;
}

// Storage-block bindings of gl/shaders/common.glsl (work counters) and exact.glsl (max-mip).
constexpr GLuint kCountersBinding = 0;
constexpr GLuint kHeightFieldBinding = 1;
// common.glsl: kCounterSlots slots of kCounterCount counters, in WorkCounters order below.
constexpr int kCounterSlots = 256;
constexpr int kCounterCount = 5;

struct Program {
  GLuint id = 0;
  Locations loc;
  bool height_field = false;  // reads HeightFieldBuffer (the exact twin)
};

// How a texture is uploaded: as stored, or as 32-bit float of the values the CPU's sampler
// decodes (Texture::fetch_r into R32F: depth maps and one-channel cone maps; Texture::fetch into
// RGBA32F: quad cone maps), so that a twin reads exactly the CPU's values.
enum class Upload { kNative, kR32F, kRGBA32F };

struct CachedTexture {
  TexturePtr owner;  // keeps the address from being reused while cached
  GLuint id = 0;
};

// A cached max-mip: the depth texture and the wraps it was packed with.
using HeightFieldKey = std::tuple<const Texture*, Wrap, Wrap>;

// Deletes (with `del`, glDeleteTextures or glDeleteBuffers) the cached objects whose texture only
// the cache still holds.
template <class Map, class Delete>
void drop_unowned(Map& cache, Delete del) {
  for (auto it = cache.begin(); it != cache.end();) {
    if (it->second.owner.use_count() == 1) {
      del(1, &it->second.id);
      it = cache.erase(it);
    } else {
      ++it;
    }
  }
}

// Depth maps and cone maps (the slots the searches read) go up as 32-bit float of the CPU's
// decoded values; everything else as stored.
Upload upload_for(const PluginDescriptor& p, int slot, const Texture& t) {
  if (slot >= p.num_textures) return Upload::kNative;
  const std::string name = p.textures[slot].name;
  if (name == "depth" || name == "depth_back") return Upload::kR32F;  // depth_back: relief_dual
  if (is_derived_slot(name))
    return format_channels(t.format()) == 1 ? Upload::kR32F : Upload::kRGBA32F;
  return Upload::kNative;
}

// A draw range in the uploaded vertex and index buffers.
struct DrawRange {
  int material;
  GLsizei count;
  size_t index_offset;
  GLint base_vertex;
  GLint first_triangle;  // index of its first triangle in the TrianglePlanesBuffer
};

// common.glsl's TrianglePlanesBuffer: per triangle a header (first part's offset, part count,
// varying count, unused; ints stored bit for bit), then the parts: (x0, y0) as ints, the corners
// (x, y) x 3 and the CPU rasterizer's planes (depth, 1/w, the draw's varyings times 1/w: 16, or
// kCountExtended with COLOR_0 or TEXCOORD_1), three floats each.
constexpr GLuint kTrianglePlanesBinding = 3;
constexpr int kTriangleHeader = 4;
// The vertex stream: every draw's varyings padded to kGlVaryings floats (relief.vert's six vec4;
// colour 1 and uv1 0 where the mesh has none).
constexpr int kGlVaryings = 24;
static_assert(varying::kCountExtended <= kGlVaryings);
// Texture units of common.glsl's emissive_texture and occlusion_texture.
constexpr GLuint kEmissiveUnit = 16;
constexpr GLuint kOcclusionUnit = 17;

float int_bits(int32_t v) {
  float f;
  std::memcpy(&f, &v, sizeof f);
  return f;
}

// The texture and sampler objects per material and slot, and the exact twin's max-mip buffer.
struct DrawTextures {
  std::vector<std::array<GLuint, kMaxTextureSlots>> tex, samplers;
  // per material: emissive texture and sampler, occlusion texture and sampler
  std::vector<std::array<GLuint, 4>> extra;
  std::vector<GLuint> fields;
};

// What a pass has bound: the material whose uniforms each program holds, and whether its frame
// uniforms are the pass's.
struct BindCache {
  std::map<GLuint, int> material_of;
};

// Storage-block binding of gl/shaders/shadow_map.glsl and the first texture unit of its maps.
constexpr GLuint kShadowViewsBinding = 2;
constexpr GLuint kShadowUnit = 8;
// shadow_map.glsl: floats per light (16 header + 6 view + 6 projection matrices).
constexpr int kShadowViewHeader = 16;
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

class GlBackend final : public Backend {
 public:
  GlBackend(std::unique_ptr<gl::Context> ctx, const BackendConfig& config)
      : ctx_(std::move(ctx)), count_work_(config.count_work) {}
  ~GlBackend() override;
  std::string name() const override { return "gl"; }
  Result<RenderResult> render(const Scene& scene, const Plan& plan) override;

 private:
  // The program of a plugin's twin ("depth_only" for casters without a shadow-pass variant).
  // alpha_test: a MASK material's, which discards, so it cannot take early fragment tests.
  Result<const Program*> program_for(const std::string& plugin, EffectMask effects,
                                     DepthOutput depth_output, bool aovs, bool count,
                                     double* compile_ms, bool alpha_test = false);
  // Renders the faces of one shadow pass into the layers of its depth texture.
  Status shadow_pass(const Scene& scene, const Plan& plan, const PassPlan& pass,
                     const std::vector<const Program*>& programs, const DrawTextures& textures,
                     const std::vector<const Program*>& fresh, bool count, RenderResult& result);
  // Uploads the draws `keep` accepts (plus one degenerate warm-up triangle at the end).
  // Also uploads each triangle's CPU interpolation planes for a width x height target.
  std::vector<DrawRange> upload_draws(const std::vector<PreparedDraw>& prepared,
                                      const std::vector<const Program*>& programs, int width,
                                      int height, size_t* warmup_offset);
  // Sets a program's frame and material uniforms, textures and state for material mi.
  void bind_material(const Program& p, int mi, const Plan& plan, const FrameUniforms& frame,
                     const DrawTextures& textures, BindCache& cache);
  // Zeroes the work counters and binds them (count) before a pass; sums them into `work` after.
  void reset_counters();
  Status read_counters(WorkCounters& work);
  // Ends a pass timed from t_pass with the TIME_ELAPSED query begun for it.
  void end_pass(PassStats& stats, Clock::time_point t_pass);
  Result<GLuint> height_field_for(const BoundMaterial& m, std::vector<GLuint>& transient_buffers);
  GLuint texture_for(const Texture* t, const BoundMaterial& m, Upload upload,
                     std::vector<GLuint>& transient);
  GLuint sampler_for(const SamplerState& s);
  Status ensure_target(int w, int h, bool aovs);
  void release_target();

  std::unique_ptr<gl::Context> ctx_;
  bool count_work_ = false;  // BackendConfig::count_work
  std::map<std::string, Program> programs_;
  std::map<std::pair<const Texture*, Upload>, CachedTexture> textures_;
  std::map<HeightFieldKey, CachedTexture> height_fields_;
  GLuint empty_field_ = 0;  // a HeightFieldBuffer with no levels (no depth texture)
  GLuint counters_ = 0;
  std::map<uint32_t, GLuint> samplers_;
  GLuint fbo_ = 0, color_ = 0, depth_ = 0, aov_[2] = {0, 0};
  int fb_w_ = 0, fb_h_ = 0;
  bool fb_aovs_ = false;
  GLuint vao_ = 0, vbo_clip_ = 0, vbo_vary_ = 0, ebo_ = 0, query_ = 0;
  // Shadow maps: one 32-bit float depth array texture (a layer per face) per light, kept while
  // its size holds; the depth-only FBO they are drawn through; the receivers' view data.
  struct ShadowTexture {
    GLuint id = 0;
    int size = 0, faces = 0;
  };
  std::map<int, ShadowTexture> shadow_textures_;
  GLuint shadow_fbo_ = 0, shadow_views_ = 0;
  GLuint triangle_planes_ = 0;
};

GlBackend::~GlBackend() {
  if (!ctx_ || !ctx_->make_current().ok()) return;
  for (auto& [k, p] : programs_) glDeleteProgram(p.id);
  for (auto& [k, t] : textures_) glDeleteTextures(1, &t.id);
  for (auto& [k, b] : height_fields_) glDeleteBuffers(1, &b.id);
  GLuint ssbos[] = {empty_field_, counters_};
  glDeleteBuffers(2, ssbos);
  for (auto& [k, s] : samplers_) glDeleteSamplers(1, &s);
  release_target();
  if (vao_) glDeleteVertexArrays(1, &vao_);
  GLuint bufs[] = {vbo_clip_, vbo_vary_, ebo_};
  glDeleteBuffers(3, bufs);
  if (query_) glDeleteQueries(1, &query_);
  for (auto& [k, t] : shadow_textures_) glDeleteTextures(1, &t.id);
  if (shadow_fbo_) glDeleteFramebuffers(1, &shadow_fbo_);
  if (shadow_views_) glDeleteBuffers(1, &shadow_views_);
  if (triangle_planes_) glDeleteBuffers(1, &triangle_planes_);
}

Result<const Program*> GlBackend::program_for(const std::string& plugin, EffectMask effects,
                                              DepthOutput depth_output, bool aovs, bool count,
                                              double* compile_ms, bool alpha_test) {
  const bool writes_depth = depth_output != DepthOutput::kNone;
  const std::string key = plugin + "/" + std::to_string(effects) + "/" +
                          std::to_string(int(depth_output)) + (aovs ? "a" : "") +
                          (count ? "c" : "") + (alpha_test ? "m" : "");
  if (auto it = programs_.find(key); it != programs_.end()) return &it->second;
  const std::string frag = gl_twin_file(plugin);
  if (!gl::shader_file_exists(frag))
    return Status::error("gl: technique \"" + plugin + "\" has no GLSL twin (gl/shaders/" + frag +
                         ")");
  auto flag = [&](const char* name, bool on) { return std::string(name) + (on ? " 1" : " 0"); };
  const std::vector<std::string> defines = {
      flag("EFFECT_SELF_SHADOW", effects & kEffectSelfShadow),
      flag("EFFECT_DEPTH_WRITE", effects & kEffectDepthWrite),
      flag("EFFECT_SILHOUETTE", effects & kEffectSilhouette),
      flag("EFFECT_SHADOW_PASS", effects & kEffectShadowPass),
      flag("EFFECT_RECEIVE_SHADOW", effects & kEffectReceiveShadow),
      flag("RELIEF_WRITES_DEPTH", writes_depth),
      flag("RELIEF_AOVS", aovs),
      flag("RELIEF_DEPTH_FARTHER", depth_output == DepthOutput::kFarther),
      flag("RELIEF_COUNT", count),
      flag("RELIEF_ALPHA_TEST", alpha_test),
  };
  const auto t0 = Clock::now();
  Result<unsigned> id = gl::build_program("relief.vert", frag, defines);
  if (!id.ok()) return id.status();
  Program p;
  p.id = *id;
  p.loc = find_locations(p.id);
  p.height_field = glGetProgramResourceIndex(p.id, GL_SHADER_STORAGE_BLOCK, "HeightFieldBuffer") !=
                   GL_INVALID_INDEX;
  if (p.height_field) {
    // The packer writes std430 with hf_data right after the header; check the driver agrees.
    const GLuint var = glGetProgramResourceIndex(p.id, GL_BUFFER_VARIABLE, "hf_data[0]");
    const GLenum prop = GL_OFFSET;
    GLint offset = -1;
    if (var != GL_INVALID_INDEX)
      glGetProgramResourceiv(p.id, GL_BUFFER_VARIABLE, var, 1, &prop, 1, nullptr, &offset);
    if (offset != gl::PackedHeightField::kHeaderWords * 4) {
      glDeleteProgram(p.id);
      return Status::error("gl: " + frag + ": HeightFieldBuffer.hf_data at byte " +
                           std::to_string(offset) + ", gl/height_field.h packs it at " +
                           std::to_string(gl::PackedHeightField::kHeaderWords * 4));
    }
  }
  *compile_ms += ms_since(t0);
  return &programs_.emplace(key, p).first->second;
}

GLuint GlBackend::sampler_for(const SamplerState& s) {
  const int aniso = s.filter == Filter::kAnisotropic ? std::clamp(s.max_aniso, 1, 16) : 1;
  const uint32_t key = uint32_t(s.filter) | uint32_t(s.wrap_u) << 4 | uint32_t(s.wrap_v) << 8 |
                       uint32_t(aniso) << 12;
  if (auto it = samplers_.find(key); it != samplers_.end()) return it->second;
  GLuint id = 0;
  glCreateSamplers(1, &id);
  GLenum min = GL_LINEAR_MIPMAP_LINEAR, mag = GL_LINEAR;
  switch (s.filter) {
    case Filter::kNearest:
      min = GL_NEAREST_MIPMAP_NEAREST;
      mag = GL_NEAREST;
      break;
    case Filter::kBilinear:
      min = GL_LINEAR_MIPMAP_NEAREST;
      break;
    case Filter::kTrilinear:
    case Filter::kAnisotropic:
      min = GL_LINEAR_MIPMAP_LINEAR;
      break;
  }
  glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(min));
  glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, static_cast<GLint>(mag));
  glSamplerParameteri(id, GL_TEXTURE_WRAP_S, static_cast<GLint>(wrap_gl(s.wrap_u)));
  glSamplerParameteri(id, GL_TEXTURE_WRAP_T, static_cast<GLint>(wrap_gl(s.wrap_v)));
  if (ctx_->has_extension("GL_ARB_texture_filter_anisotropic") ||
      ctx_->has_extension("GL_EXT_texture_filter_anisotropic"))
    glSamplerParameterf(id, GL_TEXTURE_MAX_ANISOTROPY, static_cast<float>(aniso));
  samplers_.emplace(key, id);
  return id;
}

// The shared pointer of the material that holds `t` (null if none: then nothing may be cached).
TexturePtr owner_of(const BoundMaterial& m, const Texture* t) {
  for (const TexturePtr& p : m.keep_alive)
    if (p.get() == t) return p;
  return nullptr;
}

GLuint GlBackend::texture_for(const Texture* t, const BoundMaterial& m, Upload upload,
                              std::vector<GLuint>& transient) {
  const std::pair<const Texture*, Upload> key{t, upload};
  if (auto it = textures_.find(key); it != textures_.end()) return it->second.id;
  const FormatGl f = upload == Upload::kR32F      ? FormatGl{GL_R32F, GL_RED, GL_FLOAT}
                     : upload == Upload::kRGBA32F ? FormatGl{GL_RGBA32F, GL_RGBA, GL_FLOAT}
                                                  : format_gl(t->format(), t->color_space());
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &id);
  glTextureStorage2D(id, t->levels(), f.internal, t->width(0), t->height(0));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  // Row 0 in memory is v = 0 in both backends: uploaded as stored, no flip.
  std::vector<float> r;
  for (int l = 0; l < t->levels(); ++l) {
    const MipLevel& lv = t->level(l);
    const void* texels = lv.data.data();
    if (upload == Upload::kR32F) {
      // the values the CPU's sample_r_lod decodes, texel for texel
      r.resize(static_cast<size_t>(lv.width) * lv.height);
      for (int y = 0; y < lv.height; ++y)
        for (int x = 0; x < lv.width; ++x)
          r[static_cast<size_t>(y) * lv.width + x] = t->fetch_r(l, x, y);
      texels = r.data();
    } else if (upload == Upload::kRGBA32F) {
      // the values the CPU's sample_lod decodes, all four channels
      r.resize(static_cast<size_t>(lv.width) * lv.height * 4);
      for (int y = 0; y < lv.height; ++y)
        for (int x = 0; x < lv.width; ++x) {
          const glm::vec4 v = t->fetch(l, x, y);
          for (int c = 0; c < 4; ++c) r[(static_cast<size_t>(y) * lv.width + x) * 4 + c] = v[c];
        }
      texels = r.data();
    }
    glTextureSubImage2D(id, l, 0, 0, lv.width, lv.height, f.format, f.type, texels);
  }
  glTextureParameteri(id, GL_TEXTURE_BASE_LEVEL, 0);
  glTextureParameteri(id, GL_TEXTURE_MAX_LEVEL, t->levels() - 1);
  if (TexturePtr owner = owner_of(m, t))
    textures_.emplace(key, CachedTexture{owner, id});
  else
    transient.push_back(id);  // nothing keeps the address alive: do not cache
  return id;
}

Result<GLuint> GlBackend::height_field_for(const BoundMaterial& m,
                                           std::vector<GLuint>& transient_buffers) {
  const int slot = texture_slot_index(*m.plugin, "depth");
  const Texture* t = slot >= 0 ? m.uniforms.textures[slot] : nullptr;
  if (!t || t->empty()) {
    if (!empty_field_) {
      const std::vector<uint32_t> zeros(gl::PackedHeightField::kHeaderWords, 0u);
      glCreateBuffers(1, &empty_field_);
      glNamedBufferStorage(empty_field_, static_cast<GLsizeiptr>(zeros.size() * 4), zeros.data(),
                           0);
    }
    return empty_field_;
  }
  const SamplerState& s = m.uniforms.samplers[slot];
  const HeightFieldKey key{t, s.wrap_u, s.wrap_v};
  if (auto it = height_fields_.find(key); it != height_fields_.end()) return it->second.id;
  Result<gl::PackedHeightField> packed = gl::pack_height_field(*t, s);
  if (!packed.ok()) return packed.status();
  GLuint id = 0;
  glCreateBuffers(1, &id);
  glNamedBufferStorage(id, static_cast<GLsizeiptr>(packed->words.size() * 4), packed->words.data(),
                       0);
  if (TexturePtr owner = owner_of(m, t))
    height_fields_.emplace(key, CachedTexture{owner, id});
  else
    transient_buffers.push_back(id);  // nothing keeps the address alive: do not cache
  return id;
}

void GlBackend::release_target() {
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  GLuint tex[] = {color_, depth_, aov_[0], aov_[1]};
  glDeleteTextures(4, tex);
  fbo_ = color_ = depth_ = aov_[0] = aov_[1] = 0;
  fb_w_ = fb_h_ = 0;
}

Status GlBackend::ensure_target(int w, int h, bool aovs) {
  if (fbo_ && fb_w_ == w && fb_h_ == h && fb_aovs_ == aovs) return {};
  release_target();
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  if (w < 1 || h < 1 || w > max_size || h > max_size)
    return Status::error("gl: target " + std::to_string(w) + "x" + std::to_string(h) +
                         " outside 1.." + std::to_string(max_size));
  glCreateFramebuffers(1, &fbo_);
  auto make = [&](GLenum internal, GLuint* id) {
    glCreateTextures(GL_TEXTURE_2D, 1, id);
    glTextureStorage2D(*id, 1, internal, w, h);
    glTextureParameteri(*id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(*id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  };
  make(GL_RGBA32F, &color_);
  make(GL_DEPTH_COMPONENT32F, &depth_);
  glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, color_, 0);
  glNamedFramebufferTexture(fbo_, GL_DEPTH_ATTACHMENT, depth_, 0);
  if (aovs) {
    make(GL_RGBA32F, &aov_[0]);
    make(GL_RGBA32F, &aov_[1]);
    glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT1, aov_[0], 0);
    glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT2, aov_[1], 0);
    const GLenum bufs[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glNamedFramebufferDrawBuffers(fbo_, 3, bufs);
  } else {
    const GLenum bufs[] = {GL_COLOR_ATTACHMENT0};
    glNamedFramebufferDrawBuffers(fbo_, 1, bufs);
  }
  const GLenum status = glCheckNamedFramebufferStatus(fbo_, GL_DRAW_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char buf[96];
    std::snprintf(buf, sizeof(buf), "gl: framebuffer incomplete (0x%04x)", status);
    release_target();
    return Status::error(buf);
  }
  fb_w_ = w;
  fb_h_ = h;
  fb_aovs_ = aovs;
  return gl_check("framebuffer setup");
}

void set_frame_uniforms(GLuint p, const Locations& l, const FrameUniforms& f) {
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

void set_material_uniforms(GLuint p, const Locations& l, const MaterialUniforms& m) {
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
  // glTF material terms (common.glsl finish_surface, sample_slot); unused ones have no location.
  auto set_map = [&](const std::string& name, const UvMap& u) {
    glProgramUniform2fv(p, glGetUniformLocation(p, (name + ".col0").c_str()), 1, &u.col0[0]);
    glProgramUniform2fv(p, glGetUniformLocation(p, (name + ".col1").c_str()), 1, &u.col1[0]);
    glProgramUniform2fv(p, glGetUniformLocation(p, (name + ".offset").c_str()), 1, &u.offset[0]);
    glProgramUniform1i(p, glGetUniformLocation(p, (name + ".set").c_str()), u.set);
    glProgramUniform1i(p, glGetUniformLocation(p, (name + ".identity").c_str()),
                       u.identity ? 1 : 0);
  };
  for (int i = 0; i < kMaxTextureSlots; ++i)
    set_map("material.uv_maps[" + std::to_string(i) + "]", m.uv_maps[i]);
  set_map("material.emissive_uv", m.emissive_uv);
  set_map("material.occlusion_uv", m.occlusion_uv);
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

std::vector<DrawRange> GlBackend::upload_draws(const std::vector<PreparedDraw>& prepared,
                                               const std::vector<const Program*>& programs,
                                               int width, int height, size_t* warmup_offset) {
  std::vector<DrawRange> ranges;
  size_t nv = 0, ni = 0;
  for (const PreparedDraw& d : prepared) {
    nv += d.clip.size();
    ni += d.indices ? d.indices->size() : 0;
  }
  std::vector<glm::vec4> clip;
  std::vector<float> vary, tri, parts;
  std::vector<uint32_t> idx;
  CpuTrianglePlanes planes;
  clip.reserve(nv);
  vary.reserve(nv * kGlVaryings);
  idx.reserve(ni + 3);
  for (const PreparedDraw& d : prepared) {
    if (!d.indices || d.indices->empty() || !programs[d.material]) continue;
    ranges.push_back({d.material, static_cast<GLsizei>(d.indices->size()), idx.size(),
                      static_cast<GLint>(clip.size()),
                      static_cast<GLint>(tri.size() / kTriangleHeader)});
    // The CPU's planes of every triangle it draws unclipped: the twins interpolate with them,
    // so both backends shade the same numbers (GL's own interpolation differs by ~1e-6, which
    // cone steps and relaxed-cone shadows turn into different hits).
    const std::vector<uint32_t>& ix = *d.indices;
    for (size_t i = 0; i + 2 < ix.size(); i += 3) {
      const size_t base = tri.size();
      tri.resize(base + kTriangleHeader, 0.0f);
      if (std::max({ix[i], ix[i + 1], ix[i + 2]}) >= d.clip.size()) continue;
      const glm::vec4 c[3] = {d.clip[ix[i]], d.clip[ix[i + 1]], d.clip[ix[i + 2]]};
      const size_t dnv = static_cast<size_t>(d.num_varyings);
      const float* v[3] = {&d.varyings[ix[i] * dnv], &d.varyings[ix[i + 1] * dnv],
                           &d.varyings[ix[i + 2] * dnv]};
      if (!cpu_triangle_planes(c, v, d.num_varyings, width, height, planes)) continue;
      tri[base] = int_bits(static_cast<int32_t>(parts.size()));  // rebased below
      tri[base + 1] = int_bits(static_cast<int32_t>(planes.parts.size()));
      tri[base + 2] = int_bits(d.num_varyings);
      for (const CpuTrianglePlanes::Part& part : planes.parts) {
        parts.push_back(int_bits(part.x0));
        parts.push_back(int_bits(part.y0));
        parts.insert(parts.end(), part.corner, part.corner + 6);
        parts.insert(parts.end(), part.planes.begin(), part.planes.end());
      }
    }
    clip.insert(clip.end(), d.clip.begin(), d.clip.end());
    for (size_t k = 0; k < d.clip.size(); ++k) {
      const float* src = &d.varyings[k * static_cast<size_t>(d.num_varyings)];
      vary.insert(vary.end(), src, src + d.num_varyings);
      for (int j = d.num_varyings; j < kGlVaryings; ++j)
        vary.push_back(j < varying::kUv1 ? 1.0f : 0.0f);
    }
    idx.insert(idx.end(), d.indices->begin(), d.indices->end());
  }
  *warmup_offset = idx.size();  // one degenerate triangle (see render)
  idx.insert(idx.end(), {0u, 0u, 0u});
  if (clip.empty()) clip.emplace_back(0.0f);  // the warm-up triangle reads vertex 0
  vary.resize(std::max(vary.size(), static_cast<size_t>(kGlVaryings)));
  glNamedBufferData(vbo_clip_, static_cast<GLsizeiptr>(clip.size() * sizeof(glm::vec4)),
                    clip.data(), GL_STREAM_DRAW);
  glNamedBufferData(vbo_vary_, static_cast<GLsizeiptr>(vary.size() * sizeof(float)), vary.data(),
                    GL_STREAM_DRAW);
  glNamedBufferData(ebo_, static_cast<GLsizeiptr>(idx.size() * sizeof(uint32_t)), idx.data(),
                    GL_STREAM_DRAW);
  // Parts after the headers: rebase the headers' offsets.
  for (size_t h = 0; h < tri.size(); h += kTriangleHeader) {
    int32_t first;
    std::memcpy(&first, &tri[h], sizeof first);
    tri[h] = int_bits(first + static_cast<int32_t>(tri.size()));
  }
  tri.insert(tri.end(), parts.begin(), parts.end());
  tri.resize(std::max(tri.size(), static_cast<size_t>(kTriangleHeader)));
  if (!triangle_planes_) glCreateBuffers(1, &triangle_planes_);
  glNamedBufferData(triangle_planes_, static_cast<GLsizeiptr>(tri.size() * sizeof(float)),
                    tri.data(), GL_STREAM_DRAW);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kTrianglePlanesBinding, triangle_planes_);
  return ranges;
}

void GlBackend::bind_material(const Program& p, int mi, const Plan& plan,
                              const FrameUniforms& frame, const DrawTextures& textures,
                              BindCache& cache) {
  const BoundMaterial& m = plan.materials[mi];
  glUseProgram(p.id);
  auto [it, first_use] = cache.material_of.emplace(p.id, -1);
  if (first_use) {
    set_frame_uniforms(p.id, p.loc, frame);
    glProgramUniform2f(p.id, glGetUniformLocation(p.id, "viewport_size"),
                       static_cast<float>(frame.width), static_cast<float>(frame.height));
  }
  if (it->second != mi) {
    set_material_uniforms(p.id, p.loc, m.uniforms);
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

Status GlBackend::read_counters(WorkCounters& work) {
  // The slots of common.glsl's WorkCountersBuffer, summed into the CPU's WorkCounters.
  std::vector<uint32_t> c(kCounterSlots * kCounterCount);
  glGetNamedBufferSubData(counters_, 0, static_cast<GLsizeiptr>(c.size() * sizeof(uint32_t)),
                          c.data());
  uint64_t sum[kCounterCount] = {};
  for (int slot = 0; slot < kCounterSlots; ++slot)
    for (int k = 0; k < kCounterCount; ++k) sum[k] += c[slot * kCounterCount + k];
  work.fragments = sum[0];
  work.texture_fetches = sum[1];
  work.search_steps = sum[2];
  work.shadow_steps = sum[3];
  work.discarded = sum[4];
  return gl_check("work counters");
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

// Draws a degenerate triangle with each program built in this frame, in the pass's state: drivers
// may finish compiling at the first draw (llvmpipe JITs its fragment code there).
void warm_up(const std::vector<const Program*>& fresh, const std::vector<const Program*>& programs,
             size_t warmup_offset, const std::function<void(const Program&, int)>& bind,
             double* compile_ms) {
  const auto t = Clock::now();
  bool drew = false;
  for (size_t mi = 0; mi < programs.size(); ++mi) {
    if (!programs[mi] || std::find(fresh.begin(), fresh.end(), programs[mi]) == fresh.end())
      continue;
    bind(*programs[mi], static_cast<int>(mi));
    glProgramUniform1i(programs[mi]->id, programs[mi]->loc.tri_base, -1);  // no planes
    glDrawElementsBaseVertex(
        GL_TRIANGLES, 3, GL_UNSIGNED_INT,
        reinterpret_cast<const void*>(static_cast<uintptr_t>(warmup_offset * sizeof(uint32_t))), 0);
    drew = true;
  }
  if (!drew) return;
  glFinish();
  *compile_ms += ms_since(t);
}

void draw_ranges(const std::vector<DrawRange>& ranges, const std::vector<const Program*>& programs,
                 const std::function<void(const Program&, int)>& bind) {
  for (const DrawRange& r : ranges) {
    const Program& p = *programs[r.material];
    bind(p, r.material);
    glProgramUniform1i(p.id, p.loc.tri_base, r.first_triangle);
    glDrawElementsBaseVertex(
        GL_TRIANGLES, r.count, GL_UNSIGNED_INT,
        reinterpret_cast<const void*>(static_cast<uintptr_t>(r.index_offset * sizeof(uint32_t))),
        r.base_vertex);
  }
}

Status GlBackend::shadow_pass(const Scene& scene, const Plan& plan, const PassPlan& pass,
                              const std::vector<const Program*>& programs,
                              const DrawTextures& textures,
                              const std::vector<const Program*>& fresh, bool count,
                              RenderResult& result) {
  const ShadowPassSetup& s = pass.shadow;
  PassStats stats = shadow_pass_stats(pass);
  ShadowTexture& t = shadow_textures_[pass.light];
  if (t.id == 0 || t.size != s.size || t.faces != s.faces) {
    if (t.id) glDeleteTextures(1, &t.id);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t.id);
    glTextureStorage3D(t.id, 1, GL_DEPTH_COMPONENT32F, s.size, s.size, s.faces);
    glTextureParameteri(t.id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(t.id, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    t.size = s.size;
    t.faces = s.faces;
  }
  if (!shadow_fbo_) glCreateFramebuffers(1, &shadow_fbo_);
  glNamedFramebufferDrawBuffer(shadow_fbo_, GL_NONE);
  glNamedFramebufferReadBuffer(shadow_fbo_, GL_NONE);
  // The casters only (CPU: pass.instances with shadow_caster materials).
  std::vector<const Program*> casters(plan.materials.size(), nullptr);
  std::vector<bool> drawn(scene.instances.size(), false);
  for (int i : pass.instances) drawn[i] = true;
  double pass_ms = 0.0, gpu_ms = 0.0;
  bool gpu_valid = true;
  for (int f = 0; f < s.faces; ++f) {
    const FrameUniforms frame = shadow_face_frame(s, f);
    std::vector<PreparedDraw> prepared = prepare_draws(scene, frame.view_proj);
    prepared.erase(std::remove_if(prepared.begin(), prepared.end(),
                                  [&](const PreparedDraw& d) {
                                    return !drawn[d.instance] ||
                                           !plan.materials[d.material].shadow_caster;
                                  }),
                   prepared.end());
    size_t warmup_offset = 0;
    const std::vector<DrawRange> ranges =
        upload_draws(prepared, programs, s.size, s.size, &warmup_offset);
    glNamedFramebufferTextureLayer(shadow_fbo_, GL_DEPTH_ATTACHMENT, t.id, 0, f);
    const GLenum status = glCheckNamedFramebufferStatus(shadow_fbo_, GL_DRAW_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      return Status::error("gl: shadow framebuffer incomplete (" + pass.name + ")");
    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
    glViewport(0, 0, s.size, s.size);
    BindCache cache;
    auto bind = [&](const Program& p, int mi) {
      bind_material(p, mi, plan, frame, textures, cache);
    };
    if (f == 0) warm_up(fresh, programs, warmup_offset, bind, &result.compile_ms);
    if (count) reset_counters();
    const auto t_pass = Clock::now();
    glBeginQuery(GL_TIME_ELAPSED, query_);
    const float depth_clear = 0.0f;
    glClearNamedFramebufferfv(shadow_fbo_, GL_DEPTH, 0, &depth_clear);
    draw_ranges(ranges, programs, bind);
    PassStats face;
    end_pass(face, t_pass);
    pass_ms += face.ms;
    gpu_valid = gpu_valid && face.gpu_ms >= 0.0;
    gpu_ms += face.gpu_ms;
    if (count) {
      WorkCounters work;
      RELIEF_RETURN_IF_ERROR(read_counters(work));
      stats.raster.work += work;
    }
    RELIEF_RETURN_IF_ERROR(gl_check("shadow pass"));
  }
  stats.ms = pass_ms;
  stats.gpu_ms = gpu_valid ? gpu_ms : -1.0;
  result.passes.push_back(stats);
  return {};
}

Result<RenderResult> GlBackend::render(const Scene& scene, const Plan& plan) {
  const auto t_frame = Clock::now();
  RELIEF_RETURN_IF_ERROR(ctx_->make_current());
  while (glGetError() != GL_NO_ERROR) {
  }
  RenderResult result;
  result.device = ctx_->info().renderer;
  const bool aovs = plan.frame.aovs != 0;
  const bool count = count_work_;
  const int w = plan.frame.width, h = plan.frame.height;

  // Drop cached textures and max-mips nobody else holds any more.
  drop_unowned(textures_, glDeleteTextures);
  drop_unowned(height_fields_, glDeleteBuffers);

  // Programs: the main pass's variant of every drawn material and, when there are shadow passes,
  // the casters' shadow-pass variant (or depth only). The first frame of a variant compiles it.
  const size_t nm = plan.materials.size();
  std::vector<const Program*> programs(nm, nullptr), shadow_programs(nm, nullptr);
  std::vector<const Program*> fresh;  // built in this frame
  auto get = [&](const std::string& plugin, EffectMask effects, DepthOutput depth, bool with_aovs,
                 const Program** out, bool alpha_test = false) -> Status {
    const size_t before = programs_.size();
    Result<const Program*> p =
        program_for(plugin, effects, depth, with_aovs, count, &result.compile_ms, alpha_test);
    if (!p.ok()) return p.status();
    *out = *p;
    if (programs_.size() != before) fresh.push_back(*p);
    return {};
  };
  const bool has_shadow_pass =
      std::any_of(plan.passes.begin(), plan.passes.end(),
                  [](const PassPlan& p) { return p.kind == PassPlan::Kind::kShadow; });
  std::vector<PreparedDraw> prepared = prepare_draws(scene, plan.frame.view_proj);
  for (const PreparedDraw& d : prepared) {
    if (d.material < 0 || d.material >= static_cast<int>(nm))
      return Status::error("gl: instance " + std::to_string(d.instance) + " has no material");
    if (programs[d.material]) continue;
    const BoundMaterial& m = plan.materials[d.material];
    if (!m.plugin) return Status::error("gl: material " + std::to_string(d.material) + " unbound");
    RELIEF_RETURN_IF_ERROR(get(m.plugin->name, m.effects, m.plugin->depth_output(m.effects), aovs,
                               &programs[d.material], m.uniforms.alpha_mode == AlphaMode::kMask));
  }
  for (size_t mi = 0; mi < nm && has_shadow_pass; ++mi) {
    const BoundMaterial& m = plan.materials[mi];
    if (!m.plugin || !m.shadow_caster) continue;
    const bool mask = m.uniforms.alpha_mode == AlphaMode::kMask;
    if (m.shadow_effects)
      RELIEF_RETURN_IF_ERROR(get(m.plugin->name, m.shadow_effects,
                                 m.plugin->depth_output(m.shadow_effects), false,
                                 &shadow_programs[mi], mask));
    else if (mask)  // cut out: the twin's own discard (the CPU's MaskCasterKernel)
      RELIEF_RETURN_IF_ERROR(
          get(m.plugin->name, 0, m.plugin->depth_output(0), false, &shadow_programs[mi], true));
    else
      RELIEF_RETURN_IF_ERROR(get("depth_only", 0, DepthOutput::kNone, false, &shadow_programs[mi]));
  }

  // Uploads: textures (cached while the scene holds them) and this frame's vertex data.
  const auto t_upload = Clock::now();
  std::vector<GLuint> transient, transient_buffers;
  // What nothing caches dies with the frame, on every return path.
  struct Transients {
    std::vector<GLuint>& textures;
    std::vector<GLuint>& buffers;
    ~Transients() {
      glDeleteTextures(static_cast<GLsizei>(textures.size()), textures.data());
      glDeleteBuffers(static_cast<GLsizei>(buffers.size()), buffers.data());
    }
  } transients{transient, transient_buffers};
  DrawTextures textures;
  textures.tex.resize(nm);
  textures.samplers.resize(nm);
  textures.fields.assign(nm, 0);
  textures.extra.assign(nm, {0, 0, 0, 0});
  for (size_t mi = 0; mi < nm; ++mi) {
    if (!programs[mi] && !shadow_programs[mi]) continue;
    const BoundMaterial& m = plan.materials[mi];
    if (const Texture* t = m.uniforms.emissive_texture; t && !t->empty()) {
      textures.extra[mi][0] = texture_for(t, m, Upload::kNative, transient);
      textures.extra[mi][1] = sampler_for(m.uniforms.emissive_sampler);
    }
    if (const Texture* t = m.uniforms.occlusion_texture; t && !t->empty()) {
      textures.extra[mi][2] = texture_for(t, m, Upload::kNative, transient);
      textures.extra[mi][3] = sampler_for(m.uniforms.occlusion_sampler);
    }
    for (int s = 0; s < kMaxTextureSlots; ++s) {
      const Texture* t = m.uniforms.textures[s];
      textures.tex[mi][s] =
          t && !t->empty() ? texture_for(t, m, upload_for(*m.plugin, s, *t), transient) : 0;
      textures.samplers[mi][s] = t ? sampler_for(m.uniforms.samplers[s]) : 0;
    }
    if ((programs[mi] && programs[mi]->height_field) ||
        (shadow_programs[mi] && shadow_programs[mi]->height_field)) {
      Result<GLuint> f = height_field_for(m, transient_buffers);
      if (!f.ok()) return f.status();
      textures.fields[mi] = *f;
    }
  }
  if (count && !counters_) {
    glCreateBuffers(1, &counters_);
    glNamedBufferStorage(counters_, kCounterSlots * kCounterCount * sizeof(uint32_t), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
  }
  if (!vao_) {
    glCreateVertexArrays(1, &vao_);
    GLuint bufs[3];
    glCreateBuffers(3, bufs);
    vbo_clip_ = bufs[0];
    vbo_vary_ = bufs[1];
    ebo_ = bufs[2];
    glVertexArrayVertexBuffer(vao_, 0, vbo_clip_, 0, sizeof(glm::vec4));
    glVertexArrayVertexBuffer(vao_, 1, vbo_vary_, 0, sizeof(float) * kGlVaryings);
    glEnableVertexArrayAttrib(vao_, 0);
    glVertexArrayAttribFormat(vao_, 0, 4, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao_, 0, 0);
    for (int a = 0; a < kGlVaryings / 4; ++a) {
      glEnableVertexArrayAttrib(vao_, 1 + a);
      glVertexArrayAttribFormat(vao_, 1 + a, 4, GL_FLOAT, GL_FALSE, sizeof(float) * 4 * a);
      glVertexArrayAttribBinding(vao_, 1 + a, 1);
    }
    glVertexArrayElementBuffer(vao_, ebo_);
    glCreateQueries(GL_TIME_ELAPSED, 1, &query_);
  }
  RELIEF_RETURN_IF_ERROR(ensure_target(w, h, aovs));
  glFinish();
  result.upload_ms = ms_since(t_upload);
  RELIEF_RETURN_IF_ERROR(gl_check("upload"));

  // Fixed state of every pass: reversed-Z, no blending, CCW front faces.
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glDepthMask(GL_TRUE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glFrontFace(GL_CCW);
  glCullFace(GL_BACK);
  glBindVertexArray(vao_);

  // Shadow passes (plan order), then the receivers' view of each map.
  std::vector<float> views(static_cast<size_t>(kMaxLights) * kShadowViewFloats, 0.0f);
  for (const PassPlan& pass : plan.passes) {
    if (pass.kind != PassPlan::Kind::kShadow) continue;
    if (pass.light < 0 || pass.light >= kMaxLights)
      return Status::error("gl: shadow pass \"" + pass.name + "\" has no light uniform");
    RELIEF_RETURN_IF_ERROR(
        shadow_pass(scene, plan, pass, shadow_programs, textures, fresh, count, result));
    pack_shadow_view(pass.shadow, plan.shadow,
                     &views[static_cast<size_t>(pass.light) * kShadowViewFloats]);
  }
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

  // The main pass.
  FrameUniforms frame = plan.frame;
  frame.width = w;
  frame.height = h;
  size_t warmup_offset = 0;
  // Plan::draw_order: opaque and MASK draws, then BLEND ones back to front (as the CPU).
  std::vector<PreparedDraw> ordered;
  ordered.reserve(prepared.size());
  for (int i : main_draw_order(plan, prepared.size())) ordered.push_back(std::move(prepared[i]));
  const std::vector<DrawRange> ranges = upload_draws(ordered, programs, w, h, &warmup_offset);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, w, h);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  BindCache cache;
  // BLEND draws: src-over of the straight-alpha colour onto the premultiplied target (the CPU's
  // DrawCall::blend), depth tested but not written, no AOVs.
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  auto bind = [&](const Program& p, int mi) {
    bind_material(p, mi, plan, frame, textures, cache);
    const bool blend = plan.materials[mi].uniforms.alpha_mode == AlphaMode::kBlend;
    if (blend) {
      glEnablei(GL_BLEND, 0);
    } else {
      glDisablei(GL_BLEND, 0);
    }
    glDepthMask(blend ? GL_FALSE : GL_TRUE);
    if (aovs)
      for (GLuint a = 1; a <= 2; ++a) glColorMaski(a, !blend, !blend, !blend, !blend);
  };
  warm_up(fresh, programs, warmup_offset, bind, &result.compile_ms);
  if (count) reset_counters();
  const auto t_pass = Clock::now();
  // Begun after binding the target: llvmpipe attributes a query to the framebuffer's scene.
  glBeginQuery(GL_TIME_ELAPSED, query_);
  // premultiplied, as the CPU's; warm-up draws may have left a BLEND draw's state
  const glm::vec4 bg = clear_color(scene);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glClearNamedFramebufferfv(fbo_, GL_COLOR, 0, &bg[0]);
  if (aovs) {
    const float zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(fbo_, GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(fbo_, GL_COLOR, 2, zero);
  }
  const float depth_clear = 0.0f;
  glClearNamedFramebufferfv(fbo_, GL_DEPTH, 0, &depth_clear);
  draw_ranges(ranges, programs, bind);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  PassStats main;
  main.name = "main";
  end_pass(main, t_pass);
  RELIEF_RETURN_IF_ERROR(gl_check("main pass"));
  if (count) RELIEF_RETURN_IF_ERROR(read_counters(main.raster.work));
  result.passes.push_back(main);

  // Read back, flipping rows: GL's row 0 is the bottom, the Image's the top.
  const auto t_read = Clock::now();
  Framebuffer fb(w, h, plan.frame.aovs);
  std::vector<float> buf(static_cast<size_t>(w) * h * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  auto read_rgba = [&](GLenum attachment) {
    glNamedFramebufferReadBuffer(fbo_, attachment);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, buf.data());
  };
  auto finite = [](float v) { return std::isfinite(v) ? v : 0.0f; };
  read_rgba(GL_COLOR_ATTACHMENT0);
  for (int y = 0; y < h; ++y) {
    const float* row = &buf[static_cast<size_t>(h - 1 - y) * w * 4];
    for (int x = 0; x < w; ++x)
      fb.color.at(x, y) = glm::vec4(finite(row[x * 4]), finite(row[x * 4 + 1]),
                                    finite(row[x * 4 + 2]), finite(row[x * 4 + 3]));
  }
  if (aovs) {
    for (int a = 0; a < 2; ++a) {
      read_rgba(GL_COLOR_ATTACHMENT1 + a);
      for (int y = 0; y < h; ++y) {
        const float* row = &buf[static_cast<size_t>(h - 1 - y) * w * 4];
        for (int x = 0; x < w; ++x) {
          float* dst = fb.aov_at(x, y);
          for (int c = 0; c < 4 && a * 4 + c < kAovTotalChannels; ++c)
            dst[a * 4 + c] = finite(row[x * 4 + c]);
        }
      }
    }
  }
  glNamedFramebufferReadBuffer(fbo_, GL_COLOR_ATTACHMENT0);
  std::vector<float> dbuf(static_cast<size_t>(w) * h);
  glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, dbuf.data());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      fb.depth.at(x, y) = finite(dbuf[static_cast<size_t>(h - 1 - y) * w + x]);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  RELIEF_RETURN_IF_ERROR(gl_check("read back"));
  result.readback_ms = ms_since(t_read);
  result.framebuffer = std::move(fb);
  result.frame_ms = ms_since(t_frame);
  return result;
}

}  // namespace

Result<std::unique_ptr<Backend>> make_gl_backend(const BackendConfig& config) {
  Result<std::unique_ptr<gl::Context>> ctx = gl::Context::create(config.gpu);
  if (!ctx.ok()) return ctx.status();
  return std::unique_ptr<Backend>(std::make_unique<GlBackend>(std::move(*ctx), config));
}

}  // namespace relief
