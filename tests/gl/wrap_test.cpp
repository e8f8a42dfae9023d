// gl/shaders/wrap.glsl against rasterizer/texture.h wrap_texel: the GLSL wrap that the cone
// twins' texelFetch reads use (division-free, branch-free) gives the CPU's texel for every wrap
// mode, for indices across the whole range scaled_coord can produce (|i| <= 2^26, and i + 1) and
// sizes from 1 texel to the mirror period of a 16384-texel image. Run in a compute shader, one
// invocation per (i, size, wrap); each returns wrap_pair's two texels and wrap_texel's.
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include "gl/shader.h"
#include "rasterizer/texture.h"
#include "tests/gl/gl_test_util.h"

namespace relief::gl {
namespace {

struct WrapCase {
  int32_t i, size, wrap, pad;
};

std::vector<WrapCase> wrap_cases() {
  const std::vector<int> sizes = {1,  2,   3,    4,    5,    6,    7,     13,
                                  64, 100, 1000, 1023, 1024, 4097, 16383, 16384};
  std::vector<int> indices = {0,         1,         -1,        2,         -2,       67108864,
                              -67108864, 67108863,  -67108863, 67108862,  33554433, -33554433,
                              16777217,  -16777217, 16777216,  -16777215, 8388609,  -8388609};
  std::vector<WrapCase> cases;
  std::mt19937 rng(20261205);
  std::uniform_int_distribution<int> any(-67108864, 67108864);
  for (int size : sizes)
    for (int w : {static_cast<int>(Wrap::kRepeat), static_cast<int>(Wrap::kClamp),
                  static_cast<int>(Wrap::kMirror)}) {
      std::vector<int> is = indices;
      // both sides of every period boundary near zero and near the ends of the range, where the
      // float quotient rounds
      for (int k : {-3, -2, -1, 0, 1, 2, 3})
        for (int d : {-1, 0, 1}) {
          is.push_back(k * size + d);
          is.push_back(k * 2 * size + d);
          is.push_back(67108864 / (2 * size) * 2 * size + k * size + d);
          is.push_back(-(67108864 / (2 * size) * 2 * size) + k * size + d);
        }
      for (int r = 0; r < 200; ++r) is.push_back(any(rng));
      for (int i : is)
        if (i >= -67108864 && i <= 67108864) cases.push_back({i, size, w, 0});
    }
  return cases;
}

const char* kComputeSource = R"(#version 450 core
#include "prelude.glsl"
#include "wrap.glsl"
layout(local_size_x = 64) in;
struct WrapCase { int i, size, wrap, pad; };
layout(std430, binding = 0) readonly buffer Cases { WrapCase cases[]; };
layout(std430, binding = 1) writeonly buffer Texels { ivec4 texels[]; };
uniform int count;
void main() {
  int k = int(gl_GlobalInvocationID.x);
  if (k >= count) return;
  WrapCase c = cases[k];
  ivec2 pair = wrap_pair(c.i, c.size, c.wrap);
  texels[k] = ivec4(pair, wrap_texel(c.i, c.size, c.wrap), 0);
}
)";

TEST(GlslWrap, EveryWrapModeGivesTheCpusTexelAcrossTheRange) {
  RELIEF_REQUIRE_GL();
  Result<ShaderSource> src = preprocess_shader("wrap_test.comp", kComputeSource, {});
  ASSERT_TRUE(src.ok()) << src.status().message();
  Result<unsigned> shader = compile_shader(GL_COMPUTE_SHADER, *src);
  ASSERT_TRUE(shader.ok()) << shader.status().message();
  Result<unsigned> program = link_program({*shader}, "wrap_test");
  glDeleteShader(*shader);
  ASSERT_TRUE(program.ok()) << program.status().message();

  const std::vector<WrapCase> cases = wrap_cases();
  const GLsizei n = static_cast<GLsizei>(cases.size());
  GLuint buffers[2];
  glCreateBuffers(2, buffers);
  glNamedBufferStorage(buffers[0], static_cast<GLsizeiptr>(cases.size() * sizeof(WrapCase)),
                       cases.data(), 0);
  glNamedBufferStorage(buffers[1], static_cast<GLsizeiptr>(cases.size() * 4 * sizeof(int32_t)),
                       nullptr, GL_MAP_READ_BIT);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[0]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffers[1]);
  glUseProgram(*program);
  glUniform1i(glGetUniformLocation(*program, "count"), n);
  glDispatchCompute(static_cast<GLuint>((n + 63) / 64), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<int32_t> texels(cases.size() * 4);
  glGetNamedBufferSubData(buffers[1], 0, static_cast<GLsizeiptr>(texels.size() * sizeof(int32_t)),
                          texels.data());
  ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  glUseProgram(0);
  glDeleteBuffers(2, buffers);
  glDeleteProgram(*program);

  int wrong = 0;
  for (size_t k = 0; k < cases.size(); ++k) {
    const WrapCase& c = cases[k];
    const Wrap w = static_cast<Wrap>(c.wrap);
    const int want0 = wrap_texel(c.i, c.size, w);
    const int want1 = wrap_texel(c.i + 1, c.size, w);
    const int32_t* got = &texels[4 * k];
    if (got[0] != want0 || got[1] != want1 || got[2] != want0) {
      if (++wrong <= 10)
        ADD_FAILURE() << "i " << c.i << ", size " << c.size << ", wrap " << c.wrap << ": GLSL ("
                      << got[0] << ", " << got[1] << ", " << got[2] << "), CPU (" << want0 << ", "
                      << want1 << ")";
    }
  }
  EXPECT_EQ(wrong, 0) << " of " << cases.size() << " cases";
  EXPECT_GT(cases.size(), 10000u);
}

}  // namespace
}  // namespace relief::gl
