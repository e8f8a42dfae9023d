// Writes the GLSL prelude (prelude.glsl; CMakeLists.txt runs this at build time): the constants
// the GLSL twins share with C++, taken here from their one source, so no shader copies a number
// by hand. From shaders_cpp/uniforms.h (and rasterizer/texture.h): the limits, the light kinds,
// the standard varying layout, the alpha modes, Filter and Wrap, under the names GLSL has always
// used for them. From the built-in plugin descriptors (PluginRegistry::global(): the list CMake
// generates from the RELIEF_BUILTIN_PLUGIN markers in plugins/*.cpp), for every technique T:
//   kParam_T_P        index of parameter P in T's schema (material.params[kParam_T_P])
//   kChoice_T_P_C     the value of enum parameter P's choice C
//   kNumParams_T      the schema's length
//   kSlot_T_S         index of texture slot S (textures[kSlot_T_S], has_texture[...])
//   kNumSlots_T       the number of slots
// '-' in a name becomes '_' (docs/plugins.md, "Adding a built-in technique").
// Usage: glsl_prelude OUTPUT
#include <cctype>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "gl/gl_layout_internal.h"
#include "gl/height_field.h"
#include "plugins/registry.h"
#include "shaders_cpp/shadow_lookup.h"
#include "shaders_cpp/uniforms.h"

namespace {

using relief::PluginDescriptor;

// A name as part of a GLSL identifier; empty when it cannot be one (GLSL reserves "__").
std::string glsl_part(const char* name) {
  std::string s = name;
  for (char& c : s)
    if (c == '-') c = '_';
  for (char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return "";
  if (s.empty() || s.find("__") != std::string::npos || s.front() == '_' || s.back() == '_')
    return "";
  return s;
}

class Writer {
 public:
  bool constant(const std::string& name, int value, const char* note = nullptr) {
    if (!names_.insert(name).second) {
      std::fprintf(stderr, "glsl_prelude: two constants named %s\n", name.c_str());
      return false;
    }
    out_ << "const int " << name << " = " << value << ";";
    if (note) out_ << "  // " << note;
    out_ << "\n";
    return true;
  }
  // A float written with 9 significant digits, which reads back as the same float.
  bool float_constant(const std::string& name, float value, const char* note = nullptr) {
    if (!names_.insert(name).second) {
      std::fprintf(stderr, "glsl_prelude: two constants named %s\n", name.c_str());
      return false;
    }
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", value);
    std::string v = text;
    if (v.find_first_of(".e") == std::string::npos) v += ".0";
    out_ << "const float " << name << " = " << v << ";";
    if (note) out_ << "  // " << note;
    out_ << "\n";
    return true;
  }
  void line(const std::string& text) { out_ << text << "\n"; }
  std::string text() const { return out_.str(); }

 private:
  std::ostringstream out_;
  std::set<std::string> names_;
};

bool write_technique(Writer& w, const PluginDescriptor& p) {
  const std::string t = glsl_part(p.name);
  bool ok = !t.empty();
  w.line("");
  w.line(std::string("// ---- technique \"") + p.name + "\" ----");
  for (int i = 0; ok && i < p.num_params; ++i) {
    const std::string name = glsl_part(p.params[i].name);
    ok = !name.empty() && w.constant("kParam_" + t + "_" + name, i);
    if (p.params[i].type != relief::ParamType::kEnum) continue;
    const std::vector<std::string> choices = relief::split_choices(p.params[i].choices);
    for (size_t c = 0; ok && c < choices.size(); ++c) {
      const std::string choice = glsl_part(choices[c].c_str());
      ok = !choice.empty() &&
           w.constant("kChoice_" + t + "_" + name + "_" + choice, static_cast<int>(c));
    }
  }
  ok = ok && w.constant("kNumParams_" + t, p.num_params);
  for (int i = 0; ok && i < p.num_textures; ++i) {
    const std::string name = glsl_part(p.textures[i].name);
    ok = !name.empty() && w.constant("kSlot_" + t + "_" + name, i);
  }
  ok = ok && w.constant("kNumSlots_" + t, p.num_textures);
  if (!ok)
    std::fprintf(stderr, "glsl_prelude: technique '%s': a name is no GLSL identifier part\n",
                 p.name);
  return ok;
}

struct Shared {
  const char* section;  // a comment line before the entry, or nullptr
  const char* name;
  int value;
  const char* note;
};

template <class E>
constexpr int as_int(E e) {
  return static_cast<int>(e);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: glsl_prelude OUTPUT\n");
    return 2;
  }
  namespace v = relief::varying;
  using relief::AlphaMode;
  using relief::Filter;
  using relief::LightType;
  using relief::ShadingModel;
  using relief::Wrap;
  namespace L = relief::gl_layout;
  const Shared shared[] = {
      {"shaders_cpp/uniforms.h: limits", "kMaxParams", relief::kMaxParams, nullptr},
      {nullptr, "kMaxTextureSlots", relief::kMaxTextureSlots, nullptr},
      {nullptr, "kMaxLights", relief::kMaxLights, nullptr},
      {nullptr, "kEnvShCount", relief::kEnvShCount, "shaders_cpp/environment_maps.h"},
      {"LightType", "kLightDirectional", as_int(LightType::kDirectional), nullptr},
      {nullptr, "kLightPoint", as_int(LightType::kPoint), nullptr},
      {nullptr, "kLightSpot", as_int(LightType::kSpot), nullptr},
      {"namespace varying: the standard varying layout", "kPosition", v::kPosition, nullptr},
      {nullptr, "kNormal", v::kNormal, nullptr},
      {nullptr, "kTangent", v::kTangent, nullptr},
      {nullptr, "kUv", v::kUv, nullptr},
      {nullptr, "kQuadric", v::kQuadric, nullptr},
      {nullptr, "kTileScale", v::kTileScale, nullptr},
      {nullptr, "kCount", v::kCount, nullptr},
      {nullptr, "kColor", v::kColor, "COLOR_0: the GL vertex stream always carries it"},
      {nullptr, "kUv1", v::kUv1, "TEXCOORD_1, likewise"},
      {nullptr, "kCountExtended", v::kCountExtended, nullptr},
      {nullptr, "kCountGl", (v::kCountExtended + 3) / 4 * 4,
       "kCountExtended rounded up to whole vec4 attributes"},
      {"AlphaMode (MaterialUniforms::alpha_mode)", "kAlphaOpaque", as_int(AlphaMode::kOpaque),
       nullptr},
      {nullptr, "kAlphaMask", as_int(AlphaMode::kMask), nullptr},
      {nullptr, "kAlphaBlend", as_int(AlphaMode::kBlend), nullptr},
      {"ShadingModel (MaterialUniforms::shading)", "kShadingBlinnPhong",
       as_int(ShadingModel::kBlinnPhong), nullptr},
      {nullptr, "kShadingMetallicRoughness", as_int(ShadingModel::kMetallicRoughness), nullptr},
      {"rasterizer/texture.h Filter and Wrap", "kFilterNearest", as_int(Filter::kNearest), nullptr},
      {nullptr, "kFilterBilinear", as_int(Filter::kBilinear), nullptr},
      {nullptr, "kFilterTrilinear", as_int(Filter::kTrilinear), nullptr},
      {nullptr, "kFilterAnisotropic", as_int(Filter::kAnisotropic), nullptr},
      {nullptr, "kWrapRepeat", as_int(Wrap::kRepeat), nullptr},
      {nullptr, "kWrapClamp", as_int(Wrap::kClamp), nullptr},
      {nullptr, "kWrapMirror", as_int(Wrap::kMirror), nullptr},
      {"gl/gl_layout_internal.h: texture units, storage-block bindings, buffer layouts",
       "kShadowUnit", L::kShadowUnit, nullptr},
      {nullptr, "kEmissiveUnit", L::kEmissiveUnit, nullptr},
      {nullptr, "kOcclusionUnit", L::kOcclusionUnit, nullptr},
      {nullptr, "kMetallicRoughnessUnit", L::kMetallicRoughnessUnit, nullptr},
      {nullptr, "kEnvSpecularUnit", L::kEnvSpecularUnit, nullptr},
      {nullptr, "kEnvBrdfUnit", L::kEnvBrdfUnit, nullptr},
      {nullptr, "kCountersBinding", L::kCountersBinding, nullptr},
      {nullptr, "kHeightFieldBinding", L::kHeightFieldBinding, nullptr},
      {nullptr, "kShadowViewsBinding", L::kShadowViewsBinding, nullptr},
      {nullptr, "kTrianglePlanesBinding", L::kTrianglePlanesBinding, nullptr},
      {nullptr, "kTriangleHeader", L::kTriangleHeader, nullptr},
      {nullptr, "kShadowViewHeader", L::kShadowViewHeader, nullptr},
      {nullptr, "kMaxShadowFaces", relief::kMaxShadowFaces, "shaders_cpp/shadow_lookup.h"},
      {nullptr, "kMaxFieldLevels", relief::gl::kMaxFieldLevels, "gl/height_field.h"},
      {nullptr, "kCounterSlots", L::kCounterSlots, nullptr},
      {nullptr, "kCounterFragments", L::kCounterFragments, nullptr},
      {nullptr, "kCounterFetches", L::kCounterFetches, nullptr},
      {nullptr, "kCounterSearchSteps", L::kCounterSearchSteps, nullptr},
      {nullptr, "kCounterShadowSteps", L::kCounterShadowSteps, nullptr},
      {nullptr, "kCounterDiscarded", L::kCounterDiscarded, nullptr},
      {nullptr, "kCounterCount", L::kCounterCount, nullptr},
  };
  Writer w;
  w.line("// Generated by gl/tools/glsl_prelude.cpp from shaders_cpp/uniforms.h and the built-in");
  w.line("// plugin descriptors; do not edit (docs/plugins.md, \"Adding a built-in technique\").");
  bool ok = true;
  for (const Shared& s : shared) {
    if (s.section) {
      w.line("");
      w.line(std::string("// ---- ") + s.section + " ----");
    }
    ok = ok && w.constant(s.name, s.value, s.note);
  }
  w.line("");
  w.line("// ---- float constants ----");
  ok = ok && w.float_constant("kMinGgxAlpha", relief::kMinGgxAlpha,
                              "shaders_cpp/uniforms.h: the smallest GGX alpha");
  for (const PluginDescriptor* p : relief::PluginRegistry::global().all())
    ok = ok && write_technique(w, *p);
  if (!ok) return 1;
  std::ofstream out(argv[1], std::ios::binary | std::ios::trunc);
  out << w.text();
  out.close();
  if (!out) {
    std::fprintf(stderr, "glsl_prelude: cannot write %s\n", argv[1]);
    return 1;
  }
  return 0;
}
