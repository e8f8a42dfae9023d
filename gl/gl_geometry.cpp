// The GL backend's geometry (gl/gl_backend_internal.h, BackendConfig::gl_interpolation).
//
// kGpu (the default): each scene instance's world-space vertices, as prepare_instance makes them,
// live in GPU buffers across frames. A frame finds them by a hash of everything prepare_instance
// reads (the mesh's arrays, the instance's transform, the material's uv transform and shells), so
// an unchanged instance costs a hash (11 to 20 ms for the 100 MB of a 2 M-triangle mesh) instead
// of a prepare and an upload, and a posed mesh (skins, morphs) or a moved instance gets a new key
// and is uploaded again. The vertex stage transforms the positions by each pass's
// view-projection, and GL interpolates.
//
// kCpuPlanes: the prepare stage's instances, transformed per view on the CPU and uploaded each
// pass with the CPU rasterizer's planes of every triangle (gl_resources.cpp upload_draws).
#include <algorithm>
#include <cstdint>
#include <vector>

#include <epoxy/gl.h>

#include "gl/gl_backend_internal.h"

namespace relief::gl_detail {
namespace {

// The triangles of d whose three indices name a vertex: d's own indices when all do (a validated
// scene), else a copy without the others (written to `kept`).
const std::vector<uint32_t>& valid_indices(const PreparedInstance& d, std::vector<uint32_t>& kept) {
  const std::vector<uint32_t>& ix = *d.indices;
  const size_t whole = ix.size() / 3 * 3;
  const bool all = ix.size() == whole && std::all_of(ix.begin(), ix.end(), [&](uint32_t i) {
                     return i < d.world.size();
                   });
  if (all) return ix;
  for (size_t t = 0; t < whole; t += 3)
    if (std::max({ix[t], ix[t + 1], ix[t + 2]}) < d.world.size())
      kept.insert(kept.end(), {ix[t], ix[t + 1], ix[t + 2]});
  return kept;
}

template <class T>
void store(GLuint buffer, const std::vector<T>& data) {
  glNamedBufferStorage(buffer,
                       static_cast<GLsizeiptr>(std::max<size_t>(data.size(), 1) * sizeof(T)),
                       data.empty() ? nullptr : data.data(), 0);
}

}  // namespace

Status GlBackend::frame_geometry(const Scene& scene, const Plan& plan, FrameGeometry& geometry,
                                 RenderResult& result) {
  geometry.materials.clear();
  for (const Instance& inst : scene.instances) geometry.materials.push_back(inst.material);
  if (interpolation_ == GlInterpolation::kCpuPlanes) {
    geometry.prep = prepare_frame(scene, plan);
    result.prepare_ms = geometry.prep.ms;
    return {};
  }
  const auto t0 = Clock::now();
  // The warm-up triangle (gl_passes.cpp warm_up) alone in vao_'s streams, at index 0: nothing
  // else is streamed in this mode, so once a frame serves every pass.
  size_t warmup_offset = 0;
  upload_draws({}, {}, 0, 0, &warmup_offset);
  double prepare_ms = 0.0;
  const std::vector<MaterialLayers> layers = plan_layers(plan);
  geometry.cached.assign(scene.instances.size(), nullptr);
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const uint64_t key = instance_key(scene, i, layers);
    auto [it, fresh] = geometry_.try_emplace(key);
    CachedGeometry& g = it->second;
    if (fresh) {
      const auto t_prep = Clock::now();
      const PreparedInstance d = prepare_instance(scene, i, layers);
      std::vector<float> varyings;
      append_padded_varyings(d.varyings.data(), d.num_varyings, d.world.size(), varyings);
      std::vector<uint32_t> kept;
      const std::vector<uint32_t>& indices = valid_indices(d, kept);
      prepare_ms += ms_since(t_prep);
      glCreateVertexArrays(1, &g.vao);
      glCreateBuffers(3, g.buffers);
      store(g.buffers[0], d.world);
      store(g.buffers[1], varyings);
      store(g.buffers[2], indices);
      format_vertex_array(g.vao, g.buffers[0], g.buffers[1], g.buffers[2]);
      g.count = static_cast<GLsizei>(indices.size());
      ++result.geometry_prepared;
    } else if (!g.used) {
      ++result.geometry_reused;
    }
    g.used = true;
    if (g.count > 0) geometry.cached[i] = &g;
  }
  glFinish();  // the uploads' cost lands here, not in the first pass that reads them
  result.prepare_ms = prepare_ms;
  result.geometry_ms = ms_since(t0) - prepare_ms;
  Status uploaded = gl_check("geometry upload");
  if (!uploaded.ok()) {  // an upload failed (out of memory): keep nothing that may be partial
    geometry.cached.assign(scene.instances.size(), nullptr);
    for (auto& [key, g] : geometry_) {
      glDeleteVertexArrays(1, &g.vao);
      glDeleteBuffers(3, g.buffers);
    }
    geometry_.clear();
  }
  return uploaded;
}

std::vector<DrawRange> GlBackend::view_ranges(const FrameGeometry& geometry,
                                              const std::vector<int>& instances,
                                              const std::vector<const Program*>& programs,
                                              const glm::mat4& view_proj, int width, int height,
                                              size_t* warmup_offset) {
  const auto t0 = Clock::now();
  std::vector<DrawRange> ranges;
  if (interpolation_ == GlInterpolation::kCpuPlanes) {
    std::vector<PreparedDraw> draws;
    draws.reserve(instances.size());
    for (int i : instances) draws.push_back(view_draw(geometry.prep.instances[i], view_proj));
    ranges = upload_draws(draws, programs, width, height, warmup_offset);
  } else {
    *warmup_offset = 0;  // streamed once a frame by frame_geometry
    for (int i : instances) {
      const CachedGeometry* g = geometry.cached[i];
      const int material = geometry.materials[i];
      if (g && programs[material]) ranges.push_back({material, g->count, 0, 0, -1, g->vao});
    }
  }
  geometry_ms_ += ms_since(t0);
  return ranges;
}

void GlBackend::drop_unused_geometry() {
  for (auto it = geometry_.begin(); it != geometry_.end();) {
    if (it->second.used) {
      it->second.used = false;
      ++it;
      continue;
    }
    glDeleteVertexArrays(1, &it->second.vao);
    glDeleteBuffers(3, it->second.buffers);
    it = geometry_.erase(it);
  }
}

}  // namespace relief::gl_detail
