// The built-in `bending` scene: a relief-mapped cylinder bent by two joints over time, the test
// of the relief paper's claim (Policarpo, Oliveira and Comba 2005, section 1) that relief stays
// attached to an animated, deforming surface when its tangent frames deform with it.
#pragma once

#include "base/status.h"
#include "scene/scene.h"

namespace relief {

// A cylinder of radius 0.25 along +y from 0 to 2 (kBendRings rings of kBendSegments quads, plus
// caps) with the brick relief material of `plane`, skinned to two joints: `root` at the origin
// and `bend` at y = 1 (weights blend smoothly over 0.7 < y < 1.3). The animation `bend` turns the
// `bend` joint about z from 0 to 75 degrees and back over 2 seconds (LINEAR quaternion keys every
// 0.25 s, 48 frames at 24 fps). Frame 0 is the bind pose.
inline constexpr int kBendRings = 48, kBendSegments = 32;
inline constexpr double kBendPeriod = 2.0, kBendMaxDeg = 75.0;
Result<Scene> make_bending_scene();

}  // namespace relief
