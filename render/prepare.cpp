// The prepare stage shared by both backends (render/render.h): world-space varyings in the standard
// layout and plugin state, once per frame; clip positions per view.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string_view>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "base/hash.h"
#include "render/render.h"

namespace relief {

namespace {

// Replaces d's single surface by `layers` shells (PluginDescriptor::layers): copy k, drawn k-th,
// is shell i = layers-1-k of height fraction h = i/layers, outermost first so that the depth test
// rejects the inner shells behind opaque outer texels. The polygon is the level of the tallest
// tips (depth 0), so shell i lies (1 - h) relief heights below it along the unit world normal; it
// carries (i, layers) in the quadric slot, which shell techniques never read as a quadric.
void make_shells(PreparedInstance& d, const std::vector<uint32_t>& indices, int layers,
                 float depth_scale) {
  const size_t n = d.world.size();
  const int nv = d.num_varyings;
  const std::vector<glm::vec4> world = std::move(d.world);
  const std::vector<float> varyings = std::move(d.varyings);
  d.world.resize(n * layers);
  d.varyings.resize(varyings.size() * layers);
  auto shell_indices = std::make_shared<std::vector<uint32_t>>();
  shell_indices->reserve(indices.size() * layers);
  for (int k = 0; k < layers; ++k) {
    const int i = layers - 1 - k;
    const float below = 1.0f - static_cast<float>(i) / static_cast<float>(layers);
    for (size_t v = 0; v < n; ++v) {
      const float* src = &varyings[v * nv];
      float* o = &d.varyings[(k * n + v) * nv];
      std::copy(src, src + nv, o);
      const glm::vec3 nrm(src[varying::kNormal], src[varying::kNormal + 1],
                          src[varying::kNormal + 2]);
      const float len = glm::length(nrm);
      // relief_world_height (plugins/relief_shell.h) at the vertex's tile scale
      const float height =
          depth_scale * (src[varying::kTileScale] + src[varying::kTileScale + 1]) * 0.5f;
      const glm::vec3 unit = len > 0.0f && std::isfinite(len) ? nrm / len : glm::vec3(0.0f);
      const glm::vec3 offset = unit * (-below * height);
      const glm::vec4 wp = world[v] + glm::vec4(offset, 0.0f);
      d.world[k * n + v] = wp;
      for (int c = 0; c < 3; ++c) o[varying::kPosition + c] = wp[c];
      o[varying::kQuadric] = static_cast<float>(i);
      o[varying::kQuadric + 1] = static_cast<float>(layers);
    }
    const uint32_t base = static_cast<uint32_t>(k * n);
    for (uint32_t index : indices) shell_indices->push_back(base + index);
  }
  d.layers = layers;
  d.layer_indices = std::move(shell_indices);
  d.indices = d.layer_indices.get();
}

}  // namespace

MaterialLayers material_layers(const BoundMaterial& material) {
  constexpr int kMaxLayers = 256;
  const PluginDescriptor* plugin = material.plugin;
  MaterialLayers out;
  if (!plugin || !plugin->layers) return out;
  out.layers = std::clamp(plugin->layers(material.uniforms.params), 1, kMaxLayers);
  for (int p = 0; p < plugin->num_params; ++p)
    if (std::string_view(plugin->params[p].name) == "depth_scale")
      out.depth_scale = material.uniforms.params[p];
  return out;
}

PreparedInstance prepare_instance(const Scene& scene, size_t i,
                                  std::span<const MaterialLayers> layers) {
  const Instance& inst = scene.instances[i];
  const Mesh& mesh = scene.meshes[inst.mesh];
  const Material& mat = scene.materials[inst.material];
  PreparedInstance d;
  d.instance = static_cast<int>(i);
  d.material = inst.material;
  d.indices = &mesh.indices;
  const size_t n = mesh.positions.size();
  // COLOR_0 and TEXCOORD_1 travel only for meshes that have them (varying::kCountExtended).
  const bool extended = !mesh.colors.empty() || !mesh.uvs1.empty();
  const int nv = extended ? varying::kCountExtended : varying::kCount;
  d.num_varyings = nv;
  d.world.resize(n);
  d.varyings.resize(n * nv);
  const glm::mat4 model = inst.transform;
  const glm::mat3 linear(model);
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
  const float handedness = glm::determinant(linear) < 0.0f ? -1.0f : 1.0f;
  for (size_t v = 0; v < n; ++v) {
    const glm::vec4 wp = model * glm::vec4(mesh.positions[v], 1.0f);
    d.world[v] = wp;
    float* o = &d.varyings[v * nv];
    const glm::vec3 nrm =
        v < mesh.normals.size() ? normal_matrix * mesh.normals[v] : glm::vec3(0, 0, 1);
    const glm::vec4 t = v < mesh.tangents.size() ? mesh.tangents[v] : glm::vec4(1, 0, 0, 1);
    const glm::vec3 wt = linear * glm::vec3(t);
    const glm::vec2 uv =
        v < mesh.uvs.size() ? mesh.uvs[v] * mat.uv_scale + mat.uv_offset : glm::vec2(0);
    glm::vec2 ts = v < mesh.tile_scale.size() ? mesh.tile_scale[v] : glm::vec2(1);
    // World units per (tiled) uv unit along T and B.
    ts = ts / glm::max(glm::abs(mat.uv_scale), glm::vec2(1e-12f));
    // Object to world: scale by how much the model matrix stretches T and B.
    const glm::vec3 on = v < mesh.normals.size() ? mesh.normals[v] : glm::vec3(0, 0, 1);
    const glm::vec3 ob = glm::cross(on, glm::vec3(t));
    const float wt_len = glm::length(wt), wb_len = glm::length(linear * ob);
    ts *= glm::vec2(wt_len, wb_len);
    // The quadric z = a x^2 + b y^2 (x, y along T and B, z along -N) is fitted in object units.
    // In world units x and y stretch as T and B do, z as the distance between tangent planes
    // (1 / |N^-T n| for a unit n), so a' = a * sz / sx^2. Exact for uniform scales and for
    // scales along T, B and N; identity transforms leave the coefficients bit for bit.
    glm::vec2 q = v < mesh.quadric.size() ? mesh.quadric[v] : glm::vec2(0);
    if (v < mesh.quadric.size() && v < mesh.normals.size()) {
      const float sx = wt_len / glm::length(glm::vec3(t));
      const float sy = wb_len / glm::length(ob);
      const float sz = glm::length(on) / glm::length(nrm);
      if (sx > 0.0f && sy > 0.0f && std::isfinite(sz))
        q *= glm::vec2(sz / (sx * sx), sz / (sy * sy));
    }
    const float vals[varying::kCount] = {
        wp.x, wp.y, wp.z, nrm.x, nrm.y, nrm.z, wt.x, wt.y, wt.z, t.w * handedness,
        uv.x, uv.y, q.x,  q.y,   ts.x,  ts.y};
    for (int k = 0; k < varying::kCount; ++k) o[k] = vals[k];
    if (extended) {
      const glm::vec4 c = v < mesh.colors.size() ? mesh.colors[v] : glm::vec4(1.0f);
      const glm::vec2 uv1 = v < mesh.uvs1.size() ? mesh.uvs1[v] : glm::vec2(0.0f);
      const float ext[] = {c.r, c.g, c.b, c.a, uv1.x, uv1.y};
      for (int k = 0; k < varying::kCountExtended - varying::kCount; ++k)
        o[varying::kCount + k] = ext[k];
    }
  }
  if (static_cast<size_t>(inst.material) < layers.size() && layers[inst.material].layers > 0)
    make_shells(d, mesh.indices, layers[inst.material].layers, layers[inst.material].depth_scale);
  return d;
}

std::vector<MaterialLayers> plan_layers(const Plan& plan) {
  std::vector<MaterialLayers> layers(plan.materials.size());
  for (size_t m = 0; m < plan.materials.size(); ++m) layers[m] = material_layers(plan.materials[m]);
  return layers;
}

std::vector<PreparedInstance> prepare_instances(const Scene& scene,
                                                std::span<const MaterialLayers> layers) {
  std::vector<PreparedInstance> out;
  out.reserve(scene.instances.size());
  for (size_t i = 0; i < scene.instances.size(); ++i)
    out.push_back(prepare_instance(scene, i, layers));
  return out;
}

uint64_t instance_key(const Scene& scene, size_t i, std::span<const MaterialLayers> layers) {
  const Instance& inst = scene.instances[i];
  const Mesh& m = scene.meshes[inst.mesh];
  const Material& mat = scene.materials[inst.material];
  Hash64 h;
  h.elements(m.positions);
  h.elements(m.normals);
  h.elements(m.uvs);
  h.elements(m.uvs1);
  h.elements(m.colors);
  h.elements(m.tangents);
  h.elements(m.quadric);
  h.elements(m.tile_scale);
  h.elements(m.indices);
  h.value(inst.transform);
  h.value(mat.uv_scale);
  h.value(mat.uv_offset);
  const MaterialLayers shells =
      static_cast<size_t>(inst.material) < layers.size() ? layers[inst.material] : MaterialLayers{};
  h.value(shells.layers);
  h.value(shells.depth_scale);
  return h.digest();
}

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// The frame's instances, each taken from `cache` when it holds the instance's key.
std::vector<PreparedInstance> cached_instances(const Scene& scene,
                                               const std::vector<MaterialLayers>& layers,
                                               PreparedCache& cache, std::vector<uint64_t>& keys) {
  const auto t0 = Clock::now();
  keys.resize(scene.instances.size());
  for (size_t i = 0; i < scene.instances.size(); ++i) keys[i] = instance_key(scene, i, layers);
  cache.key_ms = ms_since(t0);
  cache.reused = cache.prepared = 0;
  std::vector<PreparedInstance> out;
  out.reserve(scene.instances.size());
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    auto node = cache.kept.extract(keys[i]);
    if (node.empty()) {
      out.push_back(prepare_instance(scene, i, layers));
      ++cache.prepared;
      continue;
    }
    PreparedInstance d = std::move(node.mapped());
    const Instance& inst = scene.instances[i];
    d.instance = static_cast<int>(i);
    d.material = inst.material;
    if (!d.layer_indices) d.indices = &scene.meshes[inst.mesh].indices;  // this scene's copy
    out.push_back(std::move(d));
    ++cache.reused;
  }
  return out;
}

}  // namespace

void keep_prepared(PreparedFrame&& frame, PreparedCache& cache) {
  cache.kept.clear();
  if (frame.keys.size() != frame.instances.size()) return;
  for (size_t i = 0; i < frame.instances.size(); ++i)
    cache.kept.insert_or_assign(frame.keys[i], std::move(frame.instances[i]));
}

PreparedFrame prepare_frame(const Scene& scene, const Plan& plan, PreparedCache* cache) {
  const auto t0 = Clock::now();
  PreparedFrame frame;
  if (cache)
    frame.instances = cached_instances(scene, plan_layers(plan), *cache, frame.keys);
  else
    frame.instances = prepare_instances(scene, plan_layers(plan));
  frame.states.resize(plan.materials.size());
  for (size_t m = 0; m < plan.materials.size(); ++m) {
    const PluginDescriptor* plugin = plan.materials[m].plugin;
    if (!plugin || !plugin->create_state) continue;
    void* state = plugin->create_state(plan.materials[m].uniforms);
    void (*destroy)(void*) = plugin->destroy_state;
    if (state)
      frame.states[m] = std::shared_ptr<void>(state, [destroy](void* s) {
        if (destroy) destroy(s);
      });
  }
  frame.ms = ms_since(t0);
  return frame;
}

PreparedDraw view_draw(const PreparedInstance& instance, const glm::mat4& view_proj) {
  PreparedDraw d;
  d.instance = instance.instance;
  d.material = instance.material;
  d.clip.resize(instance.world.size());
  for (size_t v = 0; v < instance.world.size(); ++v) d.clip[v] = view_proj * instance.world[v];
  d.varyings = instance.varyings;
  d.num_varyings = instance.num_varyings;
  d.indices = instance.indices;
  return d;
}

std::vector<PreparedDraw> view_draws(const PreparedFrame& frame, const glm::mat4& view_proj) {
  std::vector<PreparedDraw> out;
  out.reserve(frame.instances.size());
  for (const PreparedInstance& instance : frame.instances)
    out.push_back(view_draw(instance, view_proj));
  return out;
}

}  // namespace relief
