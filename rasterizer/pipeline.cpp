// The CPU pipeline's frame (rasterizer/pipeline.h): triangle setup and binning into tiles
// (rasterizer/setup.cpp, with the clipper in rasterizer/clip.cpp; in parallel over runs of
// vertices and segments of triangles), then the tiles in parallel, each cleared and traversed
// (rasterizer/raster_tile.cpp) by one thread.
#include "rasterizer/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "base/check.h"
#include "base/simd.h"
#include "rasterizer/raster_tile.h"
#include "rasterizer/setup_internal.h"

namespace relief {

using namespace raster_detail;

struct Rasterizer::Impl {
  // Frame state, reused between frames so steady state does not allocate.
  FrameSetup setup;  // setup triangles, their attribute planes, binned by tile
  std::vector<std::unique_ptr<Worker>> workers;
  RasterStats stats;
  int tiles_x = 0, tiles_y = 0, tile = 64;

  TileGrid grid() const { return {setup.runs, tile, tiles_x}; }
};

Rasterizer::Rasterizer(ThreadPool& pool, RasterConfig config)
    : pool_(pool), config_(config), impl_(std::make_unique<Impl>()) {
  // Links base/simd.cpp, whose start-up code applies RELIEF_SIMD, into every program that draws:
  // the draws dispatch on the level it sets.
  (void)simd_level();
  CHECK(config_.tile_size >= 8 && config_.tile_size <= 512 && config_.tile_size % 2 == 0);
}

Rasterizer::~Rasterizer() = default;

RasterStats Rasterizer::draw(Framebuffer& fb, std::span<const DrawCall> draws,
                             const ClearValues* clear) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  Impl& im = *impl_;
  im.stats = RasterStats{};
  CHECK(fb.width > 0 && fb.height > 0 && fb.width <= kMaxTargetSize && fb.height <= kMaxTargetSize);
  im.tile = config_.tile_size;
  im.tiles_x = (fb.width + im.tile - 1) / im.tile;
  im.tiles_y = (fb.height + im.tile - 1) / im.tile;
  im.setup.run(pool_, draws, fb.width, fb.height, im.tile, im.tiles_x, im.tiles_y, im.stats);
  const auto t1 = Clock::now();

  while (static_cast<int>(im.workers.size()) < pool_.size())
    im.workers.push_back(std::make_unique<Worker>());
  for (auto& w : im.workers) {
    w->counters = WorkCounters{};
    w->quads = 0;
  }
  const TileGrid grid = im.grid();
  pool_.run(im.tiles_x * im.tiles_y, [&](int tile, int worker) {
    raster_tile(grid, *im.workers[worker], fb, draws, tile, clear);
  });
  for (auto& w : im.workers) {
    im.stats.work += w->counters;
    im.stats.quads += w->quads;
  }
  const auto t2 = Clock::now();
  im.stats.setup_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  im.stats.raster_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
  return im.stats;
}

void transform_positions(const glm::mat4& mvp, std::span<const glm::vec3> positions,
                         std::vector<glm::vec4>& clip) {
  clip.resize(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) clip[i] = mvp * glm::vec4(positions[i], 1.0f);
}

}  // namespace relief
