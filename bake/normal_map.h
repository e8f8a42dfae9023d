// Tangent-space normal maps from depth maps (Policarpo, Oliveira, Comba 2005, section 2: the relief
// texture stores the normal of the depth map's surface; here it is derived by central differences).
//
// Conventions (DESIGN.md): a depth map holds values in [0,1], 0 at the top reference surface and 1
// deepest; it spans uv [0,1]^2 with texel (i, j) centred at ((i + 0.5) / w, (j + 0.5) / h).
// `depth_scale` is the relief's depth in uv units, so depth d sits at P(u, v) = (u, v,
// -d * depth_scale). With T = dP/du (x, along +u), B = dP/dv (y, along +v) and N = T x B (z, out of
// the surface) the unnormalised normal is (depth_scale * dd/du, depth_scale * dd/dv, 1).
// dd/du, dd/dv come from central differences of level 0 at texel centres, in uv units
// ((d[i+1] - d[i-1]) * w / 2). At a border, `wrap` takes the neighbour from the opposite side
// (a tiling map); otherwise the missing neighbour is clamped and the difference is one-sided
// (divided by the real distance, one texel). A map one texel wide has zero slope along that axis.
//
// Stored components (NormalConvention): kGltf, the glTF 2.0 convention every normal map relief
// reads follows (plugins/surface.h normal_from_texel): red = x along +u, green = y toward the
// image top (-v; texel row 0 is the top row, at v = 0), blue = z; so green = -n_v. kDirectX stores
// green = +n_v (green toward the image bottom), for tools that expect that ("DirectX" or "Y-").
#pragma once

#include "rasterizer/texture.h"

namespace relief {

enum class NormalConvention { kGltf, kDirectX };

// RGBA8 linear: rgb = n * 0.5 + 0.5, alpha = 1, with a full mip chain (average). The depth is read
// from the first channel of level 0 (any format). Precondition: depth not empty.
Texture normal_map_from_depth(const Texture& depth, float depth_scale, bool wrap,
                              NormalConvention convention = NormalConvention::kGltf);

// The same normals unquantised: RGBA16F with rgb = n (components in [-1, 1]), alpha = 1, full mip
// chain (average; averaged normals are not renormalised).
Texture normal_map_from_depth_float(const Texture& depth, float depth_scale, bool wrap,
                                    NormalConvention convention = NormalConvention::kGltf);

}  // namespace relief
