// Built-in scenes, generated in code (`relief scenes` lists them).
#pragma once

#include <string>
#include <vector>

#include "base/status.h"
#include "scene/scene.h"

namespace relief {

struct BuiltinSceneInfo {
  std::string name;
  std::string description;
};

const std::vector<BuiltinSceneInfo>& builtin_scenes();
// The scene `make demo` renders when none is named.
const char* default_scene_name();
Result<Scene> make_builtin_scene(const std::string& name);

// The depth map of the `pattern` scene, one tile of size x size texels (size a multiple of 16;
// the scene uses kPatternSize): R8, linear, 0 at the reference surface and 1 deepest, with an
// average mip chain, periodic (the scene samples it with repeat wrap). Four quadrants separated
// by one-texel walls (depth 0) at x, y = 0 and size / 2: smooth (a spherical dome on sine
// swells), sharp (a pyramid and a cone), thin (a grid of one-texel walls every 8 texels and
// one-texel pillars over a floor at depth 1) and terraces (eight sharp steps crossed by
// one-texel diagonal walls). Like figure 6 of Policarpo et al. 2005 and figure 18-1 of
// Policarpo and Oliveira 2007 (GPU Gems 3, relaxed cone stepping): features a linear search
// with too few steps misses.
inline constexpr int kPatternSize = 256;
Texture make_pattern_depth(int size);

// Level 0 of `t`'s first channel as a texture of the same format without mips (a depth map a
// search can only read at full resolution).
TexturePtr texture_level0(const Texture& t);

}  // namespace relief
