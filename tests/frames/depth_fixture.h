// Test scenes whose depth maps are cut to level 0 (no mips): the searches then sample exactly the
// field `exact` intersects at every distance, so any difference is the search's alone.
#pragma once

#include "builtin/builtin.h"
#include "scene/scene.h"

namespace relief {

// `s` with every material's depth map cut to level 0.
inline Scene level0_depth(Scene s) {
  for (Material& m : s.materials) {
    const auto it = m.textures.find("depth");
    if (it != m.textures.end()) it->second = texture_level0(*it->second);
  }
  return s;
}

}  // namespace relief
