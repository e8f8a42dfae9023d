// The fragment-stage ABI between the rasterizer and shader plugins (DESIGN.md, "The fragment-shader
// plugin ABI"). The rasterizer hands a shader packets of up to kPacketQuads 2x2 quads of one
// triangle, in structure-of-arrays form. Lane l of quad q is index q*4 + l, with l = 0 (x, y),
// 1 (x+1, y), 2 (x, y+1), 3 (x+1, y+1): dFdx = v[q*4+1] - v[q*4+0], dFdy = v[q*4+2] - v[q*4+0]
// (coarse derivatives, as GL permits). Lanes outside the triangle are helper lanes: their
// varyings are extrapolated so derivatives exist, and their outputs are ignored.
#pragma once

#include <cstdint>

#include "rasterizer/image.h"

namespace relief {

inline constexpr int kQuadLanes = 4;
inline constexpr int kPacketQuads = 16;
inline constexpr int kPacketLanes = kPacketQuads * kQuadLanes;
inline constexpr int kMaxVaryings = 32;

struct alignas(64) FragmentPacket {
  int num_quads = 0;
  int num_varyings = 0;
  bool front_facing = true;        // gl_FrontFacing, one triangle per packet
  uint8_t coverage[kPacketQuads];  // bit l set: lane l of the quad is inside the triangle
  float frag_x[kPacketLanes];      // gl_FragCoord.x (pixel centre, x + 0.5), origin top-left
  float frag_y[kPacketLanes];      // gl_FragCoord.y (pixel centre), rows top to bottom
  float frag_z[kPacketLanes];      // polygon depth, reversed-Z [0, 1]
  float inv_w[kPacketLanes];       // gl_FragCoord.w = 1 / w_clip
  float varyings[kMaxVaryings][kPacketLanes];  // perspective-correct

  bool lane_covered(int lane) const { return (coverage[lane >> 2] >> (lane & 3)) & 1; }
};

// What a shader writes. `discard` bits mark killed lanes; depth is read only when the draw's
// shader declares a depth output.
struct alignas(64) FragmentOutput {
  float color[4][kPacketLanes];
  float depth[kPacketLanes];
  uint8_t discard[kPacketQuads];  // bit l set: lane l discarded
  float aov[kAovTotalChannels][kPacketLanes];
};

// Work a shader did, per thread; the frame sums them. Counted for covered lanes only.
struct WorkCounters {
  uint64_t fragments = 0;        // covered fragments shaded
  uint64_t texture_fetches = 0;  // sample calls (one bilinear sample = one fetch)
  uint64_t search_steps = 0;     // intersection-search iterations
  uint64_t shadow_steps = 0;     // self-shadow ray iterations
  uint64_t discarded = 0;        // covered fragments discarded
  WorkCounters& operator+=(const WorkCounters& o) {
    fragments += o.fragments;
    texture_fetches += o.texture_fetches;
    search_steps += o.search_steps;
    shadow_steps += o.shadow_steps;
    discarded += o.discarded;
    return *this;
  }
};

}  // namespace relief
