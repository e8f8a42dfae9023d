// Test scenes whose depth maps are cut to level 0 (no mips): the searches then sample exactly the
// field `exact` intersects at every distance, so any difference is the search's alone.
#pragma once

#include <memory>
#include <vector>

#include "scene/scene.h"

namespace relief {

// The texture's level 0 alone, same format.
inline TexturePtr level0_only(const Texture& d) {
  std::vector<float> v(static_cast<size_t>(d.width(0)) * d.height(0));
  for (int y = 0; y < d.height(0); ++y)
    for (int x = 0; x < d.width(0); ++x)
      v[static_cast<size_t>(y) * d.width(0) + x] = d.fetch_r(0, x, y);
  return std::make_shared<Texture>(
      Texture::from_floats(d.format(), d.width(0), d.height(0), v.data()));
}

// `s` with every material's depth map cut to level 0.
inline Scene level0_depth(Scene s) {
  for (Material& m : s.materials) {
    const auto it = m.textures.find("depth");
    if (it != m.textures.end()) it->second = level0_only(*it->second);
  }
  return s;
}

}  // namespace relief
