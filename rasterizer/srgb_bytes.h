// The 8-bit sRGB encoding of linear colour, as .png output (scene/image_io.cpp) and the sRGB
// textures' levels (rasterizer/texture.cpp: from_floats, generate_mips) store it: encode_srgb8
// (rasterizer/texture.h, the definition: lround(255 * srgb(clamp(c, 0, 1))), srgb the IEC
// 61966-2-1 curve in double) through tables instead of a pow a channel.
#pragma once

#include <cstdint>

namespace relief {

// encode_srgb8(c) for every float c, by table: for each byte k from 1 to 255 the smallest float
// whose byte is k (found by bisection over the float bit patterns with encode_srgb8), and the
// byte at the first float of each run of 2^16 float bit patterns in [0, 1]. A value's byte is
// its run's byte, raised past every threshold it reaches (a run spans less than one byte). Equal
// to the definition for all 2^30 floats in [0, 1] (tests/rasterizer/srgb_bytes_test.cpp checks
// every one), and both clamp outside it.
uint8_t srgb_byte(float c);

}  // namespace relief
