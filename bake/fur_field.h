// Generated depth fields of short straight fur and of grass, for relief techniques that render
// them as a height field (McGuire and McGuire 2005, "Steep Parallax Mapping", section "Fur and
// Grass": short straight fur and grass as a dense field of tall strands, one polygon, no shells).
//
// Conventions (bake/normal_map.h, DESIGN.md): depth 0 at the reference surface, which is the level
// of the tallest strand tips, 1 deepest: the skin or the ground. Texel (x, y) is centred at
// (x + 0.5, y + 0.5) in texel units. Every distance wraps around (the field is periodic with
// period `size` on both axes), so the map tiles without a seam: a strand centred near one border
// shows on the opposite one too.
//
// Parameters (FurFieldOptions):
//   size     texels on a side (square; any size >= 1, 512 by default; at most 4096).
//   density  strands per 100 x 100 texels (10^4 texels) of the field, whatever its size: the field
//            holds lround(density * size^2 / 10^4) strands, centred uniformly at random. 0 gives
//            no strand: the whole field is ground at depth 1 in the ground colour.
//   radius   a strand's radius in texels (fur: the round strand's; grass: the blade's half width
//            at its root), in [0.5, 32]: thinner strands fall between texel centres.
//   jitter   in [0, 1]: each strand's tip height is full height times a uniform value in
//            [1 - jitter, 1], so its tip depth lies in [0, jitter]; 0 puts every tip at depth 0.
//   seed     any 64-bit value; the same options give bit-identical fields on every machine (an
//            own splitmix64 generator and plain IEEE arithmetic: +, *, /, sqrt; no std::
//            distributions, whose results the standard leaves to the library).
//
// Strands (where strands overlap, the higher surface wins: the texel keeps the smallest depth):
//   fur    a round strand whose top is rounded: height falls from its tip height at the centre to
//          70 % of it at the edge along a circular arc, then drops to the skin, so the normal map
//          tilts outward toward the edge like a cylinder's side.
//   grass  a blade: a tapered capsule along a random direction, 6 radii long, half width `radius`
//          at the root narrowing to a fifth of it at the tip; it rises from 70 % of its tip
//          height at the root to its tip height at the far end (a slight lean), with the same
//          rounded cross-section as fur.
//
// Colour (linear RGB per texel): a root-to-tip gradient by height (1 - depth), dark at the root,
// light at the tip; fur brownish grey (a per-strand mix toward grey and a brightness jitter),
// grass green with a slight per-blade hue shift; ground texels get the root colour.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "base/status.h"
#include "rasterizer/texture.h"

namespace relief {

enum class FurKind { kFur, kGrass };
const char* fur_kind_name(FurKind kind);

struct FurFieldOptions {
  FurKind kind = FurKind::kFur;
  int size = 512;
  float density = 800.0f;  // strands per 100 x 100 texels
  float radius = 1.5f;     // texels
  float jitter = 0.3f;     // tip heights in [1 - jitter, 1] of full height
  uint64_t seed = 1;
};

// The defaults of a kind: fur 800 strands per 10^4 texels of radius 1.5; grass 90 blades of
// radius 2. Both size 512, jitter 0.3 (fur) and 0.4 (grass), seed 1.
FurFieldOptions fur_field_defaults(FurKind kind);

// One strand as placed: centre (fur) or root (grass) in texels, unwrapped in [0, size); the
// blade's unit direction (grass; (1, 0) for fur); tip height in (0, 1]; tip colour (linear).
struct FurStrand {
  float x = 0.0f, y = 0.0f;
  float dir_x = 1.0f, dir_y = 0.0f;
  float height = 1.0f;
  glm::vec3 tip{1.0f};
};

struct FurField {
  int size = 0;
  std::vector<float> depth;      // size * size, row-major, in [0, 1]
  std::vector<glm::vec3> color;  // linear RGB, size * size
  std::vector<FurStrand> strands;
};

// OK, or a usage error naming the first bad option in one line ("fur field: --radius ...").
Status check_fur_field_options(const FurFieldOptions& o);
// The field of `o` (check_fur_field_options first; its error otherwise).
Result<FurField> make_fur_field(const FurFieldOptions& o);

// The depth as an R16 texture (16-bit, what a 16-bit grey PNG holds), linear, average mips.
Texture fur_depth_texture(const FurField& f);
// The colour as RGBA8 sRGB, alpha 1, average mips.
Texture fur_color_texture(const FurField& f);
// The tangent-space normal map of a field's depth texture (bake/normal_map.h, wrapping at the
// borders so it tiles like the field), for a material of this depth_scale.
Texture fur_normal_texture(const Texture& depth, float depth_scale);

}  // namespace relief
