// Shared by the GL tests: one context per test program, or the reason there is none.
#pragma once

#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "gl/context.h"

namespace relief::gl::testing {

// The process's context (created once). Null when no EGL display can be created at all; then
// *why says why and the test skips.
inline Context* shared_context(std::string* why) {
  static std::string reason;
  static std::unique_ptr<Context> ctx = [] {
    Result<std::unique_ptr<Context>> c = Context::create(-1);
    if (!c.ok()) {
      reason = c.status().message();
      return std::unique_ptr<Context>();
    }
    return std::move(*c);
  }();
  if (why) *why = reason;
  if (ctx) {
    EXPECT_TRUE(ctx->make_current().ok());
  }
  return ctx.get();
}

}  // namespace relief::gl::testing

// Skips the test (printing why) when no EGL display can be created at all.
#define RELIEF_REQUIRE_GL()                                          \
  do {                                                               \
    std::string relief_why_;                                         \
    if (!::relief::gl::testing::shared_context(&relief_why_))        \
      GTEST_SKIP() << "no OpenGL through EGL here: " << relief_why_; \
  } while (0)
