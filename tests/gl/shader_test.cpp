#include "gl/shader.h"

#include <algorithm>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include "gl/embedded_shaders.h"
#include "gl/gl_backend.h"
#include "plugins/registry.h"
#include "tests/gl/gl_test_util.h"

namespace relief::gl {
namespace {

std::vector<std::string> variant_defines(EffectMask e, bool writes_depth, bool aovs,
                                         bool farther = false, bool count = false) {
  auto flag = [](const char* n, bool on) { return std::string(n) + (on ? " 1" : " 0"); };
  return {flag("RELIEF_DEPTH_FARTHER", farther),
          flag("RELIEF_COUNT", count),
          flag("EFFECT_SELF_SHADOW", e & kEffectSelfShadow),
          flag("EFFECT_DEPTH_WRITE", e & kEffectDepthWrite),
          flag("EFFECT_SILHOUETTE", e & kEffectSilhouette),
          flag("EFFECT_SHADOW_PASS", e & kEffectShadowPass),
          flag("EFFECT_RECEIVE_SHADOW", e & kEffectReceiveShadow),
          flag("EFFECT_HEIGHT_AO", e & kEffectHeightAo),
          flag("RELIEF_WRITES_DEPTH", writes_depth),
          flag("RELIEF_AOVS", aovs)};
}

TEST(Shader, EveryFragmentFileCompilesAndLinks) {
  RELIEF_REQUIRE_GL();
  const std::vector<std::string> files = list_shader_files();
  ASSERT_FALSE(files.empty());
  int built = 0;
  for (const std::string& f : files) {
    if (f.size() < 5 || f.substr(f.size() - 5) != ".frag") continue;
    for (int aovs = 0; aovs < 2; ++aovs) {
      Result<unsigned> p = build_program("relief.vert", f, variant_defines(0, false, aovs != 0));
      ASSERT_TRUE(p.ok()) << p.status().message();
      glDeleteProgram(*p);
      ++built;
    }
  }
  EXPECT_GE(built, 4);  // flat and normal at least
}

TEST(Shader, EveryTwinCompilesForEveryEffectCombination) {
  RELIEF_REQUIRE_GL();
  int twins = 0;
  for (const PluginDescriptor* plugin : PluginRegistry::global().all()) {
    if (!gl_has_twin(plugin->name)) continue;
    ++twins;
    const EffectMask supported = plugin->supported_effects;
    // Every subset of the supported effects.
    for (EffectMask e = supported;; e = (e - 1) & supported) {
      const DepthOutput depth = plugin->depth_output(e);
      const bool writes_depth = depth != DepthOutput::kNone;
      // as the backend builds it, with and without the work counters
      for (int count = 0; count < 2; ++count) {
        Result<unsigned> p = build_program(
            "relief.vert", gl_twin_file(plugin->name),
            variant_defines(e, writes_depth, false, depth == DepthOutput::kFarther, count != 0));
        EXPECT_TRUE(p.ok()) << plugin->name << " effects " << e << ": " << p.status().message();
        if (p.ok()) glDeleteProgram(*p);
      }
      if (e == 0) break;
    }
  }
  EXPECT_GE(twins, 7);  // flat, normal and the relief family
}

TEST(Shader, CompileErrorNamesFileAndLine) {
  RELIEF_REQUIRE_GL();
  const std::string text =
      "#version 450 core\n"
      "#include \"common.glsl\"\n"
      "float visibility(int i, vec3 l) { return 1.0; }\n"
      "void main() {\n"
      "  out_color = vec4(undeclared_thing);\n"  // line 5
      "}\n";
  Result<ShaderSource> src =
      preprocess_shader("broken.frag", text, variant_defines(0, false, false));
  ASSERT_TRUE(src.ok()) << src.status().message();
  Result<unsigned> s = compile_shader(GL_FRAGMENT_SHADER, *src);
  ASSERT_FALSE(s.ok());
  const std::string& m = s.status().message();
  EXPECT_NE(m.find("broken.frag:5:"), std::string::npos) << m;
  EXPECT_NE(m.find("undeclared_thing"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

TEST(Shader, CompileErrorInIncludedFileNamesThatFile) {
  RELIEF_REQUIRE_GL();
  auto reader = [](const std::string& name) -> Result<std::string> {
    if (name == "lib.glsl") return std::string("float f() {\n  return 1.0\n}\n");  // line 3: ';'
    return Status::error("no " + name);
  };
  const std::string text =
      "#version 450 core\n"
      "// a comment\n"
      "#include \"lib.glsl\"\n"
      "out vec4 c;\n"
      "void main() { c = vec4(f()); }\n";
  Result<ShaderSource> src = preprocess_shader("main.frag", text, {}, reader);
  ASSERT_TRUE(src.ok()) << src.status().message();
  ASSERT_EQ(src->files.size(), 2u);
  Result<unsigned> s = compile_shader(GL_FRAGMENT_SHADER, *src);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("lib.glsl:3:"), std::string::npos) << s.status().message();
}

TEST(Shader, LineNumbersResumeAfterInclude) {
  RELIEF_REQUIRE_GL();
  auto reader = [](const std::string&) -> Result<std::string> {
    return std::string("float f() { return 1.0; }\n// two\n// three\n");
  };
  const std::string text =
      "#version 450 core\n"
      "#include \"lib.glsl\"\n"
      "out vec4 c;\n"
      "void main() {\n"
      "  c = vec4(f()) + nope;\n"  // line 5 of main.frag
      "}\n";
  Result<ShaderSource> src = preprocess_shader("main.frag", text, {"FOO 1"}, reader);
  ASSERT_TRUE(src.ok());
  Result<unsigned> s = compile_shader(GL_FRAGMENT_SHADER, *src);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("main.frag:5:"), std::string::npos) << s.status().message();
}

TEST(Shader, PreprocessorRejectsBadInput) {
  auto none = [](const std::string& n) -> Result<std::string> { return Status::error("no " + n); };
  EXPECT_FALSE(preprocess_shader("a.frag", "void main() {}\n", {}, none).ok());  // no #version
  Result<ShaderSource> missing =
      preprocess_shader("a.frag", "#version 450 core\n#include \"x.glsl\"\n", {}, none);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("a.frag:2"), std::string::npos);
  auto self = [](const std::string&) -> Result<std::string> {
    return std::string("#include \"loop.glsl\"\n");
  };
  Result<ShaderSource> cycle =
      preprocess_shader("a.frag", "#version 450 core\n#include \"loop.glsl\"\n", {}, self);
  ASSERT_FALSE(cycle.ok());
  EXPECT_NE(cycle.status().message().find("cycle"), std::string::npos) << cycle.status().message();
}

TEST(Shader, DefinesFollowTheVersionLine) {
  auto none = [](const std::string& n) -> Result<std::string> { return Status::error("no " + n); };
  Result<ShaderSource> s = preprocess_shader(
      "a.frag", "// head\n#version 450 core\nvoid main() {}\n", {"A 1", "B"}, none);
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_EQ(s->text.find("#version 450 core\n#define A 1\n#define B\n#line 3 0\n"),
            s->text.find("#version"));
}

TEST(Shader, DriverLogFormats) {
  const std::vector<std::string> files = {"main.frag", "common.glsl"};
  EXPECT_EQ(format_shader_log("1:12(5): error: `x' undeclared\n", files),
            "common.glsl:12: error: `x' undeclared");
  EXPECT_EQ(format_shader_log("0(7) : error C1008: undefined variable \"x\"\n", files),
            "main.frag:7: error C1008: undefined variable \"x\"");
  EXPECT_EQ(format_shader_log("ERROR: 1:3: 'x' : undeclared identifier\n", files),
            "common.glsl:3: 'x' : undeclared identifier");
  // Errors win over earlier warnings.
  EXPECT_EQ(format_shader_log("0:2(1): warning: unused\n0:9(1): error: bad\n", files),
            "main.frag:9: error: bad");
  EXPECT_EQ(format_shader_log("link failed somehow\n", files), "link failed somehow");
}

TEST(Shader, EveryShaderFileIsEmbedded) {
  // The installed binary reads the embedded copies: CMakeLists.txt lists every gl/shaders file
  // for gl/embedded_shaders.cpp (a glob) and the generated prelude.glsl.
  std::vector<std::string> embedded;
  for (const EmbeddedShader& e : embedded_shaders()) embedded.emplace_back(e.name);
  for (const std::string& f : list_shader_files())
    EXPECT_NE(std::find(embedded.begin(), embedded.end(), f), embedded.end())
        << f << " is not embedded (CMakeLists.txt, embedded_shader_list.inc)";
  for (const EmbeddedShader& e : embedded_shaders()) EXPECT_GT(e.size, 0u) << e.name;
}

}  // namespace
}  // namespace relief::gl
