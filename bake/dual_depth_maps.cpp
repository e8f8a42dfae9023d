// Dual-depth relief textures baked with our rasterizer (Policarpo, Oliveira and Comba, I3D 2005,
// section 3.1): two orthographic passes along -z with the GREATER depth test, the first keeping the
// nearest surface, the second (depth mirrored) the farthest; the shader writes the interpolated
// normal as colour.
#include "bake/dual_depth_maps.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "rasterizer/pipeline.h"

namespace relief {
namespace {

// Colour = the normalised normal varying (0, 0, 1 where it has no length).
void normal_shader(const void*, const FragmentPacket& in, FragmentOutput& out, WorkCounters&) {
  for (int l = 0; l < in.num_quads * kQuadLanes; ++l) {
    glm::vec3 n(in.varyings[0][l], in.varyings[1][l], in.varyings[2][l]);
    const float len = glm::length(n);
    n = len > 1e-20f && std::isfinite(len) ? n / len : glm::vec3(0.0f, 0.0f, 1.0f);
    for (int c = 0; c < 3; ++c) out.color[c][l] = n[c];
    out.color[3][l] = 1.0f;
  }
}

}  // namespace

DualDepthMaps bake_dual_depth(std::span<const glm::vec3> positions,
                              std::span<const glm::vec3> normals, std::span<const uint32_t> indices,
                              int size, float grow, int threads) {
  DualDepthMaps maps;
  maps.size = size;
  const size_t n = static_cast<size_t>(size) * size;
  maps.front.assign(n, 1.0f);
  maps.back.assign(n, 0.0f);
  maps.front_normal.assign(n, glm::vec3(0.0f, 0.0f, 1.0f));
  maps.back_normal.assign(n, glm::vec3(0.0f, 0.0f, 1.0f));
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (positions.empty() || indices.empty()) {
    maps.box_min = glm::vec3(-0.5f);
    maps.box_max = glm::vec3(0.5f);
    return maps;
  }
  const glm::vec3 c = (lo + hi) * 0.5f;
  const float half = std::max({hi.x - lo.x, hi.y - lo.y, 1e-6f}) * 0.5f * std::max(grow, 1.0f);
  // a sliver of room above and below so the extreme points are not clipped by near and far
  const float pad = std::max(hi.z - lo.z, 1e-6f) * 1e-4f;
  maps.box_min = glm::vec3(c.x - half, c.y - half, lo.z - pad);
  maps.box_max = glm::vec3(c.x + half, c.y + half, hi.z + pad);
  const float range = maps.box_max.z - maps.box_min.z;

  std::vector<float> varyings(positions.size() * 3);
  for (size_t i = 0; i < positions.size(); ++i)
    for (int k = 0; k < 3; ++k)
      varyings[i * 3 + k] = i < normals.size() ? normals[i][k] : (k == 2 ? 1.0f : 0.0f);
  ThreadPool pool(threads);
  Rasterizer raster(pool);
  for (int pass = 0; pass < 2; ++pass) {
    // clip z = 1 - depth (front: the largest is the nearest) or depth (back: the deepest)
    std::vector<glm::vec4> clip(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
      const glm::vec3& p = positions[i];
      const float depth = (maps.box_max.z - p.z) / range;
      clip[i] =
          glm::vec4((p.x - c.x) / half, (p.y - c.y) / half, pass == 0 ? 1.0f - depth : depth, 1.0f);
    }
    DrawCall dc;
    dc.clip = clip;
    dc.varyings = varyings;
    dc.num_varyings = 3;
    dc.indices = indices;
    dc.cull = CullMode::kNone;
    dc.shader = &normal_shader;
    Framebuffer fb(size, size);
    const ClearValues clear{glm::vec4(0.0f, 0.0f, 1.0f, 0.0f), 0.0f};
    raster.draw(fb, std::span<const DrawCall>(&dc, 1), &clear);
    for (int r = 0; r < size; ++r)
      for (int x = 0; x < size; ++x) {
        const float z = fb.depth.at(x, r);
        if (!(z > 0.0f)) continue;                                      // absent
        const size_t t = static_cast<size_t>(size - 1 - r) * size + x;  // row 0 of the map: v = 0
        const glm::vec4 col = fb.color.at(x, r);
        if (pass == 0) {
          maps.front[t] = 1.0f - z;
          maps.front_normal[t] = glm::vec3(col);
        } else {
          maps.back[t] = z;
          maps.back_normal[t] = glm::vec3(col);
        }
      }
  }
  return maps;
}

}  // namespace relief
