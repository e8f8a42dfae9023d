#include "gl/context.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include "gl/gl_backend.h"
#include "tests/gl/gl_test_util.h"

namespace relief::gl {
namespace {

TEST(Context, CreatesCore45Surfaceless) {
  RELIEF_REQUIRE_GL();
  Context* ctx = testing::shared_context(nullptr);
  const ContextInfo& info = ctx->info();
  EXPECT_FALSE(info.renderer.empty());
  EXPECT_FALSE(info.vendor.empty());
  EXPECT_NE(info.version.find("4."), std::string::npos) << info.version;
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_GE(major * 10 + minor, 45);
  EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
  // No default framebuffer: the context was made current without a surface.
  GLint fbo = -1;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fbo);
  EXPECT_EQ(fbo, 0);
  std::printf("[ info     ] %s: %s | %s | %s\n", info.platform.c_str(), info.renderer.c_str(),
              info.vendor.c_str(), info.version.c_str());
}

TEST(Context, ClipControlAndFloatTargetsWork) {
  RELIEF_REQUIRE_GL();
  // One clear of an RGBA32F + D32F FBO read back: what the backend relies on.
  GLuint fbo = 0, tex[2] = {0, 0};
  glCreateFramebuffers(1, &fbo);
  glCreateTextures(GL_TEXTURE_2D, 2, tex);
  glTextureStorage2D(tex[0], 1, GL_RGBA32F, 4, 4);
  glTextureStorage2D(tex[1], 1, GL_DEPTH_COMPONENT32F, 4, 4);
  glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex[0], 0);
  glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, tex[1], 0);
  ASSERT_EQ(glCheckNamedFramebufferStatus(fbo, GL_DRAW_FRAMEBUFFER),
            GLenum(GL_FRAMEBUFFER_COMPLETE));
  const float c[4] = {2.5f, -1.0f, 0.25f, 1.0f};
  glClearNamedFramebufferfv(fbo, GL_COLOR, 0, c);
  const float d = 0.0f;
  glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &d);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  float px[4] = {};
  glReadPixels(1, 1, 1, 1, GL_RGBA, GL_FLOAT, px);
  EXPECT_EQ(px[0], 2.5f);  // float target: not clamped
  EXPECT_EQ(px[1], -1.0f);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
  glDeleteTextures(2, tex);
  glDeleteFramebuffers(1, &fbo);
}

TEST(Context, MissingDeviceIsOneLineError) {
  // Needs no working driver: an index no machine has fails cleanly either way.
  Result<std::unique_ptr<Context>> c = Context::create(100000);
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.status().message().rfind("no EGL display", 0), 0u) << c.status().message();
  EXPECT_EQ(c.status().message().find('\n'), std::string::npos);
  Result<std::unique_ptr<Backend>> b = make_gl_backend({.gpu = 100000});
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.status().exit_code(), 1);
}

TEST(Context, ListsDevicesOrSaysWhy) {
  Result<std::vector<EglDevice>> d = list_egl_devices();
  if (!d.ok()) {
    EXPECT_FALSE(d.status().message().empty());
    return;
  }
  for (size_t i = 0; i < d->size(); ++i) {
    EXPECT_EQ((*d)[i].index, static_cast<int>(i));
    EXPECT_FALSE((*d)[i].name.empty());
  }
}

TEST(Context, TwoContextsCoexist) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Context>> a = Context::create(-1);
  Result<std::unique_ptr<Context>> b = Context::create(-1);
  ASSERT_TRUE(a.ok()) << a.status().message();
  ASSERT_TRUE(b.ok()) << b.status().message();
  ASSERT_TRUE((*a)->make_current().ok());
  b.value().reset();  // destroying one must not break the other (shared EGLDisplay)
  ASSERT_TRUE((*a)->make_current().ok());
  GLuint buf = 0;
  glCreateBuffers(1, &buf);
  EXPECT_NE(buf, 0u);
  glDeleteBuffers(1, &buf);
  a.value().reset();
  EXPECT_NE(testing::shared_context(nullptr), nullptr);
}

}  // namespace
}  // namespace relief::gl
