// Planning and executing a frame (DESIGN.md, "One frame, as data", steps 3 to 5).
//
// make_plan() turns a Scene and RenderOptions into passes and, per instance, the plugin variant
// and bound material it draws with, keeping only the effects the scene calls for. A Backend
// executes a Plan: the CPU backend (render/cpu_backend.cpp) with the tile rasterizer and the C++
// plugins, the GL backend (gl/) with their GLSL twins. Both read the same prepared vertex data
// (prepare_frame), the same textures and the same uniforms, and return the same RenderResult.
#pragma once

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/status.h"
#include "plugins/plugin.h"
#include "rasterizer/image.h"
#include "rasterizer/pipeline.h"
#include "render/shadow_map.h"
#include "scene/scene.h"

namespace relief {

// What one frame asks for; make_plan() turns it into a Plan, which is all a backend reads.
struct RenderOptions {
  int width = 800;
  int height = 600;
  int camera = 0;         // index into Scene::cameras
  std::string technique;  // when set, replaces every relief material's technique
  std::map<std::string, std::string> params;  // key=value overrides of plugin parameters
  AovMask aovs = 0;
  bool scalar_lanes = false;  // run kernels one fragment at a time (reference path)
  // Effect switches over the whole scene (the scene's own choices still apply): shadow passes
  // (shadow maps) and self-shadow rays. Bias and filtering of the shadow-map lookups.
  bool shadows = true;
  bool self_shadow = true;
  ShadowSettings shadow;
  // How each shadow map's resolution is chosen (render/shadow_map.h ShadowSize): kLight, the
  // light's shadow_resolution; kView, at most that and no more than a texel per pixel of the view.
  ShadowSize shadow_size = ShadowSize::kLight;
  // CPU backend: each shadow map's tiles are drawn when the main pass's lookups first reach them
  // (docs/effects.md, "Shadow maps drawn on demand"); false draws every tile before the main pass.
  // The image is the same either way.
  bool shadow_on_demand = true;
  // Image-based light (docs/environment.md): the baked maps of an environment (`--env`; null:
  // none), named for --explain, turned and scaled by env_view. Without one, a scene that has no
  // lights is lit by the built-in studio environment when `studio_environment` is set (a glTF
  // file without lights renders lit), else by its ambient colour alone.
  std::shared_ptr<const EnvironmentMaps> environment;
  std::string environment_name;
  EnvironmentView env_view;
  bool studio_environment = true;
  // Height-field ambient occlusion over every relief material (those with a depth map): each
  // value set replaces the material's (`--height-ao`, `--height-ao-radius`,
  // `--height-ao-strength`).
  std::optional<int> height_ao_rays;
  std::optional<float> height_ao_radius, height_ao_strength;
};

// One material bound to its plugin: parameter values in schema order, textures by slot.
struct BoundMaterial {
  std::string name;  // Material::name
  const PluginDescriptor* plugin = nullptr;
  MaterialUniforms uniforms;
  EffectMask effects = 0;              // requested & supported
  std::vector<std::string> reasons;    // why each effect is on or off (for --explain)
  std::vector<TexturePtr> keep_alive;  // textures referenced by uniforms
  bool double_sided = false;
  // Shadow passes: whether the material's instances are drawn into them and with which variant
  // (kEffectShadowPass: intersection from the light and corrected depth; 0: polygon depth, no
  // shading).
  bool shadow_caster = false;
  EffectMask shadow_effects = 0;
};

struct PassPlan {
  enum class Kind { kShadow, kMain } kind = Kind::kMain;
  std::string name;
  std::string reason;
  int light = -1;              // shadow passes
  std::vector<int> instances;  // shadow passes: the casters drawn
  ShadowPassSetup shadow;      // shadow passes: the light's view
};

struct Plan {
  std::vector<BoundMaterial> materials;  // parallel to Scene::materials
  std::vector<PassPlan> passes;
  FrameUniforms frame;  // main-pass camera and lights
  // The image-based light frame.environment points into (null: none) and why (for --explain).
  std::shared_ptr<const EnvironmentMaps> environment;
  std::string environment_reason;
  ShadowSettings shadow;             // lookups of every shadow pass
  bool shadow_on_demand = true;      // RenderOptions::shadow_on_demand
  std::vector<std::string> skipped;  // passes not made, and why (for --explain)
  // The main pass's instances in draw order: the OPAQUE and MASK ones in submission order, then
  // the BLEND ones back to front by the view depth of their bounds' centre (ties: submission
  // order). Both backends draw in this order.
  std::vector<int> draw_order;
  std::string explain() const;  // human-readable plan, one line per decision
};

Result<Plan> make_plan(const Scene& scene, const RenderOptions& options);

// plan.draw_order when it covers the n prepared draws (a plan made for this scene), else the
// submission order 0..n-1 (a scene changed since it was planned).
inline std::vector<int> main_draw_order(const Plan& plan, size_t n) {
  bool fits = plan.draw_order.size() == n;
  for (int i : plan.draw_order) fits = fits && i >= 0 && static_cast<size_t>(i) < n;
  if (fits) return plan.draw_order;
  std::vector<int> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = static_cast<int>(i);
  return order;
}

// The colour a frame's target is cleared to: the scene's background, alpha clamped to [0, 1],
// premultiplied (targets hold premultiplied linear colour; docs/aovs.md, "Output alpha").
inline glm::vec4 clear_color(const Scene& scene) {
  const float a = scene.background.a >= 0.0f ? std::min(scene.background.a, 1.0f) : 0.0f;
  return glm::vec4(glm::vec3(scene.background) * a, a);
}

// The prepare stage (DESIGN.md, "One frame, as data", step 2): what every pass of a frame reads,
// made once at the start of the frame by whichever backend runs it. The world-space vertex data
// of every instance does not depend on the view, so the main pass and every shadow-map face share
// it and each pass transforms only the positions it draws to clip space (view_draw); the plugin
// state of each bound material (PluginDescriptor::create_state) is made once too. Cross-frame
// reuse: both backends keep each instance's prepared vertices between frames, keyed by a hash of
// what prepare_instance reads (instance_key): the CPU backend in a PreparedCache, the GL
// backend's default mode on the GPU (gl/gl_geometry.cpp).

// World-space vertex data of one instance, in the standard varying layout (plugins/plugin.h).
struct PreparedInstance {
  int instance = 0;
  int material = 0;
  std::vector<glm::vec4> world;        // model * (position, 1) per vertex
  std::vector<float> varyings;         // num_varyings per vertex
  int num_varyings = varying::kCount;  // kCountExtended when the mesh has COLOR_0 or TEXCOORD_1
  const std::vector<uint32_t>* indices = nullptr;
  // A layered material (PluginDescriptor::layers): the number of shell copies in world and
  // varyings (0: not layered), and their indices, which `indices` then points at (held on the
  // heap, so that moving the instance keeps the pointer valid).
  int layers = 0;
  std::shared_ptr<const std::vector<uint32_t>> layer_indices;
};
// How the prepare stage draws one material: `layers` offset shells of the surface (0: the plain
// surface), spread over the relief height of its `depth_scale` (uv units; plugins/relief_shell.h).
struct MaterialLayers {
  int layers = 0;
  float depth_scale = 0.0f;
};
// Every instance of the scene, in submission order; `layers` is parallel to Scene::materials
// (empty or shorter: plain surfaces).
std::vector<PreparedInstance> prepare_instances(const Scene& scene,
                                                std::span<const MaterialLayers> layers = {});
// Scene instance i alone, as prepare_instances makes it.
PreparedInstance prepare_instance(const Scene& scene, size_t i,
                                  std::span<const MaterialLayers> layers = {});
// A bound material's shells: its plugin's layers hook clamped to 1..256 (0 without a hook) and
// its `depth_scale` parameter (0 when the schema has none).
MaterialLayers material_layers(const BoundMaterial& material);
// material_layers of every material of the plan, parallel to Plan::materials.
std::vector<MaterialLayers> plan_layers(const Plan& plan);

struct PreparedFrame {
  std::vector<PreparedInstance> instances;    // parallel to Scene::instances
  std::vector<uint64_t> keys;                 // instance_key of each (with a PreparedCache)
  std::vector<std::shared_ptr<void>> states;  // parallel to Plan::materials; null: no state
  double ms = 0.0;                            // wall time of prepare_frame
  const void* state(int material) const { return states[material].get(); }
};
// A hash (base/hash.h) of everything prepare_instance(scene, i, layers) reads: the mesh's arrays,
// the instance's transform, its material's uv transform and shells. Equal keys, equal instances.
uint64_t instance_key(const Scene& scene, size_t i, std::span<const MaterialLayers> layers);

// Prepared instances kept from one frame for the next, by instance_key (the CPU backend's):
// what the last frame prepared, and how many instances it found here or prepared anew.
struct PreparedCache {
  std::map<uint64_t, PreparedInstance> kept;
  int reused = 0, prepared = 0;
  double key_ms = 0.0;  // the last frame's hashing
};

// With a cache: each instance whose key the cache holds is taken from it (its index pointers
// set to this scene's), the rest are prepared; keep_prepared hands the frame's instances back.
PreparedFrame prepare_frame(const Scene& scene, const Plan& plan, PreparedCache* cache = nullptr);
// Puts a finished frame's instances into the cache, replacing what it held (so it holds one
// frame's geometry at most).
void keep_prepared(PreparedFrame&& frame, PreparedCache& cache);

// One instance seen from one view: its clip positions, and its prepared varyings (borrowed from
// the PreparedInstance, which must outlive it).
struct PreparedDraw {
  int instance = 0;
  int material = 0;
  std::vector<glm::vec4> clip;
  std::span<const float> varyings;  // num_varyings per vertex
  int num_varyings = varying::kCount;
  const std::vector<uint32_t>* indices = nullptr;
};
PreparedDraw view_draw(const PreparedInstance& instance, const glm::mat4& view_proj);
// Every prepared instance from one view, in submission order.
std::vector<PreparedDraw> view_draws(const PreparedFrame& frame, const glm::mat4& view_proj);

struct PassStats {
  std::string name;
  double ms = 0.0;
  RasterStats raster;    // CPU backend
  double gpu_ms = -1.0;  // GL backend: GL_TIME_ELAPSED of the pass (-1: not measured)
  PassPlan::Kind kind = PassPlan::Kind::kMain;
  int light = -1;      // shadow passes: index into Scene::lights
  int faces = 1;       // shadow passes: 6 for a point light's cube (raster counters summed)
  int resolution = 0;  // shadow passes: texels per side
};

// A shadow pass's stats before it runs: its name, kind, light, faces and resolution (both
// backends).
inline PassStats shadow_pass_stats(const PassPlan& pass) {
  PassStats stats;
  stats.name = pass.name;
  stats.kind = PassPlan::Kind::kShadow;
  stats.light = pass.light;
  stats.faces = pass.shadow.faces;
  stats.resolution = pass.shadow.size;
  return stats;
}

struct RenderResult {
  Framebuffer framebuffer;
  std::vector<PassStats> passes;
  double frame_ms = 0.0;
  std::string device;  // "cpu (N threads)" or the GL renderer string
  // Both backends, part of frame_ms: the prepare stage (prepare_frame: world-space vertices and
  // plugin state, once per frame).
  double prepare_ms = 0.0;
  // GL backend, parts of frame_ms: shader compile and link (non-zero on the first frame of a
  // variant, zero in steady state), texture and vertex uploads, and reading the images back.
  double compile_ms = 0.0;
  double upload_ms = 0.0;
  double readback_ms = 0.0;
  // Part of frame_ms: the frame's geometry. Both backends keep each instance's prepared
  // vertices between frames (the GL backend on the GPU, in its default GlInterpolation::kGpu)
  // and find them by a hash of its mesh, transform and material (instance_key): geometry_ms is
  // the hashing (and on GL the uploads), geometry_reused the instances found, geometry_prepared
  // those prepared anew (their prepare in prepare_ms). GL with the CPU's planes: every pass's
  // clip positions, planes and vertices, computed and uploaded (nothing kept).
  double geometry_ms = 0.0;
  int geometry_reused = 0, geometry_prepared = 0;
  // CPU backend, part of frame_ms: the main target made or recycled (its first frame of a size
  // allocates and clears it).
  double target_ms = 0.0;
};

// What frame_ms holds beyond the named parts (prepare, compile, upload, geometry, target, every
// pass, read-back): a few microseconds of bookkeeping when every stage is timed; --stats reports
// it as other_ms.
inline double unaccounted_ms(const RenderResult& r) {
  double parts =
      r.prepare_ms + r.compile_ms + r.upload_ms + r.readback_ms + r.geometry_ms + r.target_ms;
  for (const PassStats& p : r.passes) parts += p.ms;
  return r.frame_ms - parts;
}

// How the GL backend interpolates a triangle's varyings. kGpu: the GPU's own (perspective-correct)
// interpolation of world-space vertices kept on the GPU across frames; what a user renders with.
// kCpuPlanes: the CPU rasterizer's planes of every triangle, computed and uploaded each frame,
// so that both backends shade the same numbers (the agreement tests; ~1e-6 apart otherwise,
// which cone steps and relaxed-cone shadows turn into different hits).
enum class GlInterpolation { kGpu, kCpuPlanes };
// "gpu" or "cpu-planes" (the CLI's --gl-interpolation); a usage error names the flag otherwise.
inline Result<GlInterpolation> parse_gl_interpolation(const std::string& name) {
  if (name == "gpu") return GlInterpolation::kGpu;
  if (name == "cpu-planes") return GlInterpolation::kCpuPlanes;
  return Status::usage("--gl-interpolation: expected gpu or cpu-planes, got '" + name + "'");
}

// How a backend runs, fixed when it is made: what does not change from frame to frame.
struct BackendConfig {
  int threads = 0;     // CPU: worker threads, 0 = all cores
  int tile_size = 64;  // CPU: tile side in pixels (even, 8..512)
  int gpu = -1;        // GL: EGL device index, -1 = the first usable
  // GL: count the work counters (fetches, steps) with atomics; the CPU always counts.
  bool count_work = false;
  GlInterpolation gl_interpolation = GlInterpolation::kGpu;
};

// Executes a Plan. Everything a frame asks for (size, AOVs, passes, camera, shadow settings, the
// scalar reference path) is in the plan (Plan::frame, Plan::passes, Plan::shadow); the scene
// supplies the geometry and textures the plan names.
class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::string name() const = 0;
  virtual Result<RenderResult> render(const Scene& scene, const Plan& plan) = 0;
  // Hands a finished frame back once its images are no longer needed, so that the next render()
  // of the same size reuses its buffers instead of allocating and faulting them in again
  // (multi-frame renders, benchmarks). Optional; the default drops them.
  virtual void recycle(RenderResult&& done) {}
};

// The CPU backend keeps its thread pool between frames.
std::unique_ptr<Backend> make_cpu_backend(const BackendConfig& config = {});

}  // namespace relief
