// The GL backend's resources (gl/gl_backend_internal.h): textures, samplers and max-mips (cached
// while the scene holds their texture), the vertex, index and triangle-plane buffers of a pass,
// the render target and the shadow maps.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <epoxy/gl.h>

#include "gl/gl_backend_internal.h"
#include "gl/height_field.h"
#include "plugins/registry.h"
#include "render/derived_maps.h"

#ifndef GL_TEXTURE_MAX_ANISOTROPY
#define GL_TEXTURE_MAX_ANISOTROPY 0x84FE
#endif

namespace relief::gl_detail {
namespace {

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

// Deletes (with `del`, given the cache entry) the cached objects whose texture or environment only
// the cache still holds.
template <class Map, class Delete>
void drop_unowned(Map& cache, Delete del) {
  for (auto it = cache.begin(); it != cache.end();) {
    if (it->second.owner.use_count() == 1) {
      del(it->second);
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

// The shared pointer of the material that holds `t` (null if none: then nothing may be cached).
TexturePtr owner_of(const BoundMaterial& m, const Texture* t) {
  for (const TexturePtr& p : m.keep_alive)
    if (p.get() == t) return p;
  return nullptr;
}

// The texels of level l as uploaded: as stored (kNative), or decoded into `scratch`.
const void* upload_texels(const Texture& t, int l, Upload upload, std::vector<float>& scratch) {
  const MipLevel& lv = t.level(l);
  if (upload == Upload::kR32F) {
    // the values the CPU's sample_r_lod decodes, texel for texel
    scratch.resize(static_cast<size_t>(lv.width) * lv.height);
    for (int y = 0; y < lv.height; ++y)
      for (int x = 0; x < lv.width; ++x)
        scratch[static_cast<size_t>(y) * lv.width + x] = t.fetch_r(l, x, y);
    return scratch.data();
  }
  if (upload == Upload::kRGBA32F) {
    // the values the CPU's sample_lod decodes, all four channels
    scratch.resize(static_cast<size_t>(lv.width) * lv.height * 4);
    for (int y = 0; y < lv.height; ++y)
      for (int x = 0; x < lv.width; ++x) {
        const glm::vec4 v = t.fetch(l, x, y);
        for (int c = 0; c < 4; ++c) scratch[(static_cast<size_t>(y) * lv.width + x) * 4 + c] = v[c];
      }
    return scratch.data();
  }
  return lv.data.data();
}

// The (min, mag) filters of a sampler's Filter.
std::pair<GLenum, GLenum> filters_gl(Filter f) {
  switch (f) {
    case Filter::kNearest:
      return {GL_NEAREST_MIPMAP_NEAREST, GL_NEAREST};
    case Filter::kBilinear:
      return {GL_LINEAR_MIPMAP_NEAREST, GL_LINEAR};
    case Filter::kTrilinear:
    case Filter::kAnisotropic:
      return {GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR};
  }
  return {GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR};
}

// common.glsl's TrianglePlanesBuffer: per triangle a header (first part's offset, part count,
// varying count, unused; ints stored bit for bit), then the parts: (x0, y0) as ints, the corners
// (x, y) x 3 and the CPU rasterizer's planes (depth, 1/w, the draw's varyings times 1/w: 16, or
// kCountExtended with COLOR_0 or TEXCOORD_1), three floats each.

float int_bits(int32_t v) {
  float f;
  std::memcpy(&f, &v, sizeof f);
  return f;
}

// What upload_draws gathers before it uploads: clip positions, varyings (kGlVaryings a vertex),
// indices, and the TrianglePlanesBuffer's headers (tri) and parts.
struct DrawStreams {
  std::vector<glm::vec4> clip;
  std::vector<float> vary, tri, parts;
  std::vector<uint32_t> idx;
};

void reserve_streams(const std::vector<PreparedDraw>& prepared, DrawStreams& s) {
  size_t nv = 0, ni = 0;
  for (const PreparedDraw& d : prepared) {
    nv += d.clip.size();
    ni += d.indices ? d.indices->size() : 0;
  }
  s.clip.reserve(nv);
  s.vary.reserve(nv * kGlVaryings);
  s.idx.reserve(ni + 3);
}

// The CPU's planes of every triangle it draws unclipped: the twins interpolate with them,
// so both backends shade the same numbers (GL's own interpolation differs by ~1e-6, which
// cone steps and relaxed-cone shadows turn into different hits).
void append_triangle_planes(const PreparedDraw& d, int width, int height, CpuTrianglePlanes& planes,
                            DrawStreams& s) {
  const std::vector<uint32_t>& ix = *d.indices;
  for (size_t i = 0; i + 2 < ix.size(); i += 3) {
    const size_t base = s.tri.size();
    s.tri.resize(base + kTriangleHeader, 0.0f);
    if (std::max({ix[i], ix[i + 1], ix[i + 2]}) >= d.clip.size()) continue;
    const glm::vec4 c[3] = {d.clip[ix[i]], d.clip[ix[i + 1]], d.clip[ix[i + 2]]};
    const size_t dnv = static_cast<size_t>(d.num_varyings);
    const float* v[3] = {&d.varyings[ix[i] * dnv], &d.varyings[ix[i + 1] * dnv],
                         &d.varyings[ix[i + 2] * dnv]};
    if (!cpu_triangle_planes(c, v, d.num_varyings, width, height, planes)) continue;
    s.tri[base] = int_bits(static_cast<int32_t>(s.parts.size()));  // rebased on upload
    s.tri[base + 1] = int_bits(static_cast<int32_t>(planes.parts.size()));
    s.tri[base + 2] = int_bits(d.num_varyings);
    for (const CpuTrianglePlanes::Part& part : planes.parts) {
      s.parts.push_back(int_bits(part.x0));
      s.parts.push_back(int_bits(part.y0));
      s.parts.insert(s.parts.end(), part.corner, part.corner + 6);
      s.parts.insert(s.parts.end(), part.planes.begin(), part.planes.end());
    }
  }
}

void append_vertices(const PreparedDraw& d, DrawStreams& s) {
  s.clip.insert(s.clip.end(), d.clip.begin(), d.clip.end());
  append_padded_varyings(d.varyings.data(), d.num_varyings, d.clip.size(), s.vary);
  s.idx.insert(s.idx.end(), d.indices->begin(), d.indices->end());
}

// The TrianglePlanesBuffer: the parts after the headers, whose offsets are rebased onto them.
std::vector<float>& triangle_planes_data(DrawStreams& s) {
  for (size_t h = 0; h < s.tri.size(); h += kTriangleHeader) {
    int32_t first;
    std::memcpy(&first, &s.tri[h], sizeof first);
    s.tri[h] = int_bits(first + static_cast<int32_t>(s.tri.size()));
  }
  s.tri.insert(s.tri.end(), s.parts.begin(), s.parts.end());
  s.tri.resize(std::max(s.tri.size(), static_cast<size_t>(kTriangleHeader)));
  return s.tri;
}

template <class T>
void stream_data(GLuint buffer, const std::vector<T>& data) {
  glNamedBufferData(buffer, static_cast<GLsizeiptr>(data.size() * sizeof(T)), data.data(),
                    GL_STREAM_DRAW);
}

}  // namespace

void append_padded_varyings(const float* varyings, int num_varyings, size_t vertices,
                            std::vector<float>& out) {
  const size_t base = out.size();
  out.resize(base + vertices * kGlVaryings);
  for (size_t k = 0; k < vertices; ++k) {
    const float* src = varyings + k * static_cast<size_t>(num_varyings);
    float* dst = &out[base + k * kGlVaryings];
    std::copy(src, src + num_varyings, dst);
    for (int j = num_varyings; j < kGlVaryings; ++j) dst[j] = j < varying::kUv1 ? 1.0f : 0.0f;
  }
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

FrameTransients::~FrameTransients() {
  glDeleteTextures(static_cast<GLsizei>(textures.size()), textures.data());
  glDeleteBuffers(static_cast<GLsizei>(buffers.size()), buffers.data());
}

void GlBackend::drop_unowned_textures() {
  drop_unowned(textures_, [](CachedTexture& t) { glDeleteTextures(1, &t.id); });
  drop_unowned(height_fields_, [](CachedTexture& b) { glDeleteBuffers(1, &b.id); });
  drop_unowned(environments_, [](CachedEnvironment& e) { glDeleteTextures(2, e.ids); });
}

GLuint GlBackend::sampler_for(const SamplerState& s) {
  const int aniso = s.filter == Filter::kAnisotropic ? std::clamp(s.max_aniso, 1, 16) : 1;
  const uint32_t key = uint32_t(s.filter) | uint32_t(s.wrap_u) << 4 | uint32_t(s.wrap_v) << 8 |
                       uint32_t(aniso) << 12;
  if (auto it = samplers_.find(key); it != samplers_.end()) return it->second;
  GLuint id = 0;
  glCreateSamplers(1, &id);
  const auto [min, mag] = filters_gl(s.filter);
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

namespace {

// A new GL texture of every level of t (never regenerated: the CPU's levels as they are), base
// level 0, max level levels - 1.
GLuint create_texture(const Texture& t, Upload upload) {
  const FormatGl f = upload == Upload::kR32F      ? FormatGl{GL_R32F, GL_RED, GL_FLOAT}
                     : upload == Upload::kRGBA32F ? FormatGl{GL_RGBA32F, GL_RGBA, GL_FLOAT}
                                                  : format_gl(t.format(), t.color_space());
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &id);
  glTextureStorage2D(id, t.levels(), f.internal, t.width(0), t.height(0));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  // Row 0 in memory is v = 0 in both backends: uploaded as stored, no flip.
  std::vector<float> scratch;
  for (int l = 0; l < t.levels(); ++l) {
    const MipLevel& lv = t.level(l);
    glTextureSubImage2D(id, l, 0, 0, lv.width, lv.height, f.format, f.type,
                        upload_texels(t, l, upload, scratch));
  }
  glTextureParameteri(id, GL_TEXTURE_BASE_LEVEL, 0);
  glTextureParameteri(id, GL_TEXTURE_MAX_LEVEL, t.levels() - 1);
  return id;
}

}  // namespace

GLuint GlBackend::texture_for(const Texture* t, const BoundMaterial& m, Upload upload,
                              std::vector<GLuint>& transient) {
  const std::pair<const Texture*, Upload> key{t, upload};
  if (auto it = textures_.find(key); it != textures_.end()) return it->second.id;
  const GLuint id = create_texture(*t, upload);
  if (TexturePtr owner = owner_of(m, t))
    textures_.emplace(key, CachedTexture{owner, id});
  else
    transient.push_back(id);  // nothing keeps the address alive: do not cache
  return id;
}

void GlBackend::upload_environment(const Plan& plan, FrameTransients& transients,
                                   DrawTextures& textures) {
  const EnvironmentMaps* env = plan.frame.environment;
  if (!env) return;
  auto it = environments_.find(env);
  if (it == environments_.end()) {
    // RGBA16F: the CPU's stored halves go up unchanged (format_gl: GL_RGBA16F, GL_HALF_FLOAT).
    CachedEnvironment c;
    c.ids[0] = env->specular.empty() ? 0 : create_texture(env->specular, Upload::kNative);
    c.ids[1] = env->brdf_lut.empty() ? 0 : create_texture(env->brdf_lut, Upload::kNative);
    if (plan.environment.get() == env) {
      c.owner = plan.environment;
      it = environments_.emplace(env, c).first;
    } else {  // nothing keeps the address alive: for this frame only
      transients.textures.insert(transients.textures.end(), c.ids, c.ids + 2);
      textures.env_specular = c.ids[0];
      textures.env_brdf = c.ids[1];
    }
  }
  if (it != environments_.end()) {
    textures.env_specular = it->second.ids[0];
    textures.env_brdf = it->second.ids[1];
  }
  // environment_maps.h: the chain trilinear, the table bilinear, both clamped to the edge
  textures.env_specular_sampler = sampler_for({Filter::kTrilinear, Wrap::kClamp, Wrap::kClamp, 1});
  textures.env_brdf_sampler = sampler_for({Filter::kBilinear, Wrap::kClamp, Wrap::kClamp, 1});
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

Status GlBackend::upload_textures(const Plan& plan, const FramePrograms& programs,
                                  FrameTransients& transients, DrawTextures& textures) {
  const size_t nm = plan.materials.size();
  textures.tex.resize(nm);
  textures.samplers.resize(nm);
  textures.fields.assign(nm, 0);
  textures.extra.assign(nm, {0, 0, 0, 0, 0, 0});
  for (size_t mi = 0; mi < nm; ++mi) {
    if (!programs.main[mi] && !programs.shadow[mi]) continue;
    RELIEF_RETURN_IF_ERROR(
        upload_material_textures(plan.materials[mi], mi, programs, transients, textures));
  }
  return {};
}

Status GlBackend::upload_material_textures(const BoundMaterial& m, size_t mi,
                                           const FramePrograms& programs,
                                           FrameTransients& transients, DrawTextures& textures) {
  if (const Texture* t = m.uniforms.emissive_texture; t && !t->empty()) {
    textures.extra[mi][0] = texture_for(t, m, Upload::kNative, transients.textures);
    textures.extra[mi][1] = sampler_for(m.uniforms.emissive_sampler);
  }
  if (const Texture* t = m.uniforms.occlusion_texture; t && !t->empty()) {
    textures.extra[mi][2] = texture_for(t, m, Upload::kNative, transients.textures);
    textures.extra[mi][3] = sampler_for(m.uniforms.occlusion_sampler);
  }
  if (const Texture* t = m.uniforms.metallic_roughness_texture; t && !t->empty()) {
    textures.extra[mi][4] = texture_for(t, m, Upload::kNative, transients.textures);
    textures.extra[mi][5] = sampler_for(m.uniforms.metallic_roughness_sampler);
  }
  for (int s = 0; s < kMaxTextureSlots; ++s) {
    const Texture* t = m.uniforms.textures[s];
    textures.tex[mi][s] =
        t && !t->empty() ? texture_for(t, m, upload_for(*m.plugin, s, *t), transients.textures) : 0;
    textures.samplers[mi][s] = t ? sampler_for(m.uniforms.samplers[s]) : 0;
  }
  if ((programs.main[mi] && programs.main[mi]->height_field) ||
      (programs.shadow[mi] && programs.shadow[mi]->height_field)) {
    Result<GLuint> f = height_field_for(m, transients.buffers);
    if (!f.ok()) return f.status();
    textures.fields[mi] = *f;
  }
  return {};
}

void GlBackend::ensure_counters() {
  if (counters_) return;
  glCreateBuffers(1, &counters_);
  glNamedBufferStorage(counters_, kCounterSlots * kCounterCount * sizeof(uint32_t), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
}

void GlBackend::ensure_vertex_array() {
  if (vao_) return;
  glCreateVertexArrays(1, &vao_);
  GLuint bufs[3];
  glCreateBuffers(3, bufs);
  vbo_clip_ = bufs[0];
  vbo_vary_ = bufs[1];
  ebo_ = bufs[2];
  format_vertex_array(vao_, vbo_clip_, vbo_vary_, ebo_);
  glCreateQueries(GL_TIME_ELAPSED, 1, &query_);
}

void GlBackend::format_vertex_array(GLuint vao, GLuint position, GLuint varyings, GLuint indices) {
  glVertexArrayVertexBuffer(vao, 0, position, 0, sizeof(glm::vec4));
  glVertexArrayVertexBuffer(vao, 1, varyings, 0, sizeof(float) * kGlVaryings);
  glEnableVertexArrayAttrib(vao, 0);
  glVertexArrayAttribFormat(vao, 0, 4, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao, 0, 0);
  for (int a = 0; a < kGlVaryings / 4; ++a) {
    glEnableVertexArrayAttrib(vao, 1 + a);
    glVertexArrayAttribFormat(vao, 1 + a, 4, GL_FLOAT, GL_FALSE, sizeof(float) * 4 * a);
    glVertexArrayAttribBinding(vao, 1 + a, 1);
  }
  glVertexArrayElementBuffer(vao, indices);
}

std::vector<DrawRange> GlBackend::upload_draws(const std::vector<PreparedDraw>& prepared,
                                               const std::vector<const Program*>& programs,
                                               int width, int height, size_t* warmup_offset) {
  std::vector<DrawRange> ranges;
  DrawStreams s;
  reserve_streams(prepared, s);
  CpuTrianglePlanes planes;
  for (const PreparedDraw& d : prepared) {
    if (!d.indices || d.indices->empty() || !programs[d.material]) continue;
    ranges.push_back({d.material, static_cast<GLsizei>(d.indices->size()), s.idx.size(),
                      static_cast<GLint>(s.clip.size()),
                      static_cast<GLint>(s.tri.size() / kTriangleHeader), vao_});
    append_triangle_planes(d, width, height, planes, s);
    append_vertices(d, s);
  }
  *warmup_offset = s.idx.size();  // one degenerate triangle (see warm_up in gl_passes.cpp)
  s.idx.insert(s.idx.end(), {0u, 0u, 0u});
  if (s.clip.empty()) s.clip.emplace_back(0.0f);  // the warm-up triangle reads vertex 0
  s.vary.resize(std::max(s.vary.size(), static_cast<size_t>(kGlVaryings)));
  stream_data(vbo_clip_, s.clip);
  stream_data(vbo_vary_, s.vary);
  stream_data(ebo_, s.idx);
  if (!triangle_planes_) glCreateBuffers(1, &triangle_planes_);
  stream_data(triangle_planes_, triangle_planes_data(s));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kTrianglePlanesBinding, triangle_planes_);
  return ranges;
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

GLuint GlBackend::shadow_texture(int light, const ShadowPassSetup& s) {
  ShadowTexture& t = shadow_textures_[light];
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
  return t.id;
}

}  // namespace relief::gl_detail
