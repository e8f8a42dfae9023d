// The generated GLSL prelude (gl/tools/glsl_prelude.cpp, prelude.glsl) against the C++ it is
// generated from, and the one technique list: every built-in plugin has its GLSL twin
// <name>.frag and every twin a built-in plugin; no shader indexes parameters or texture slots by
// a literal number, and a twin names only its own technique's indices. No GL context needed.
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "gl/embedded_shaders.h"
#include "gl/gl_backend.h"
#include "gl/gl_layout_internal.h"
#include "gl/height_field.h"
#include "gl/shader.h"
#include "plugins/registry.h"
#include "shaders_cpp/shadow_lookup.h"

namespace relief::gl {
namespace {

// .frag files that are no technique's twin.
const std::set<std::string> kNotTwins = {"depth_only.frag"};

std::map<std::string, int> prelude_constants() {
  Result<std::string> text = read_shader_file("prelude.glsl");
  EXPECT_TRUE(text.ok()) << text.status().message();
  std::map<std::string, int> out;
  if (!text.ok()) return out;
  static const std::regex decl(R"(const int (\w+) = (-?\d+);)");
  for (std::sregex_iterator it(text->begin(), text->end(), decl), end; it != end; ++it)
    EXPECT_TRUE(out.emplace((*it)[1].str(), std::stoi((*it)[2].str())).second) << (*it)[1];
  return out;
}

std::string glsl_name(std::string s) {
  for (char& c : s)
    if (c == '-') c = '_';
  return s;
}

// The names the prelude should hold for technique p, with their values.
std::map<std::string, int> technique_constants(const PluginDescriptor& p) {
  std::map<std::string, int> want;
  const std::string t = glsl_name(p.name);
  for (int i = 0; i < p.num_params; ++i) {
    const std::string name = glsl_name(p.params[i].name);
    want["kParam_" + t + "_" + name] = i;
    if (p.params[i].type != ParamType::kEnum) continue;
    const std::vector<std::string> choices = split_choices(p.params[i].choices);
    for (size_t c = 0; c < choices.size(); ++c)
      want["kChoice_" + t + "_" + name + "_" + glsl_name(choices[c])] = static_cast<int>(c);
  }
  want["kNumParams_" + t] = p.num_params;
  for (int i = 0; i < p.num_textures; ++i)
    want["kSlot_" + t + "_" + glsl_name(p.textures[i].name)] = i;
  want["kNumSlots_" + t] = p.num_textures;
  return want;
}

TEST(ShaderPrelude, MatchesUniformsAndEveryBuiltinDescriptor) {
  const std::map<std::string, int> got = prelude_constants();
  const std::map<std::string, int> shared = {
      {"kMaxParams", kMaxParams},
      {"kMaxTextureSlots", kMaxTextureSlots},
      {"kMaxLights", kMaxLights},
      {"kEnvShCount", kEnvShCount},
      {"kLightDirectional", int(LightType::kDirectional)},
      {"kLightPoint", int(LightType::kPoint)},
      {"kLightSpot", int(LightType::kSpot)},
      {"kPosition", varying::kPosition},
      {"kNormal", varying::kNormal},
      {"kTangent", varying::kTangent},
      {"kUv", varying::kUv},
      {"kQuadric", varying::kQuadric},
      {"kTileScale", varying::kTileScale},
      {"kCount", varying::kCount},
      {"kColor", varying::kColor},
      {"kUv1", varying::kUv1},
      {"kCountExtended", varying::kCountExtended},
      {"kCountGl", (varying::kCountExtended + 3) / 4 * 4},
      {"kAlphaOpaque", int(AlphaMode::kOpaque)},
      {"kAlphaMask", int(AlphaMode::kMask)},
      {"kAlphaBlend", int(AlphaMode::kBlend)},
      {"kShadingBlinnPhong", int(ShadingModel::kBlinnPhong)},
      {"kShadingMetallicRoughness", int(ShadingModel::kMetallicRoughness)},
      {"kFilterNearest", int(Filter::kNearest)},
      {"kFilterBilinear", int(Filter::kBilinear)},
      {"kFilterTrilinear", int(Filter::kTrilinear)},
      {"kFilterAnisotropic", int(Filter::kAnisotropic)},
      {"kWrapRepeat", int(Wrap::kRepeat)},
      {"kWrapClamp", int(Wrap::kClamp)},
      {"kWrapMirror", int(Wrap::kMirror)},
      {"kShadowUnit", gl_layout::kShadowUnit},
      {"kEmissiveUnit", gl_layout::kEmissiveUnit},
      {"kOcclusionUnit", gl_layout::kOcclusionUnit},
      {"kMetallicRoughnessUnit", gl_layout::kMetallicRoughnessUnit},
      {"kEnvSpecularUnit", gl_layout::kEnvSpecularUnit},
      {"kEnvBrdfUnit", gl_layout::kEnvBrdfUnit},
      {"kCountersBinding", gl_layout::kCountersBinding},
      {"kHeightFieldBinding", gl_layout::kHeightFieldBinding},
      {"kShadowViewsBinding", gl_layout::kShadowViewsBinding},
      {"kTrianglePlanesBinding", gl_layout::kTrianglePlanesBinding},
      {"kTriangleHeader", gl_layout::kTriangleHeader},
      {"kShadowViewHeader", gl_layout::kShadowViewHeader},
      {"kMaxShadowFaces", kMaxShadowFaces},
      {"kMaxFieldLevels", gl::kMaxFieldLevels},
      {"kCounterSlots", gl_layout::kCounterSlots},
      {"kCounterFragments", gl_layout::kCounterFragments},
      {"kCounterFetches", gl_layout::kCounterFetches},
      {"kCounterSearchSteps", gl_layout::kCounterSearchSteps},
      {"kCounterShadowSteps", gl_layout::kCounterShadowSteps},
      {"kCounterDiscarded", gl_layout::kCounterDiscarded},
      {"kCounterCount", gl_layout::kCounterCount},
  };
  std::map<std::string, int> want = shared;
  for (const PluginDescriptor* p : PluginRegistry::global().all())
    want.merge(technique_constants(*p));
  for (const auto& [name, value] : want) {
    auto it = got.find(name);
    if (it == got.end())
      ADD_FAILURE() << "prelude.glsl lacks " << name;
    else
      EXPECT_EQ(it->second, value) << name;
  }
  for (const auto& [name, value] : got)
    EXPECT_TRUE(want.count(name)) << "prelude.glsl has " << name << ", which no C++ source gives";
}

// The float constants: written so that they read back as the very float the C++ uses.
TEST(ShaderPrelude, FloatConstantsReadBackExactly) {
  Result<std::string> text = read_shader_file("prelude.glsl");
  ASSERT_TRUE(text.ok()) << text.status().message();
  std::map<std::string, float> got;
  static const std::regex decl(R"(const float (\w+) = ([-+.\deE]+);)");
  for (std::sregex_iterator it(text->begin(), text->end(), decl), end; it != end; ++it)
    got[(*it)[1].str()] = std::stof((*it)[2].str());
  const std::map<std::string, float> want = {{"kMinGgxAlpha", kMinGgxAlpha}};
  EXPECT_EQ(got, want);
}

TEST(ShaderPrelude, EmbeddedCopyIsTheBuildTreeFile) {
  std::ifstream in(RELIEF_BINARY_DIR "/generated/gl/prelude.glsl", std::ios::binary);
  ASSERT_TRUE(in) << "no generated/gl/prelude.glsl in the build tree";
  std::ostringstream disk;
  disk << in.rdbuf();
  Result<std::string> embedded = read_shader_file("prelude.glsl");
  ASSERT_TRUE(embedded.ok()) << embedded.status().message();
  EXPECT_EQ(*embedded, disk.str());
  std::ifstream source_copy(RELIEF_SOURCE_DIR "/gl/shaders/prelude.glsl");
  EXPECT_FALSE(source_copy) << "gl/shaders/prelude.glsl: the prelude is generated, not a source";
}

TEST(ShaderPrelude, EveryBuiltinHasATwinAndEveryTwinABuiltin) {
  std::set<std::string> techniques;
  for (const PluginDescriptor* p : PluginRegistry::global().all()) {
    techniques.insert(p->name);
    EXPECT_TRUE(gl_has_twin(p->name)) << p->name << " has no GLSL twin " << gl_twin_file(p->name);
  }
  for (const std::string& f : list_shader_files()) {
    if (f.size() < 5 || f.substr(f.size() - 5) != ".frag" || kNotTwins.count(f)) continue;
    EXPECT_TRUE(techniques.count(f.substr(0, f.size() - 5)))
        << f << " is no built-in technique's twin (a plugins/*.cpp with RELIEF_BUILTIN_PLUGIN)";
  }
}

TEST(ShaderPrelude, TwinsUseOnlyTheirOwnGeneratedIndices) {
  static const std::regex generated(R"(\bk(Param|Choice|NumParams|Slot|NumSlots)_\w+)");
  for (const PluginDescriptor* p : PluginRegistry::global().all()) {
    Result<std::string> text = read_shader_file(gl_twin_file(p->name));
    if (!text.ok()) continue;  // EveryBuiltinHasATwinAndEveryTwinABuiltin reports it
    const std::map<std::string, int> own = technique_constants(*p);
    for (std::sregex_iterator it(text->begin(), text->end(), generated), end; it != end; ++it)
      EXPECT_TRUE(own.count(it->str())) << gl_twin_file(p->name) << " reads " << it->str()
                                        << ", not one of technique '" << p->name << "'";
  }
}

TEST(ShaderPrelude, NoShaderIndexesParamsOrSlotsByNumber) {
  static const std::regex literal(
      R"(\b(params|textures|has_texture|uv_maps|texture_sampler)\s*\[\s*\d|sample_slot\s*\(\s*\d)");
  for (const std::string& f : list_shader_files()) {
    Result<std::string> text = read_shader_file(f);
    ASSERT_TRUE(text.ok()) << text.status().message();
    std::istringstream in(*text);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n)
      EXPECT_FALSE(std::regex_search(line, literal))
          << f << ":" << n
          << ": an index by number; use the prelude's kParam_/kSlot_ names: " << line;
  }
}

}  // namespace
}  // namespace relief::gl
