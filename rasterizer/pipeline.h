// The CPU rasterization pipeline (DESIGN.md, "The CPU pipeline").
//
// Input: draws of indexed triangles whose vertices are already in homogeneous clip space
// (reversed-Z, GL_ZERO_TO_ONE: visible when 0 <= z <= w, z = w at the near plane), each vertex
// carrying num_varyings floats. The pipeline clips against near and far, clips against a guard
// band only when a triangle leaves it, maps to a viewport whose pixel (0, 0) is top-left, snaps to
// fixed point with 8 sub-pixel bits, culls by winding (counter-clockwise in NDC is front, like
// GL's default), bins triangles into square tiles, and lets a pool of threads take tiles by an
// atomic counter. One thread owns a tile for the whole pass and processes the tile's triangles in
// submission order, so the image does not depend on the thread count or the tile size.
// Fragments reach the draw's shader in packets of 2x2 quads (fragment.h); the depth test is
// GREATER against a float32 buffer cleared to 0.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "base/thread_pool.h"
#include "rasterizer/fragment.h"
#include "rasterizer/image.h"

namespace relief {

enum class CullMode : uint8_t { kNone, kBack, kFront };

// Where the depth test runs, from what the shader writes.
enum class DepthTest : uint8_t {
  kEarly,         // shader writes no depth: test the polygon depth before shading
  kConservative,  // shader depth is never closer than the polygon's: reject early with the
                  // polygon depth, test the shader depth late
  kLate,          // shader depth is arbitrary: test after shading only
};

// The packet shader: colour, optional depth, discards and AOVs for every lane of `in`.
using PacketShader = void (*)(const void* user, const FragmentPacket& in, FragmentOutput& out,
                              WorkCounters& counters);

struct DrawCall {
  // Per vertex: clip positions, or positions that `transform` takes to clip space (the setup
  // transforms them in parallel, into its own buffers: the CPU backend's world positions).
  std::span<const glm::vec4> clip;
  const glm::mat4* transform = nullptr;
  std::span<const float> varyings;    // per vertex, num_varyings each
  int num_varyings = 0;               // <= kMaxVaryings
  std::span<const uint32_t> indices;  // three per triangle
  CullMode cull = CullMode::kBack;
  DepthTest depth_test = DepthTest::kEarly;
  bool depth_write = true;
  bool color_write = true;
  bool aov_write = false;  // copy the shader's AOVs into the framebuffer
  // Composite the shader's colour (straight alpha) over the target's, which holds premultiplied
  // colour: rgb = src.rgb * a + dst.rgb * (1 - a), alpha = a + dst.a * (1 - a) (src-over, linear).
  // Fragments of a tile are composited in submission order, so the result is deterministic.
  bool blend = false;
  PacketShader shader = nullptr;
  const void* user = nullptr;  // passed to the shader
};

struct RasterConfig {
  int tile_size = 64;  // pixels, even, 8..512
};

struct RasterStats {
  uint64_t triangles_in = 0;
  uint64_t triangles_culled = 0;   // back-facing, zero-area, non-finite or outside the view
  uint64_t triangles_clipped = 0;  // went through the clipper
  uint64_t triangles_binned = 0;   // after clipping
  uint64_t quads = 0;              // quads with coverage handed to shaders
  uint64_t tiles = 0;              // tiles of the target
  uint64_t tiles_drawn = 0;        // tiles drawn (all by draw(); on demand, those asked for)
  WorkCounters work;               // summed over threads
  double setup_ms = 0.0;           // vertices, clip, setup, binning (parallel steps)
  double raster_ms = 0.0;          // parallel: traversal and shading
};

// Largest supported target, per axis. The guard band is +-kGuardBand pixels around the viewport;
// with 8 sub-pixel bits every edge-function term fits in 64-bit integers.
inline constexpr int kMaxTargetSize = 16384;
inline constexpr int kGuardBand = 32768;

// What a pass starts from. Given to Rasterizer::draw, each tile clears its own pixels (colour,
// depth and AOVs) just before drawing them: in parallel, and while they are in cache, instead of a
// serial pass over the whole target.
struct ClearValues {
  glm::vec4 color{0.0f};
  float depth = 0.0f;
};

// The attribute planes the CPU rasterizer interpolates one triangle with, for a backend that must
// interpolate exactly as it does (the GL backend evaluates them per pixel). The setup draws a
// triangle as it is, or clips it (near, far, guard band) into a fan: one part per triangle it
// sets up, each with its bounding box's first pixel (x0, y0), its corners in pixels (x, y; rows
// top to bottom) and (c, dx, dy) per plane: depth, 1/w, then each varying times 1/w. A pixel's
// value is ((c + dx fx) + dy fy), fx = px - x0, fy = py - y0, varyings divided by the 1/w
// plane's value. False when the setup draws nothing of it.
struct CpuTrianglePlanes {
  struct Part {
    int x0 = 0, y0 = 0;
    float corner[6] = {};
    std::vector<float> planes;
  };
  std::vector<Part> parts;
};
bool cpu_triangle_planes(const glm::vec4 clip[3], const float* const varyings[3], int num_varyings,
                         int width, int height, CpuTrianglePlanes& out);

class Rasterizer {
 public:
  Rasterizer(ThreadPool& pool, RasterConfig config = {});
  ~Rasterizer();
  // Renders `draws` in order into `fb`: cleared to `*clear` tile by tile when given, else as the
  // caller left it. Not re-entrant.
  RasterStats draw(Framebuffer& fb, std::span<const DrawCall> draws,
                   const ClearValues* clear = nullptr);
  const RasterConfig& config() const { return config_; }

  // Drawing on demand, for a target of which later readers need only part (the CPU backend's
  // shadow maps: the tiles the main pass's lookups reach). prepare() sets `draws` up for `fb` as
  // draw() does and draws nothing. draw_tile(t) then draws tile t (row by row, tiles of
  // config().tile_size) exactly as draw() would, cleared to `*clear` first when given: from any
  // thread, at most once; a second caller returns once the first has drawn it. drawn() holds 1
  // for each drawn tile (stored with release order). finish() returns the counters of the tiles
  // drawn, raster_ms being the thread time spent drawing them (summed over threads); `fb`, `draws`
  // and `clear` must live until then. Tiles never drawn keep what `fb` held. Not re-entrant with
  // draw() on the same Rasterizer.
  void prepare(Framebuffer& fb, std::span<const DrawCall> draws,
               const ClearValues* clear = nullptr);
  void draw_tile(int tile);
  const std::atomic<uint8_t>* drawn() const;
  int tiles_x() const;
  int tiles_y() const;
  RasterStats finish();

 private:
  struct Impl;
  ThreadPool& pool_;
  RasterConfig config_;
  std::unique_ptr<Impl> impl_;  // frame buffers reused between frames
};

// The vertex stage for position-only input: clip = mvp * (p, 1).
void transform_positions(const glm::mat4& mvp, std::span<const glm::vec3> positions,
                         std::vector<glm::vec4>& clip);

}  // namespace relief
