// Shared by the CPU/GL agreement tests (tests/gl_frames/agreement_test.cpp says why these bounds):
// the metric, sRGB-encoded RGB PSNR >= kMinPsnr with at most kMaxOverFraction of the pixels off
// by more than kThreshold in a channel, and one GL backend per test program (its programs compile
// once, its cached textures upload once). The agreement tests run the GL backend with the CPU's
// planes (GlInterpolation::kCpuPlanes), so both backends shade the same numbers;
// tests/gl_frames/gl_geometry_test.cpp holds the default, GL's own interpolation, to the metric.
#pragma once

#include <memory>

#include <gtest/gtest.h>

#include "gl/gl_backend.h"

namespace relief::gl::testing {

inline constexpr double kMinPsnr = 35.0;
inline constexpr double kMaxOverFraction = 0.005;
inline constexpr float kThreshold = 8.0f / 255.0f;

// The program's GL backend (null, with a test failure, when none can be made).
inline Backend* shared_gl_backend() {
  static std::unique_ptr<Backend> gl = [] {
    Result<std::unique_ptr<Backend>> b =
        make_gl_backend({.gl_interpolation = GlInterpolation::kCpuPlanes});
    EXPECT_TRUE(b.ok()) << b.status().message();
    return b.ok() ? std::move(*b) : nullptr;
  }();
  return gl.get();
}

}  // namespace relief::gl::testing
