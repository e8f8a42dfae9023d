// The CPU pipeline's frame (rasterizer/pipeline.h): triangle setup and binning into tiles
// (rasterizer/setup.cpp, with the clipper in rasterizer/clip.cpp; in parallel over runs of
// vertices and segments of triangles), then the tiles in parallel, each cleared and traversed
// (rasterizer/raster_tile.cpp) by one thread.
#include "rasterizer/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <mutex>

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

  // Sets `draws` up for `fb`: the stats reset, the tile grid, the triangles binned (timed as
  // setup_ms).
  void begin(ThreadPool& pool, const Framebuffer& fb, std::span<const DrawCall> draws,
             int tile_size) {
    const auto t0 = std::chrono::steady_clock::now();
    stats = RasterStats{};
    CHECK(fb.width > 0 && fb.height > 0 && fb.width <= kMaxTargetSize &&
          fb.height <= kMaxTargetSize);
    tile = tile_size;
    tiles_x = (fb.width + tile - 1) / tile;
    tiles_y = (fb.height + tile - 1) / tile;
    setup.run(pool, draws, fb.width, fb.height, tile, tiles_x, tiles_y, stats);
    stats.tiles = static_cast<uint64_t>(tiles_x) * static_cast<uint64_t>(tiles_y);
    stats.setup_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }

  // Drawing on demand (prepare .. finish).
  Framebuffer* lazy_fb = nullptr;
  std::span<const DrawCall> lazy_draws;
  const ClearValues* lazy_clear = nullptr;
  std::unique_ptr<std::atomic<uint8_t>[]> state;  // per tile: kNotDrawn, kDrawing or kDrawn
  size_t state_size = 0;
  std::mutex lazy_mutex;                              // guards what follows
  std::vector<std::unique_ptr<Worker>> lazy_workers;  // every one made
  std::vector<Worker*> spare;                         // those no thread is drawing with
  double lazy_ms = 0.0;                               // thread time in draw_tile's draws
};

namespace {
constexpr uint8_t kNotDrawn = 0, kDrawn = 1, kDrawing = 2;
}  // namespace

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
  Impl& im = *impl_;
  im.begin(pool_, fb, draws, config_.tile_size);
  using Clock = std::chrono::steady_clock;
  const auto t1 = Clock::now();

  while (static_cast<int>(im.workers.size()) < pool_.size())
    im.workers.push_back(std::make_unique<Worker>());
  for (auto& w : im.workers) {
    w->counters = WorkCounters{};
    w->quads = 0;
  }
  const TileGrid grid = im.grid();
  im.stats.tiles_drawn = im.stats.tiles;
  pool_.run(im.tiles_x * im.tiles_y, [&](int tile, int worker) {
    raster_tile(grid, *im.workers[worker], fb, draws, tile, clear);
  });
  for (auto& w : im.workers) {
    im.stats.work += w->counters;
    im.stats.quads += w->quads;
  }
  const auto t2 = Clock::now();
  im.stats.raster_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
  return im.stats;
}

void Rasterizer::prepare(Framebuffer& fb, std::span<const DrawCall> draws,
                         const ClearValues* clear) {
  Impl& im = *impl_;
  im.begin(pool_, fb, draws, config_.tile_size);
  const size_t tiles = static_cast<size_t>(im.tiles_x) * static_cast<size_t>(im.tiles_y);
  if (im.state_size < tiles) {
    im.state = std::make_unique<std::atomic<uint8_t>[]>(tiles);
    im.state_size = tiles;
  }
  for (size_t t = 0; t < tiles; ++t) im.state[t].store(kNotDrawn, std::memory_order_relaxed);
  im.lazy_fb = &fb;
  im.lazy_draws = draws;
  im.lazy_clear = clear;
  im.spare.clear();
  for (auto& w : im.lazy_workers) {
    w->counters = WorkCounters{};
    w->quads = 0;
    im.spare.push_back(w.get());
  }
  im.lazy_ms = 0.0;
}

void Rasterizer::draw_tile(int tile) {
  Impl& im = *impl_;
  CHECK(im.lazy_fb && tile >= 0 && tile < im.tiles_x * im.tiles_y);
  std::atomic<uint8_t>& state = im.state[static_cast<size_t>(tile)];
  uint8_t seen = kNotDrawn;
  if (!state.compare_exchange_strong(seen, kDrawing, std::memory_order_acquire)) {
    // drawn, or being drawn by another thread: wait for its release
    while (seen != kDrawn) {
      state.wait(seen, std::memory_order_acquire);
      seen = state.load(std::memory_order_acquire);
    }
    return;
  }
  Worker* w;
  {
    std::lock_guard<std::mutex> lock(im.lazy_mutex);
    if (im.spare.empty()) {
      im.lazy_workers.push_back(std::make_unique<Worker>());
      im.spare.push_back(im.lazy_workers.back().get());
    }
    w = im.spare.back();
    im.spare.pop_back();
  }
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  raster_tile(im.grid(), *w, *im.lazy_fb, im.lazy_draws, tile, im.lazy_clear);
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  {
    std::lock_guard<std::mutex> lock(im.lazy_mutex);
    im.spare.push_back(w);
    im.lazy_ms += ms;
  }
  state.store(kDrawn, std::memory_order_release);
  state.notify_all();
}

const std::atomic<uint8_t>* Rasterizer::drawn() const {
  return impl_->state.get();
}
int Rasterizer::tiles_x() const {
  return impl_->tiles_x;
}
int Rasterizer::tiles_y() const {
  return impl_->tiles_y;
}

RasterStats Rasterizer::finish() {
  Impl& im = *impl_;
  std::lock_guard<std::mutex> lock(im.lazy_mutex);
  for (auto& w : im.lazy_workers) {
    im.stats.work += w->counters;
    im.stats.quads += w->quads;
  }
  im.stats.raster_ms = im.lazy_ms;
  im.stats.tiles_drawn = 0;
  for (uint64_t t = 0; t < im.stats.tiles; ++t)
    im.stats.tiles_drawn += im.state[t].load(std::memory_order_relaxed) == kDrawn;
  im.lazy_fb = nullptr;
  return im.stats;
}

void transform_positions(const glm::mat4& mvp, std::span<const glm::vec3> positions,
                         std::vector<glm::vec4>& clip) {
  clip.resize(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) clip[i] = mvp * glm::vec4(positions[i], 1.0f);
}

}  // namespace relief
