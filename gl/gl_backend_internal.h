// Internal to gl/gl_*.cpp (not installed, cmake/install.cmake): the GlBackend class behind
// make_gl_backend (gl/gl_backend.h, which describes what the backend does) and what its parts
// share. Each part is defined in the file of its kind:
//   gl_backend.cpp    the frame's steps (GlBackend::render) and the backend's lifetime
//   gl_programs.cpp   the twins' variants: compile, link, cache, uniform locations and values
//   gl_resources.cpp  textures, samplers, max-mips, vertex and triangle-plane buffers, the target
//   gl_passes.cpp     drawing: the shadow passes and the main pass
//   gl_readback.cpp   reading the target (colour, AOVs, depth) and the work counters back
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <epoxy/gl.h>

#include "base/status.h"
#include "gl/context.h"
#include "gl/gl_layout_internal.h"
#include "render/render.h"

namespace relief::gl_detail {

using Clock = std::chrono::steady_clock;
inline double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// First pending GL error as a Status (and drains the rest).
Status gl_check(const char* where);
// A sampler axis's wrap mode as GL's (GL_REPEAT, GL_CLAMP_TO_EDGE, GL_MIRRORED_REPEAT).
GLenum wrap_gl(Wrap w);
// Reads an RGBA colour attachment of `fbo` into `img` (its size), rows flipped so that row 0 is
// the top; non-finite values read as 0.
void read_image(GLuint fbo, GLenum attachment, Image& img);

// Uniform locations of one program (-1 where the compiler removed the uniform).
struct Locations {
  GLint view = -1, view_proj = -1, eye = -1, orthographic = -1, view_dir = -1, ambient = -1;
  GLint num_lights = -1, width = -1, height = -1;
  GLint has_environment = -1, env_sh = -1, env_rotation = -1, env_intensity = -1, env_max_lod = -1;
  struct Light {
    GLint type = -1, position = -1, direction = -1, color = -1, range = -1, inner = -1, outer = -1;
  } lights[kMaxLights];
  GLint params = -1, base_color = -1, specular = -1, shininess = -1, has_texture = -1;
  GLint alpha_mode = -1, alpha_cutoff = -1;
  GLint texture_sampler = -1;  // cone.glsl: (filter, wrap_u, wrap_v) per slot, for texelFetch
  GLint tri_base = -1;         // common.glsl: the draw's first triangle in TrianglePlanesBuffer
  GLint clip_from_input = -1, snap_like_cpu = -1;  // relief.vert: the interpolation mode
};

struct Program {
  GLuint id = 0;
  Locations loc;
  bool height_field = false;  // reads HeightFieldBuffer (the exact twin)
};

// One variant of a plugin's twin.
struct Variant {
  std::string plugin;
  EffectMask effects = 0;
  DepthOutput depth_output = DepthOutput::kNone;
  bool aovs = false;
  bool count = false;
  // A MASK material's, which discards, so it cannot take early fragment tests.
  bool alpha_test = false;
};

// The programs of one frame, per material: the main pass's variant and the shadow passes' (null
// where the material is not drawn in them), and the programs built in this frame.
struct FramePrograms {
  std::vector<const Program*> main, shadow;
  std::vector<const Program*> fresh;
};

// Sets a program's frame uniforms (FrameUniforms, lights included) and material uniforms
// (MaterialUniforms: plugin parameters, glTF material terms, texture samplers).
void set_frame_uniforms(const Program& p, const FrameUniforms& f);
void set_material_uniforms(const Program& p, const MaterialUniforms& m);

// Texture units, storage-block bindings and buffer layouts shared with the GLSL twins.
using namespace gl_layout;  // NOLINT: this folder's own names

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

// The textures and max-mip buffers uploaded for this frame only (nothing keeps their texture's
// address alive, so nothing caches them): deleted with the frame, on every return path.
struct FrameTransients {
  std::vector<GLuint> textures, buffers;
  FrameTransients() = default;
  FrameTransients(const FrameTransients&) = delete;
  FrameTransients& operator=(const FrameTransients&) = delete;
  ~FrameTransients();
};

// A draw range in the uploaded vertex and index buffers.
struct DrawRange {
  int material;
  GLsizei count;
  size_t index_offset;
  GLint base_vertex;
  GLint first_triangle;  // index of its first triangle in the TrianglePlanesBuffer (-1: none)
  GLuint vao;            // the vertex array holding it
};

// One instance's world-space vertices on the GPU (GlInterpolation::kGpu), kept across frames
// while a frame draws them: positions (vec4), varyings (kGlVaryings a vertex) and indices.
struct CachedGeometry {
  GLuint vao = 0, buffers[3] = {0, 0, 0};
  GLsizei count = 0;  // indices
  bool used = false;  // drawn by the current frame
};

// What a frame draws from: the CPU's prepared instances (kCpuPlanes), or each scene instance's
// cached geometry (kGpu; null where it has nothing to draw).
struct FrameGeometry {
  PreparedFrame prep;                         // kCpuPlanes
  std::vector<const CachedGeometry*> cached;  // kGpu, per scene instance
  std::vector<int> materials;                 // per scene instance
};

// The vertex stream: every draw's varyings padded to kGlVaryings floats (relief.vert's six vec4;
// colour 1 and uv1 0 where the mesh has none).
constexpr int kGlVaryings = (varying::kCountExtended + 3) / 4 * 4;  // the prelude's kCountGl
static_assert(varying::kCountExtended <= kGlVaryings);

// Appends `vertices` vertices of num_varyings floats each, padded to kGlVaryings as the vertex
// stream holds them.
void append_padded_varyings(const float* varyings, int num_varyings, size_t vertices,
                            std::vector<float>& out);

// The texture and sampler objects per material and slot, and the exact twin's max-mip buffer.
struct DrawTextures {
  std::vector<std::array<GLuint, kMaxTextureSlots>> tex, samplers;
  // per material: emissive, occlusion and metallic-roughness textures, each with its sampler
  std::vector<std::array<GLuint, 6>> extra;
  std::vector<GLuint> fields;
  // The frame's environment (FrameUniforms::environment): specular chain and split-sum table
  // with their samplers; 0 without one.
  GLuint env_specular = 0, env_brdf = 0, env_specular_sampler = 0, env_brdf_sampler = 0;
};

// An environment's maps as uploaded, cached per EnvironmentMaps while something else holds it.
struct CachedEnvironment {
  std::shared_ptr<const EnvironmentMaps> owner;  // keeps the address from being reused
  GLuint ids[2] = {0, 0};                        // specular chain, split-sum table (0: empty)
};

// What a pass has bound: the material whose uniforms each program holds, and whether its frame
// uniforms are the pass's.
struct BindCache {
  std::map<GLuint, int> material_of;
};

// Binds a program and its material for a draw (bind_material and what the pass adds to it).
using BindFn = std::function<void(const Program&, int)>;

class GlBackend final : public Backend {
 public:
  GlBackend(std::unique_ptr<gl::Context> ctx, const BackendConfig& config)
      : ctx_(std::move(ctx)),
        count_work_(config.count_work),
        interpolation_(config.gl_interpolation) {}
  ~GlBackend() override;
  std::string name() const override { return "gl"; }
  Result<RenderResult> render(const Scene& scene, const Plan& plan) override;

 private:
  // --- programs (gl_programs.cpp)
  // The program of a plugin's twin ("depth_only" for casters without a shadow-pass variant).
  Result<const Program*> program_for(const Variant& v, double* compile_ms);
  // Sets *slot to v's program, noting it in frame.fresh when this call built it.
  Status use_program(const Variant& v, const Program** slot, FramePrograms& frame,
                     double* compile_ms);
  // Programs: the main pass's variant of every drawn material and, when there are shadow passes,
  // the casters' shadow-pass variant (or depth only). The first frame of a variant compiles it.
  Status select_programs(const Scene& scene, const Plan& plan, FramePrograms& frame,
                         double* compile_ms);
  Status select_main_programs(const Scene& scene, const Plan& plan, bool aovs, bool count,
                              FramePrograms& frame, double* compile_ms);
  Status select_shadow_programs(const Plan& plan, bool count, FramePrograms& frame,
                                double* compile_ms);

  // --- resources (gl_resources.cpp)
  // Drops cached textures and max-mips nobody else holds any more.
  void drop_unowned_textures();
  // Uploads the textures (cached while the scene holds them) of every material drawn this frame.
  Status upload_textures(const Plan& plan, const FramePrograms& programs,
                         FrameTransients& transients, DrawTextures& textures);
  Status upload_material_textures(const BoundMaterial& m, size_t mi, const FramePrograms& programs,
                                  FrameTransients& transients, DrawTextures& textures);
  // Uploads the draws `keep` accepts (plus one degenerate warm-up triangle at the end).
  // Also uploads each triangle's CPU interpolation planes for a width x height target.
  std::vector<DrawRange> upload_draws(const std::vector<PreparedDraw>& prepared,
                                      const std::vector<const Program*>& programs, int width,
                                      int height, size_t* warmup_offset);
  // --- geometry (gl_geometry.cpp)
  // The frame's geometry (GlInterpolation): prepares (kCpuPlanes) or finds and uploads (kGpu)
  // every instance; counts into result.geometry_reused and geometry_prepared.
  Status frame_geometry(const Scene& scene, const Plan& plan, FrameGeometry& geometry,
                        RenderResult& result);
  // The ranges drawing `instances` (scene instance indices, in draw order) from one view of a
  // width x height target, with a degenerate warm-up triangle at *warmup_offset of vao_.
  std::vector<DrawRange> view_ranges(const FrameGeometry& geometry,
                                     const std::vector<int>& instances,
                                     const std::vector<const Program*>& programs,
                                     const glm::mat4& view_proj, int width, int height,
                                     size_t* warmup_offset);
  // Deletes the cached geometry no frame drew since the last call, and clears the marks.
  void drop_unused_geometry();
  Result<GLuint> height_field_for(const BoundMaterial& m, std::vector<GLuint>& transient_buffers);
  GLuint texture_for(const Texture* t, const BoundMaterial& m, Upload upload,
                     std::vector<GLuint>& transient);
  // The frame's environment maps (FrameUniforms::environment) into textures: cached per
  // EnvironmentMaps while the plan's owner (Plan::environment) or anyone else holds it, for this
  // frame only when the plan does not own it; nothing without an environment.
  void upload_environment(const Plan& plan, FrameTransients& transients, DrawTextures& textures);
  GLuint sampler_for(const SamplerState& s);
  // The work counters' buffer (count) and the vertex array, its buffers and the timer query:
  // made on first use and kept.
  void ensure_counters();
  void ensure_vertex_array();
  // Points vao's attributes at a position buffer (vec4), a varying buffer (kGlVaryings floats a
  // vertex) and an index buffer.
  static void format_vertex_array(GLuint vao, GLuint position, GLuint varyings, GLuint indices);
  Status ensure_target(int w, int h, bool aovs);
  void release_target();
  // The depth array texture of a light's shadow map, (re)made when its size or faces change.
  GLuint shadow_texture(int light, const ShadowPassSetup& s);

  // --- passes (gl_passes.cpp)
  // Shadow passes (plan order), then the receivers' view of each map.
  Status shadow_passes(const FrameGeometry& geometry, const Plan& plan,
                       const FramePrograms& programs, const DrawTextures& textures, bool count,
                       RenderResult& result);
  // Renders the faces of one shadow pass into the layers of its depth texture.
  Status shadow_pass(const FrameGeometry& geometry, const Plan& plan, const PassPlan& pass,
                     const FramePrograms& programs, const DrawTextures& textures, bool count,
                     RenderResult& result);
  // One face of a shadow pass: its casters into layer `face` of `depth`.
  Status shadow_face(const FrameGeometry& geometry, const Plan& plan, const PassPlan& pass,
                     int face, GLuint depth, const FramePrograms& programs,
                     const DrawTextures& textures, bool count, PassStats& stats,
                     double* compile_ms);
  // Uploads the receivers' ShadowMapView of each light and binds the maps drawn this frame.
  void bind_shadow_maps(const std::vector<float>& views);
  // The main pass: the plan's draws into the target, in Plan::draw_order.
  Status main_pass(const Scene& scene, const Plan& plan, const FrameGeometry& geometry,
                   const FramePrograms& programs, const DrawTextures& textures,
                   RenderResult& result);
  // Sets a program's frame and material uniforms, textures and state for material mi.
  void bind_material(const Program& p, int mi, const Plan& plan, const FrameUniforms& frame,
                     const DrawTextures& textures, BindCache& cache);
  // Zeroes the work counters and binds them (count) before a pass; read_counters sums them after.
  void reset_counters();
  // Ends a pass timed from t_pass with the TIME_ELAPSED query begun for it.
  void end_pass(PassStats& stats, Clock::time_point t_pass);

  // --- readback (gl_readback.cpp)
  // Reads colour, AOVs and depth of the target into fb (fb's size), flipping rows.
  Status read_back(Framebuffer& fb);
  Status read_counters(WorkCounters& work);

  std::unique_ptr<gl::Context> ctx_;
  bool count_work_ = false;                                // BackendConfig::count_work
  GlInterpolation interpolation_ = GlInterpolation::kGpu;  // BackendConfig::gl_interpolation
  std::map<uint64_t, CachedGeometry> geometry_;  // by the hash of what an instance prepares from
  double geometry_ms_ = 0.0;  // this frame's geometry time inside the passes (kCpuPlanes)
  std::map<std::string, Program> programs_;
  std::map<std::pair<const Texture*, Upload>, CachedTexture> textures_;
  std::map<HeightFieldKey, CachedTexture> height_fields_;
  std::map<const EnvironmentMaps*, CachedEnvironment> environments_;
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

}  // namespace relief::gl_detail
