// The relief paper's appendix shader as a bench-only GL program (gl/appendix_relief.h).
#include "gl/appendix_relief.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "gl/context.h"
#include "gl/gl_backend_internal.h"
#include "gl/shader.h"

namespace relief::gl {

using gl_detail::Clock;
using gl_detail::gl_check;
using gl_detail::ms_since;

struct AppendixRelief::State {
  GLuint vao = 0, vbo = 0, ibo = 0, tex = 0, sampler = 0;
  GLuint fbo = 0, color = 0, hits = 0, depth = 0;
  GLuint program = 0, program_hits = 0;
  GLsizei index_count = 0;
  int width = 0, height = 0;
  bool cull = true;
  glm::vec4 background{0.0f};

  void release_target() {
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &color);
    glDeleteTextures(1, &hits);
    glDeleteRenderbuffers(1, &depth);
    fbo = color = hits = depth = 0;
  }
  void release() {
    release_target();
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(1, &vbo);
    glDeleteBuffers(1, &ibo);
    glDeleteTextures(1, &tex);
    glDeleteSamplers(1, &sampler);
    glDeleteProgram(program);
    glDeleteProgram(program_hits);
    *this = State();
  }
};

namespace {

// One vertex as the vertex stage reads it (appendix_relief_vs.glsl).
struct Vertex {
  float position[3];
  float normal[3];
  float tangent[4];
  float uv[2];
};

uint8_t unorm8(float v) {
  return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

// The paper's relief texture: normal (rgb) and depth (a), RGBA8, at the depth map's size.
std::vector<uint8_t> relief_texels(const Texture& depth, const Texture* normal) {
  const int w = depth.width(0), h = depth.height(0);
  std::vector<uint8_t> out(static_cast<size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::vec4 n(0.5f, 0.5f, 1.0f, 1.0f);
      if (normal)
        n = normal->fetch(0, static_cast<int>(static_cast<int64_t>(x) * normal->width(0) / w),
                          static_cast<int>(static_cast<int64_t>(y) * normal->height(0) / h));
      uint8_t* t = &out[(static_cast<size_t>(y) * w + x) * 4];
      t[0] = unorm8(n.x);
      t[1] = unorm8(n.y);
      t[2] = unorm8(n.z);
      t[3] = unorm8(depth.fetch_r(0, x, y));
    }
  return out;
}

Result<GLuint> build(int linear_steps, int binary_steps, bool hits) {
  std::vector<std::string> defines = {"LINEAR_STEPS " + std::to_string(linear_steps),
                                      "BINARY_STEPS " + std::to_string(binary_steps)};
  if (hits) defines.emplace_back("APPENDIX_HITS");
  return build_program("appendix_relief_vs.glsl", "appendix_relief_fs.glsl", defines);
}

void set_uniform(GLuint p, const char* name, const glm::mat4& m) {
  glProgramUniformMatrix4fv(p, glGetUniformLocation(p, name), 1, GL_FALSE, &m[0][0]);
}
void set_uniform(GLuint p, const char* name, const glm::vec3& v) {
  glProgramUniform3f(p, glGetUniformLocation(p, name), v.x, v.y, v.z);
}

// The target: RGBA8 colour, RGBA32F hits, 32-bit float depth, width x height.
Status make_target(AppendixRelief::State& s, int width, int height) {
  s.width = width;
  s.height = height;
  glCreateTextures(GL_TEXTURE_2D, 1, &s.color);
  glTextureStorage2D(s.color, 1, GL_RGBA8, width, height);
  glCreateTextures(GL_TEXTURE_2D, 1, &s.hits);
  glTextureStorage2D(s.hits, 1, GL_RGBA32F, width, height);
  glCreateRenderbuffers(1, &s.depth);
  glNamedRenderbufferStorage(s.depth, GL_DEPTH_COMPONENT32F, width, height);
  glCreateFramebuffers(1, &s.fbo);
  glNamedFramebufferTexture(s.fbo, GL_COLOR_ATTACHMENT0, s.color, 0);
  glNamedFramebufferTexture(s.fbo, GL_COLOR_ATTACHMENT1, s.hits, 0);
  glNamedFramebufferRenderbuffer(s.fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, s.depth);
  if (glCheckNamedFramebufferStatus(s.fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    return Status::error("appendix shader: incomplete framebuffer");
  return {};
}

}  // namespace

Result<std::unique_ptr<AppendixRelief>> AppendixRelief::create(int gpu) {
  Result<std::unique_ptr<Context>> ctx = Context::create(gpu);
  if (!ctx.ok()) return ctx.status();
  RELIEF_RETURN_IF_ERROR((*ctx)->make_current());
  std::unique_ptr<AppendixRelief> a(new AppendixRelief());
  a->ctx_ = std::move(*ctx);
  a->s_ = std::make_unique<State>();
  return a;
}

AppendixRelief::~AppendixRelief() {
  if (ctx_ && s_ && ctx_->make_current().ok()) s_->release();
}

std::string AppendixRelief::device() const {
  return ctx_->info().renderer;
}

Status AppendixRelief::prepare(const Scene& scene, int width, int height, int linear_steps,
                               int binary_steps) {
  if (linear_steps < 2 || linear_steps > 1024 || binary_steps < 0 || binary_steps > 64)
    return Status::usage("appendix shader: steps " + std::to_string(linear_steps) + "+" +
                         std::to_string(binary_steps) + " out of range (2..1024 + 0..64)");
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    return Status::usage("appendix shader: size out of range");
  if (scene.instances.empty() || scene.cameras.empty() || scene.lights.empty())
    return Status::error("appendix shader: the scene needs an instance, a camera and a light");
  const Instance& inst = scene.instances[0];
  const Mesh& mesh = scene.meshes.at(inst.mesh);
  const Material& mat = scene.materials.at(inst.material);
  const auto depth_it = mat.textures.find("depth");
  if (depth_it == mat.textures.end() || !depth_it->second)
    return Status::error("appendix shader: material '" + mat.name + "' has no depth map");
  if (mesh.tangents.size() != mesh.positions.size() || mesh.normals.size() != mesh.positions.size())
    return Status::error("appendix shader: mesh '" + mesh.name + "' has no tangents");
  const auto normal_it = mat.textures.find("normal");
  const Texture* normal = normal_it != mat.textures.end() ? normal_it->second.get() : nullptr;

  RELIEF_RETURN_IF_ERROR(ctx_->make_current());
  State& s = *s_;
  s.release();

  // geometry, in world space
  const glm::mat3 m3(inst.transform);
  const glm::mat3 nm = glm::transpose(glm::inverse(m3));
  const float handed = glm::determinant(m3) < 0.0f ? -1.0f : 1.0f;
  std::vector<Vertex> verts(mesh.positions.size());
  glm::vec3 centre(0.0f);
  for (size_t i = 0; i < verts.size(); ++i) {
    const glm::vec3 p = glm::vec3(inst.transform * glm::vec4(mesh.positions[i], 1.0f));
    const glm::vec3 n = nm * mesh.normals[i];
    const glm::vec3 t = m3 * glm::vec3(mesh.tangents[i]);
    const glm::vec2 uv = mesh.uvs.empty() ? glm::vec2(0.0f) : mesh.uvs[i];
    verts[i] = {{p.x, p.y, p.z},
                {n.x, n.y, n.z},
                {t.x, t.y, t.z, mesh.tangents[i].w * handed},
                {uv.x, uv.y}};
    centre += p / static_cast<float>(verts.size());
  }
  glCreateBuffers(1, &s.vbo);
  glNamedBufferStorage(s.vbo, static_cast<GLsizeiptr>(verts.size() * sizeof(Vertex)), verts.data(),
                       0);
  glCreateBuffers(1, &s.ibo);
  glNamedBufferStorage(s.ibo, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(uint32_t)),
                       mesh.indices.data(), 0);
  s.index_count = static_cast<GLsizei>(mesh.indices.size());
  glCreateVertexArrays(1, &s.vao);
  glVertexArrayVertexBuffer(s.vao, 0, s.vbo, 0, sizeof(Vertex));
  glVertexArrayElementBuffer(s.vao, s.ibo);
  const GLuint sizes[4] = {3, 3, 4, 2};
  const GLuint offsets[4] = {offsetof(Vertex, position), offsetof(Vertex, normal),
                             offsetof(Vertex, tangent), offsetof(Vertex, uv)};
  for (GLuint a = 0; a < 4; ++a) {
    glEnableVertexArrayAttrib(s.vao, a);
    glVertexArrayAttribFormat(s.vao, a, static_cast<GLint>(sizes[a]), GL_FLOAT, GL_FALSE,
                              offsets[a]);
    glVertexArrayAttribBinding(s.vao, a, 0);
  }

  // the relief texture, level 0 only, bilinear
  const Texture& depth = *depth_it->second;
  const std::vector<uint8_t> texels = relief_texels(depth, normal);
  glCreateTextures(GL_TEXTURE_2D, 1, &s.tex);
  glTextureStorage2D(s.tex, 1, GL_RGBA8, depth.width(0), depth.height(0));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(s.tex, 0, 0, 0, depth.width(0), depth.height(0), GL_RGBA, GL_UNSIGNED_BYTE,
                      texels.data());
  glCreateSamplers(1, &s.sampler);
  glSamplerParameteri(s.sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glSamplerParameteri(s.sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glSamplerParameteri(s.sampler, GL_TEXTURE_WRAP_S,
                      static_cast<GLint>(gl_detail::wrap_gl(mat.sampler.wrap_u)));
  glSamplerParameteri(s.sampler, GL_TEXTURE_WRAP_T,
                      static_cast<GLint>(gl_detail::wrap_gl(mat.sampler.wrap_v)));

  RELIEF_RETURN_IF_ERROR(make_target(s, width, height));

  // the programs and their uniforms
  Result<GLuint> p = build(linear_steps, binary_steps, false);
  if (!p.ok()) return p.status();
  s.program = *p;
  p = build(linear_steps, binary_steps, true);
  if (!p.ok()) return p.status();
  s.program_hits = *p;
  const Camera& cam = scene.cameras[0];
  const glm::mat4 view_proj =
      cam.projection(static_cast<float>(width) / static_cast<float>(height)) * cam.view();
  const Light& light = scene.lights[0];
  const glm::vec3 to_light =
      light.type == LightType::kDirectional ? -light.direction : light.position - centre;
  const glm::vec3 light_dir =
      glm::length(to_light) > 0.0f ? glm::normalize(to_light) : glm::vec3(0.0f, 1.0f, 0.0f);
  const float depth_scale = mat.params.count("depth_scale") ? mat.params.at("depth_scale") : 0.05f;
  for (GLuint prog : {s.program, s.program_hits}) {
    set_uniform(prog, "view_proj", view_proj);
    glProgramUniform4f(prog, glGetUniformLocation(prog, "uv_transform"), mat.uv_scale.x,
                       mat.uv_scale.y, mat.uv_offset.x, mat.uv_offset.y);
    set_uniform(prog, "eye", cam.position);
    set_uniform(prog, "view_dir", glm::normalize(cam.target - cam.position));
    glProgramUniform1i(prog, glGetUniformLocation(prog, "orthographic"), cam.orthographic ? 1 : 0);
    glProgramUniform1f(prog, glGetUniformLocation(prog, "depth"), depth_scale);
    set_uniform(prog, "light_dir", light_dir);
    set_uniform(prog, "ambient", scene.ambient);
    set_uniform(prog, "diffuse", glm::vec3(mat.base_color) * light.color * light.intensity);
  }
  s.cull = !mat.double_sided;
  s.background = scene.background;
  return gl_check("appendix shader: prepare");
}

namespace {

// Fixed state and one draw of `program` into the target (colour only, or colour and hits).
void draw_once(const AppendixRelief::State& s, GLuint program, bool hits) {
  glBindFramebuffer(GL_FRAMEBUFFER, s.fbo);
  const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0,
                             static_cast<GLenum>(hits ? GL_COLOR_ATTACHMENT1 : GL_NONE)};
  glNamedFramebufferDrawBuffers(s.fbo, 2, buffers);
  glViewport(0, 0, s.width, s.height);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  if (s.cull)
    glEnable(GL_CULL_FACE);
  else
    glDisable(GL_CULL_FACE);
  glFrontFace(GL_CCW);
  glCullFace(GL_BACK);
  glClearNamedFramebufferfv(s.fbo, GL_COLOR, 0, &s.background[0]);
  if (hits) {
    const float zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(s.fbo, GL_COLOR, 1, zero);
  }
  const float depth_clear = 0.0f;
  glClearNamedFramebufferfv(s.fbo, GL_DEPTH, 0, &depth_clear);
  glUseProgram(program);
  glBindTextureUnit(0, s.tex);
  glBindSampler(0, s.sampler);
  glBindVertexArray(s.vao);
  glDrawElements(GL_TRIANGLES, s.index_count, GL_UNSIGNED_INT, nullptr);
}

}  // namespace

Result<double> AppendixRelief::draw() {
  if (!s_->program) return Status::error("appendix shader: draw before prepare");
  RELIEF_RETURN_IF_ERROR(ctx_->make_current());
  const auto t = Clock::now();
  draw_once(*s_, s_->program, false);
  glFinish();
  const double ms = ms_since(t);
  RELIEF_RETURN_IF_ERROR(gl_check("appendix shader: draw"));
  return ms;
}

Status AppendixRelief::draw_hits(Image& color, Image& hits) {
  if (!s_->program_hits) return Status::error("appendix shader: draw before prepare");
  RELIEF_RETURN_IF_ERROR(ctx_->make_current());
  draw_once(*s_, s_->program_hits, true);
  color = Image(s_->width, s_->height);
  hits = Image(s_->width, s_->height);
  gl_detail::read_image(s_->fbo, GL_COLOR_ATTACHMENT0, color);
  gl_detail::read_image(s_->fbo, GL_COLOR_ATTACHMENT1, hits);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return gl_check("appendix shader: draw with hits");
}

}  // namespace relief::gl
