// The plugin parameter schema as PluginRegistry::add checks it (an external plugin hands over
// any bytes): malformed entries are one-line errors naming the plugin and the entry, never a
// crash later in resolve_params or describe_params; values no float holds are refused by name.
// Regression cases of the fuzz_plugin_schema and fuzz_cli targets (tests/fuzz/).
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "plugins/registry.h"

namespace relief {
namespace {

ShadeFn no_select(EffectMask) {
  return nullptr;
}
DepthOutput no_depth(EffectMask) {
  return DepthOutput::kNone;
}

PluginDescriptor descriptor(const std::vector<ParamSpec>& params,
                            const std::vector<TextureSlotSpec>& slots = {}) {
  PluginDescriptor d{};
  d.abi_version = kPluginAbiVersion;
  d.name = "schema_test";
  d.description = "test";
  d.params = params.data();
  d.num_params = static_cast<int>(params.size());
  d.textures = slots.data();
  d.num_textures = static_cast<int>(slots.size());
  d.select = no_select;
  d.depth_output = no_depth;
  return d;
}

constexpr ParamSpec kGood = {"steps", ParamType::kInt, 8.0f, 1.0f, 16.0f, nullptr, "h"};

TEST(Schema, MalformedParametersAreOneLineErrorsNamingThem) {
  struct Case {
    ParamSpec spec;
    const char* expect;
  };
  const float inf = std::numeric_limits<float>::infinity();
  const Case cases[] = {
      {{nullptr, ParamType::kFloat, 0, 0, 1, nullptr, nullptr}, "parameter 1 has no name"},
      {{"", ParamType::kFloat, 0, 0, 1, nullptr, nullptr}, "parameter 1 has no name"},
      {{"steps", ParamType::kFloat, 0, 0, 1, nullptr, nullptr}, "'steps' twice"},
      {{"x", static_cast<ParamType>(7), 0, 0, 1, nullptr, nullptr}, "'x' has an unknown type"},
      {{"x", ParamType::kFloat, 5, 10, 1, nullptr, nullptr}, "'x': expected finite min"},
      {{"x", ParamType::kFloat, 0, -inf, 1, nullptr, nullptr}, "'x': expected finite min"},
      {{"x", ParamType::kInt, 20, 0, 10, nullptr, nullptr}, "'x': expected finite min"},
      // fuzz_plugin_schema: describe_params cast this range to long (undefined behaviour)
      {{"x", ParamType::kInt, 0, -1.70141e38f, 1, nullptr, nullptr}, "'x': an int range must lie"},
      {{"x", ParamType::kEnum, 0, 0, 2, nullptr, nullptr}, "'x': an enum needs choices"},
      {{"x", ParamType::kEnum, 3, 0, 3, "a|b", nullptr}, "'x': the default must index"},
      // fuzz_plugin_schema: a negative default passed and describe_params cast it to size_t
      {{"x", ParamType::kEnum, -8.79609e12f, -1e13f, 1, "a|b", nullptr},
       "'x': the default must index"},
  };
  for (const Case& c : cases) {
    const std::vector<ParamSpec> params = {kGood, c.spec};
    PluginDescriptor d = descriptor(params);
    PluginRegistry r;
    const Status s = r.add(&d);
    ASSERT_FALSE(s.ok()) << c.expect;
    EXPECT_NE(s.message().find("plugin 'schema_test'"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find(c.expect), std::string::npos) << s.message();
    EXPECT_EQ(s.message().find('\n'), std::string::npos);
    EXPECT_EQ(r.find("schema_test"), nullptr);
  }
}

// fuzz_plugin_schema: a name with a newline made a multi-line error. Names are plain
// identifiers, so every message that quotes one stays one printable line.
TEST(Schema, NamesWithControlCharactersAreRefusedInOneLine) {
  const std::vector<ParamSpec> bad_param = {kGood,
                                            {"a\nb", ParamType::kFloat, 0, 0, 1, nullptr, nullptr}};
  const std::vector<ParamSpec> bad_choice = {kGood,
                                             {"mode", ParamType::kEnum, 0, 0, 1, "a|b\n", nullptr}};
  const std::vector<TextureSlotSpec> bad_slot = {{"dep\nth", true, nullptr}};
  const std::vector<ParamSpec> good = {kGood};  // descriptors point into these vectors
  PluginDescriptor p1 = descriptor(bad_param), p2 = descriptor(bad_choice),
                   p3 = descriptor(good, bad_slot), p4 = descriptor(good);
  p4.name = "two\nlines";
  for (const PluginDescriptor* d : {&p1, &p2, &p3, &p4}) {
    PluginRegistry r;
    const Status s = r.add(d);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.message().find('\n'), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("letters, digits"), std::string::npos) << s.message();
  }
}

// fuzz_plugin_schema: `--param` text with a newline, quoted back in the error, made it two lines.
TEST(Schema, UserTextInParameterErrorsIsEscapedToOneLine) {
  const std::vector<ParamSpec> params = {kGood};
  PluginDescriptor d = descriptor(params);
  for (const auto& [name, value] : std::vector<std::pair<std::string, std::string>>{
           {"ste\nps", "1"}, {"steps", "1\n2"}, {"steps", "x\ty"}}) {
    Result<std::vector<float>> v = resolve_params(d, {}, {{name, value}});
    ASSERT_FALSE(v.ok());
    const std::string& m = v.status().message();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_EQ(m.find('\t'), std::string::npos) << m;
    EXPECT_TRUE(m.find("\\n") != std::string::npos || m.find("\\x09") != std::string::npos) << m;
  }
}

TEST(Schema, MalformedTextureSlotsAreRefused) {
  const std::vector<ParamSpec> params = {kGood};
  for (const std::vector<TextureSlotSpec>& slots :
       {std::vector<TextureSlotSpec>{{nullptr, true, nullptr}},
        std::vector<TextureSlotSpec>{{"depth", true, nullptr}, {"depth", false, nullptr}}}) {
    PluginDescriptor d = descriptor(params, slots);
    PluginRegistry r;
    EXPECT_FALSE(r.add(&d).ok());
  }
}

TEST(Schema, AWellFormedSchemaResolvesAndDescribes) {
  const std::vector<ParamSpec> params = {kGood,
                                         {"mode", ParamType::kEnum, 1, 0, 2, "a|b|c", "m"},
                                         {"on", ParamType::kBool, 1, 0, 1, nullptr, "b"}};
  PluginDescriptor d = descriptor(params);
  PluginRegistry r;
  ASSERT_TRUE(r.add(&d).ok());
  Result<std::vector<float>> v = resolve_params(d, {}, {{"mode", "c"}, {"steps", "16"}});
  ASSERT_TRUE(v.ok()) << v.status().message();
  EXPECT_EQ((*v)[0], 16.0f);
  EXPECT_EQ((*v)[1], 2.0f);
  EXPECT_NE(describe_params(d).find("mode = b"), std::string::npos) << describe_params(d);
}

TEST(Schema, ValuesNoFloatHoldsAreOutOfRangeByName) {
  const std::vector<ParamSpec> params = {kGood,
                                         {"scale", ParamType::kFloat, 0, -1, 1, nullptr, "s"}};
  PluginDescriptor d = descriptor(params);
  for (const char* text : {"1e300", "-1e39", "3.5e38"}) {
    Result<std::vector<float>> v = resolve_params(d, {}, {{"scale", text}});
    ASSERT_FALSE(v.ok()) << text;
    EXPECT_EQ(v.status().exit_code(), 2);
    EXPECT_NE(v.status().message().find("'scale': " + std::string(text) + " is outside -1..1"),
              std::string::npos)
        << v.status().message();
  }
  for (const char* text : {"1e400", "nan", "inf", "x", ""}) {
    Result<std::vector<float>> v = resolve_params(d, {}, {{"steps", text}});
    ASSERT_FALSE(v.ok()) << text;
    EXPECT_NE(v.status().message().find("'steps'"), std::string::npos) << v.status().message();
  }
}

}  // namespace
}  // namespace relief
