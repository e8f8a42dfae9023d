// The GL backend's read back (gl/gl_backend_internal.h): the target's colour, AOVs and depth into
// a Framebuffer, and the work counters into WorkCounters.
#include <cmath>
#include <cstdint>
#include <vector>

#include <epoxy/gl.h>

#include "gl/gl_backend_internal.h"

namespace relief::gl_detail {
namespace {

float finite(float v) {
  return std::isfinite(v) ? v : 0.0f;
}

// Reads one RGBA32F attachment of `fbo` into buf (GL's rows: row 0 is the bottom).
void read_rgba(GLuint fbo, GLenum attachment, int w, int h, std::vector<float>& buf) {
  glNamedFramebufferReadBuffer(fbo, attachment);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, buf.data());
}

// Row y of the Image (row 0 the top) in a buffer read back from GL (row 0 the bottom).
const float* flipped_row(const std::vector<float>& buf, int y, int w, int h, int channels) {
  return &buf[static_cast<size_t>(h - 1 - y) * w * channels];
}

void copy_color(const std::vector<float>& buf, Image& img) {
  const int w = img.width, h = img.height;
  for (int y = 0; y < h; ++y) {
    const float* row = flipped_row(buf, y, w, h, 4);
    for (int x = 0; x < w; ++x)
      img.at(x, y) = glm::vec4(finite(row[x * 4]), finite(row[x * 4 + 1]), finite(row[x * 4 + 2]),
                               finite(row[x * 4 + 3]));
  }
}

// AOV target a (0 or 1) holds the AOV channels 4a .. 4a + 3.
void copy_aovs(const std::vector<float>& buf, int a, Framebuffer& fb) {
  const int w = fb.width, h = fb.height;
  for (int y = 0; y < h; ++y) {
    const float* row = flipped_row(buf, y, w, h, 4);
    for (int x = 0; x < w; ++x) {
      float* dst = fb.aov_at(x, y);
      for (int c = 0; c < 4 && a * 4 + c < kAovTotalChannels; ++c)
        dst[a * 4 + c] = finite(row[x * 4 + c]);
    }
  }
}

void read_depth(Framebuffer& fb) {
  const int w = fb.width, h = fb.height;
  std::vector<float> dbuf(static_cast<size_t>(w) * h);
  glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, dbuf.data());
  for (int y = 0; y < h; ++y) {
    const float* row = flipped_row(dbuf, y, w, h, 1);
    for (int x = 0; x < w; ++x) fb.depth.at(x, y) = finite(row[x]);
  }
}

}  // namespace

void read_image(GLuint fbo, GLenum attachment, Image& img) {
  std::vector<float> buf(static_cast<size_t>(img.width) * img.height * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  read_rgba(fbo, attachment, img.width, img.height, buf);
  copy_color(buf, img);
}

Status GlBackend::read_back(Framebuffer& fb) {
  // Read back, flipping rows: GL's row 0 is the bottom, the Image's the top.
  const int w = fb.width, h = fb.height;
  std::vector<float> buf(static_cast<size_t>(w) * h * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  read_rgba(fbo_, GL_COLOR_ATTACHMENT0, w, h, buf);
  copy_color(buf, fb.color);
  if (fb.aov_mask != 0) {
    for (int a = 0; a < 2; ++a) {
      read_rgba(fbo_, GL_COLOR_ATTACHMENT1 + a, w, h, buf);
      copy_aovs(buf, a, fb);
    }
  }
  glNamedFramebufferReadBuffer(fbo_, GL_COLOR_ATTACHMENT0);
  read_depth(fb);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return gl_check("read back");
}

Status GlBackend::read_counters(WorkCounters& work) {
  // The slots of common.glsl's WorkCountersBuffer, summed into the CPU's WorkCounters.
  std::vector<uint32_t> c(kCounterSlots * kCounterCount);
  glGetNamedBufferSubData(counters_, 0, static_cast<GLsizeiptr>(c.size() * sizeof(uint32_t)),
                          c.data());
  uint64_t sum[kCounterCount] = {};
  for (int slot = 0; slot < kCounterSlots; ++slot)
    for (int k = 0; k < kCounterCount; ++k) sum[k] += c[slot * kCounterCount + k];
  work.fragments = sum[kCounterFragments];
  work.texture_fetches = sum[kCounterFetches];
  work.search_steps = sum[kCounterSearchSteps];
  work.shadow_steps = sum[kCounterShadowSteps];
  work.discarded = sum[kCounterDiscarded];
  return gl_check("work counters");
}

}  // namespace relief::gl_detail
