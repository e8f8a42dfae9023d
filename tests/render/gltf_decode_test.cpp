// Compressed and quantized glTF (scene/gltf_decode.h): every file here is written by the test
// with the encoder side of the library relief decodes with (meshoptimizer, draco, OpenImageIO's
// WebP writer), loaded, and compared with the same mesh or image stored plainly: exact where the
// coding is lossless, within the quantization step otherwise. Hostile variants (truncated
// streams, lying and huge counts) must end in one error line naming the file and a JSON pointer.
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <nlohmann/json.hpp>

#include "render/validate.h"
#include "scene/animation.h"
#include "scene/gltf.h"
#include "tests/apps/cli_run.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr int kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kUInt = 5125,
              kFloat = 5126;

// ---- the reference mesh: a bumpy 6 x 6 grid ----
struct RefMesh {
  std::vector<glm::vec3> pos, nrm;
  std::vector<glm::vec2> uv;
  std::vector<uint32_t> idx;
};

RefMesh grid() {
  RefMesh m;
  const int n = 6;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float x = i / float(n - 1), y = j / float(n - 1);
      const float z = 0.2f * std::sin(3.0f * x) * std::cos(2.0f * y);
      const float dzdx = 0.6f * std::cos(3.0f * x) * std::cos(2.0f * y);
      const float dzdy = -0.4f * std::sin(3.0f * x) * std::sin(2.0f * y);
      m.pos.push_back({x, y, z});
      m.nrm.push_back(glm::normalize(glm::vec3(-dzdx, -dzdy, 1.0f)));
      m.uv.push_back({x, 1.0f - y});
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      for (uint32_t v : {a, b, d, a, d, c}) m.idx.push_back(v);
    }
  return m;
}

// Per triangle corner: world position, world normal, uv (independent of vertex splitting).
struct Corners {
  std::vector<glm::vec3> p, n;
  std::vector<glm::vec2> uv;
};

Corners corners(const Scene& s) {
  Corners c;
  const Instance& inst = s.instances.at(0);
  const Mesh& m = s.meshes.at(inst.mesh);
  const glm::mat3 nm = glm::inverseTranspose(glm::mat3(inst.transform));
  for (uint32_t i : m.indices) {
    c.p.push_back(glm::vec3(inst.transform * glm::vec4(m.positions[i], 1.0f)));
    if (!m.normals.empty()) c.n.push_back(glm::normalize(nm * m.normals[i]));
    if (!m.uvs.empty()) c.uv.push_back(m.uvs[i]);
  }
  return c;
}

// `got` with each triangle's corners rotated to match `ref` best (meshopt's index codec keeps
// the triangle order but may rotate a triangle's corners).
Corners aligned(const Corners& got, const Corners& ref) {
  if (got.p.size() != ref.p.size()) return got;
  Corners out = got;
  for (size_t t = 0; t + 2 < got.p.size(); t += 3) {
    int best = 0;
    float best_d = INFINITY;
    for (int r = 0; r < 3; ++r) {
      float d = 0.0f;
      for (int c = 0; c < 3; ++c) d += glm::length(got.p[t + (c + r) % 3] - ref.p[t + c]);
      if (d < best_d) best_d = d, best = r;
    }
    for (int c = 0; c < 3; ++c) {
      const size_t from = t + (c + best) % 3;
      out.p[t + c] = got.p[from];
      if (!got.n.empty()) out.n[t + c] = got.n[from];
      if (!got.uv.empty()) out.uv[t + c] = got.uv[from];
    }
  }
  return out;
}

template <typename V>
float max_diff(const std::vector<V>& a, const std::vector<V>& b) {
  if (a.size() != b.size() || a.empty()) return INFINITY;
  float d = 0.0f;
  for (size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < V::length(); ++k) d = std::max(d, std::abs(a[i][k] - b[i][k]));
  return d;
}

void write_file(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}
template <typename T>
std::string bytes_of(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}
void pad4(std::string& s, char with = '\0') {
  while (s.size() % 4) s += with;
}

std::string glb(const json& doc, std::string bin) {
  std::string j = doc.dump();
  pad4(j, ' ');
  pad4(bin);
  std::string out;
  auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  u32(0x46546C67u);
  u32(2);
  u32(static_cast<uint32_t>(12 + 8 + j.size() + (bin.empty() ? 0 : 8 + bin.size())));
  u32(static_cast<uint32_t>(j.size()));
  u32(0x4E4F534Au);
  out += j;
  if (!bin.empty()) {
    u32(static_cast<uint32_t>(bin.size()));
    u32(0x004E4942u);
    out += bin;
  }
  return out;
}

json base_doc() {
  return {{"asset", {{"version", "2.0"}}},
          {"scene", 0},
          {"scenes", json::array({{{"nodes", {0}}}})},
          {"nodes", json::array({{{"mesh", 0}}})}};
}

// The reference mesh stored plainly (FLOAT attributes, UNSIGNED_INT indices) in `dir`.
fs::path write_plain(const fs::path& dir, const RefMesh& m) {
  std::string bin = bytes_of(m.pos) + bytes_of(m.nrm) + bytes_of(m.uv) + bytes_of(m.idx);
  write_file(dir / "plain.bin", bin);
  const size_t n = m.pos.size();
  json doc = base_doc();
  doc["meshes"] = json::array(
      {{{"primitives",
         json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
                       {"indices", 3}}})}}});
  doc["accessors"] = json::array({
      {{"bufferView", 0}, {"componentType", kFloat}, {"count", n}, {"type", "VEC3"}},
      {{"bufferView", 1}, {"componentType", kFloat}, {"count", n}, {"type", "VEC3"}},
      {{"bufferView", 2}, {"componentType", kFloat}, {"count", n}, {"type", "VEC2"}},
      {{"bufferView", 3}, {"componentType", kUInt}, {"count", m.idx.size()}, {"type", "SCALAR"}},
  });
  doc["bufferViews"] = json::array({
      {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 12 * n}},
      {{"buffer", 0}, {"byteOffset", 12 * n}, {"byteLength", 12 * n}},
      {{"buffer", 0}, {"byteOffset", 24 * n}, {"byteLength", 8 * n}},
      {{"buffer", 0}, {"byteOffset", 32 * n}, {"byteLength", 4 * m.idx.size()}},
  });
  doc["buffers"] = json::array({{{"uri", "plain.bin"}, {"byteLength", bin.size()}}});
  const fs::path p = dir / "plain.gltf";
  write_file(p, doc.dump());
  return p;
}

Corners reference_corners(const fs::path& dir, const RefMesh& m) {
  Result<Scene> s = load_scene(write_plain(dir, m).string());
  EXPECT_TRUE(s.ok()) << s.status().message();
  return s.ok() ? corners(*s) : Corners{};
}

// The error of a load that must fail: one line under 300 characters naming the file.
void expect_one_line_error(const fs::path& p, const std::string& must_contain) {
  Result<Scene> s = load_scene(p.string());
  ASSERT_FALSE(s.ok()) << p;
  const std::string& msg = s.status().message();
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_LT(msg.size(), 300u) << msg;
  EXPECT_EQ(msg.rfind(p.string() + ": ", 0), 0u) << msg;
  EXPECT_NE(msg.find(must_contain), std::string::npos) << msg;
}

// ---- KHR_mesh_quantization ----

// SHORT positions dequantized by the node's scale, normalized BYTE normals (stride 4),
// normalized SHORT uvs, UNSIGNED_SHORT indices.
json quantized_doc(const RefMesh& m, std::string& bin, bool declare) {
  const size_t n = m.pos.size();
  constexpr float kPosScale = 4000.0f;
  std::vector<int16_t> pos, uv;
  std::vector<int8_t> nrm;
  std::vector<uint16_t> idx(m.idx.begin(), m.idx.end());
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) pos.push_back(int16_t(std::lround(m.pos[i][k] * kPosScale)));
    pos.push_back(0);  // pad each element to 8 bytes
    for (int k = 0; k < 3; ++k) nrm.push_back(int8_t(std::lround(m.nrm[i][k] * 127.0f)));
    nrm.push_back(0);
    for (int k = 0; k < 2; ++k) uv.push_back(int16_t(std::lround(m.uv[i][k] * 32767.0f)));
  }
  bin = bytes_of(pos) + bytes_of(nrm) + bytes_of(uv) + bytes_of(idx);
  json doc = base_doc();
  const float s = 1.0f / kPosScale;
  doc["nodes"][0]["scale"] = {s, s, s};
  doc["meshes"] = json::array(
      {{{"primitives",
         json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
                       {"indices", 3}}})}}});
  doc["accessors"] = json::array({
      {{"bufferView", 0}, {"componentType", kShort}, {"count", n}, {"type", "VEC3"}},
      {{"bufferView", 1},
       {"componentType", kByte},
       {"normalized", true},
       {"count", n},
       {"type", "VEC3"}},
      {{"bufferView", 2},
       {"componentType", kShort},
       {"normalized", true},
       {"count", n},
       {"type", "VEC2"}},
      {{"bufferView", 3}, {"componentType", kUShort}, {"count", idx.size()}, {"type", "SCALAR"}},
  });
  doc["bufferViews"] = json::array({
      {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 8 * n}, {"byteStride", 8}},
      {{"buffer", 0}, {"byteOffset", 8 * n}, {"byteLength", 4 * n}, {"byteStride", 4}},
      {{"buffer", 0}, {"byteOffset", 12 * n}, {"byteLength", 4 * n}},
      {{"buffer", 0}, {"byteOffset", 16 * n}, {"byteLength", 2 * idx.size()}},
  });
  doc["buffers"] = json::array({{{"uri", "q.bin"}, {"byteLength", bin.size()}}});
  if (declare) {
    doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  }
  return doc;
}

TEST(GltfQuantization, ShortPositionsByteNormalsShortUvsMatchWithinTheStep) {
  const fs::path dir = test::fresh_test_dir("gltf_quant");
  const RefMesh m = grid();
  const Corners ref = reference_corners(dir, m);
  std::string bin;
  const json doc = quantized_doc(m, bin, true);
  write_file(dir / "q.bin", bin);
  write_file(dir / "q.gltf", doc.dump());
  Result<Scene> s = load_scene((dir / "q.gltf").string());
  ASSERT_TRUE(s.ok()) << s.status().message();
  const Corners got = corners(*s);
  EXPECT_LT(max_diff(got.p, ref.p), 0.5f / 4000.0f + 1e-5f);  // half a step of 1/4000
  EXPECT_LT(max_diff(got.n, ref.n), 1.5f / 127.0f);           // byte-normalized, renormalized
  EXPECT_LT(max_diff(got.uv, ref.uv), 0.5f / 32767.0f + 1e-6f);
}

TEST(GltfQuantization, QuantizedTypesWithoutTheExtensionAreRefused) {
  const fs::path dir = test::fresh_test_dir("gltf_quant");
  std::string bin;
  const json doc = quantized_doc(grid(), bin, false);
  write_file(dir / "q.bin", bin);
  write_file(dir / "q.gltf", doc.dump());
  expect_one_line_error(dir / "q.gltf", "KHR_mesh_quantization");
}

TEST(GltfQuantization, TypesOutsideTheExtensionsTableAreRefused) {
  const fs::path dir = test::fresh_test_dir("gltf_quant");
  std::string bin;
  json doc = quantized_doc(grid(), bin, true);
  write_file(dir / "q.bin", bin);
  // NORMAL as normalized UNSIGNED_BYTE: not in KHR_mesh_quantization's table.
  doc["accessors"][1]["componentType"] = kUByte;
  write_file(dir / "q.gltf", doc.dump());
  expect_one_line_error(dir / "q.gltf", "/meshes/0/primitives/0/attributes/NORMAL");
  // Non-normalized SHORT normals neither.
  doc["accessors"][1]["componentType"] = kShort;
  doc["accessors"][1].erase("normalized");
  doc["bufferViews"][1]["byteStride"] = 8;
  doc["bufferViews"][1]["byteLength"] = 8 * 36 - 2;
  write_file(dir / "q.gltf", doc.dump());
  expect_one_line_error(dir / "q.gltf", "NORMAL");
}

// ---- EXT_meshopt_compression ----

struct MeshoptOptions {
  bool sequence = false;  // indices as mode INDICES (UNSIGNED_SHORT), else TRIANGLES (UINT)
  std::function<void(json&, std::string&)> mutate;  // applied to the document and BIN chunk
};

// A GLB: buffer 0 is the BIN chunk of compressed streams, buffer 1 the fallback buffer (no uri,
// no data). Positions FLOAT (filter NONE), normals OCTAHEDRAL 8-bit, uvs EXPONENTIAL.
fs::path write_meshopt(const fs::path& dir, const RefMesh& m, const MeshoptOptions& o = {}) {
  meshopt_encodeVertexVersion(0);
  meshopt_encodeIndexVersion(1);
  const size_t n = m.pos.size(), ni = m.idx.size();
  std::string bin;
  json views = json::array();
  size_t raw = 0;
  auto add = [&](const std::vector<unsigned char>& enc, size_t stride, size_t count,
                 const char* mode, const char* filter) {
    json ext = {{"buffer", 0},          {"byteOffset", bin.size()}, {"byteLength", enc.size()},
                {"byteStride", stride}, {"count", count},           {"mode", mode}};
    if (std::strcmp(filter, "NONE") != 0) ext["filter"] = filter;
    json v = {{"buffer", 1},
              {"byteOffset", raw},
              {"byteLength", stride * count},
              {"extensions", {{"EXT_meshopt_compression", ext}}}};
    if (std::strcmp(mode, "ATTRIBUTES") == 0) v["byteStride"] = stride;
    views.push_back(v);
    bin.append(reinterpret_cast<const char*>(enc.data()), enc.size());
    pad4(bin);
    raw += stride * count;
    while (raw % 4) ++raw;
  };
  auto vertex_stream = [&](const void* data, size_t stride) {
    std::vector<unsigned char> enc(meshopt_encodeVertexBufferBound(n, stride));
    enc.resize(meshopt_encodeVertexBuffer(enc.data(), enc.size(), data, n, stride));
    return enc;
  };
  add(vertex_stream(m.pos.data(), 12), 12, n, "ATTRIBUTES", "NONE");
  std::vector<float> n4;
  for (const glm::vec3& v : m.nrm) n4.insert(n4.end(), {v.x, v.y, v.z, 0.0f});
  std::vector<int8_t> oct(4 * n);
  meshopt_encodeFilterOct(oct.data(), n, 4, 8, n4.data());
  add(vertex_stream(oct.data(), 4), 4, n, "ATTRIBUTES", "OCTAHEDRAL");
  std::vector<uint32_t> expo(2 * n);
  meshopt_encodeFilterExp(expo.data(), n, 8, 20, &m.uv[0].x);
  add(vertex_stream(expo.data(), 8), 8, n, "ATTRIBUTES", "EXPONENTIAL");
  std::vector<unsigned char> ienc;
  if (o.sequence) {
    ienc.resize(meshopt_encodeIndexSequenceBound(ni, n));
    ienc.resize(meshopt_encodeIndexSequence(ienc.data(), ienc.size(), m.idx.data(), ni));
    add(ienc, 2, ni, "INDICES", "NONE");
  } else {
    ienc.resize(meshopt_encodeIndexBufferBound(ni, n));
    ienc.resize(meshopt_encodeIndexBuffer(ienc.data(), ienc.size(), m.idx.data(), ni));
    add(ienc, 4, ni, "TRIANGLES", "NONE");
  }
  json doc = base_doc();
  doc["extensionsUsed"] = {"EXT_meshopt_compression", "KHR_mesh_quantization"};
  doc["extensionsRequired"] = {"EXT_meshopt_compression", "KHR_mesh_quantization"};
  doc["meshes"] = json::array(
      {{{"primitives",
         json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
                       {"indices", 3}}})}}});
  doc["accessors"] = json::array({
      {{"bufferView", 0}, {"componentType", kFloat}, {"count", n}, {"type", "VEC3"}},
      {{"bufferView", 1},
       {"componentType", kByte},
       {"normalized", true},
       {"count", n},
       {"type", "VEC3"}},
      {{"bufferView", 2}, {"componentType", kFloat}, {"count", n}, {"type", "VEC2"}},
      {{"bufferView", 3},
       {"componentType", o.sequence ? kUShort : kUInt},
       {"count", ni},
       {"type", "SCALAR"}},
  });
  doc["bufferViews"] = views;
  pad4(bin);
  doc["buffers"] = json::array(
      {{{"byteLength", bin.size()}},
       {{"byteLength", raw}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}});
  if (o.mutate) o.mutate(doc, bin);
  const fs::path p = dir / "meshopt.glb";
  write_file(p, glb(doc, bin));
  return p;
}

TEST(GltfMeshopt, GlbWithFallbackBufferDecodesToTheMesh) {
  const fs::path dir = test::fresh_test_dir("gltf_meshopt");
  const RefMesh m = grid();
  const Corners ref = reference_corners(dir, m);
  for (bool sequence : {false, true}) {
    Result<Scene> s = load_scene(write_meshopt(dir, m, {sequence, {}}).string());
    ASSERT_TRUE(s.ok()) << s.status().message();
    const Corners got = aligned(corners(*s), ref);
    EXPECT_EQ(max_diff(got.p, ref.p), 0.0f) << "positions are lossless";
    EXPECT_LT(max_diff(got.n, ref.n), 2.0f / 127.0f) << "8-bit octahedral normals";
    EXPECT_LT(max_diff(got.uv, ref.uv), 2e-6f) << "20-bit exponential uvs";
  }
}

// Rotation keys through the QUATERNION filter (normalized SHORT VEC4), key times plain floats.
TEST(GltfMeshopt, QuaternionFilteredRotationKeysDecode) {
  const fs::path dir = test::fresh_test_dir("gltf_meshopt");
  const std::vector<float> times = {0.0f, 0.5f, 1.0f, 1.5f};
  std::vector<float> q4;
  for (int k = 0; k < 4; ++k) {
    const glm::vec3 axis = glm::normalize(glm::vec3(1.0f, 0.3f * k, -0.5f + 0.2f * k));
    const float a = 0.7f * k + 0.2f;
    for (float c : {axis.x * std::sin(a / 2), axis.y * std::sin(a / 2), axis.z * std::sin(a / 2),
                    std::cos(a / 2)})
      q4.push_back(c);
  }
  auto mutate = [&](json& d, std::string& bin) {
    size_t raw = d["buffers"][1]["byteLength"].get<size_t>();
    auto add = [&](const void* data, size_t stride, const char* filter) {
      std::vector<unsigned char> enc(meshopt_encodeVertexBufferBound(4, stride));
      enc.resize(meshopt_encodeVertexBuffer(enc.data(), enc.size(), data, 4, stride));
      json ext = {{"buffer", 0},
                  {"byteOffset", bin.size()},
                  {"byteLength", enc.size()},
                  {"byteStride", stride},
                  {"count", 4},
                  {"mode", "ATTRIBUTES"}};
      if (std::strcmp(filter, "NONE") != 0) ext["filter"] = filter;
      d["bufferViews"].push_back({{"buffer", 1},
                                  {"byteOffset", raw},
                                  {"byteLength", 4 * stride},
                                  {"extensions", {{"EXT_meshopt_compression", ext}}}});
      bin.append(reinterpret_cast<const char*>(enc.data()), enc.size());
      pad4(bin);
      raw += 4 * stride;
    };
    add(times.data(), 4, "NONE");
    std::vector<int16_t> filtered(16);
    meshopt_encodeFilterQuat(filtered.data(), 4, 8, 12, q4.data());
    add(filtered.data(), 8, "QUATERNION");
    d["buffers"][0]["byteLength"] = bin.size();
    d["buffers"][1]["byteLength"] = raw;
    d["accessors"].push_back({{"bufferView", 4},
                              {"componentType", kFloat},
                              {"count", 4},
                              {"type", "SCALAR"},
                              {"min", {0.0}},
                              {"max", {1.5}}});
    d["accessors"].push_back({{"bufferView", 5},
                              {"componentType", kShort},
                              {"normalized", true},
                              {"count", 4},
                              {"type", "VEC4"}});
    d["animations"] = json::array(
        {{{"channels",
           json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", "rotation"}}}}})},
          {"samplers", json::array({{{"input", 4}, {"output", 5}}})}}});
  };
  Result<Scene> s = load_scene(write_meshopt(dir, grid(), {false, mutate}).string());
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_TRUE(s->animation);
  ASSERT_EQ(s->animation->clips.size(), 1u);
  const AnimationSampler& smp = s->animation->clips[0].samplers.at(0);
  EXPECT_EQ(smp.times, times);
  ASSERT_EQ(smp.values.size(), 16u);
  for (int k = 0; k < 4; ++k) {
    float same = 0.0f, flipped = 0.0f;  // q and -q are the same rotation
    for (int c = 0; c < 4; ++c) {
      same = std::max(same, std::abs(smp.values[4 * k + c] - q4[4 * k + c]));
      flipped = std::max(flipped, std::abs(smp.values[4 * k + c] + q4[4 * k + c]));
    }
    EXPECT_LT(std::min(same, flipped), 1e-3f) << "key " << k;  // 12-bit components
  }
}

TEST(GltfMeshopt, HostileStreamsGiveOneErrorLine) {
  const fs::path dir = test::fresh_test_dir("gltf_meshopt");
  const RefMesh m = grid();
  const std::string ext0 = "/bufferViews/0/extensions/EXT_meshopt_compression";
  struct Case {
    const char* what;
    std::function<void(json&, std::string&)> mutate;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {"truncated stream",
       [](json& d, std::string&) {
         auto& e = d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"];
         e["byteLength"] = e["byteLength"].get<int>() / 2;
       },
       ext0 + ": the ATTRIBUTES stream does not decode"},
      {"corrupt header byte", [](json& d, std::string& bin) { bin[0] = 0x00; },
       ext0 + ": the ATTRIBUTES stream does not decode"},
      {"lying count",
       [](json& d, std::string&) {
         d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = 37;
       },
       ext0 + ": 37 elements of 12 bytes decode to 444 bytes"},
      // A count within the stream's last 16-vertex block decodes (the codec cannot tell); the
      // attributes then disagree.
      {"lying count and byteLength",
       [](json& d, std::string&) {
         d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = 40;
         d["bufferViews"][0]["byteLength"] = 480;
         d["accessors"][0]["count"] = 40;
       },
       "/meshes/0/primitives/0/attributes/NORMAL: accessor 1 has 36 elements, POSITION has 40"},
      {"count past the stream",
       [](json& d, std::string&) {
         d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = 100;
         d["bufferViews"][0]["byteLength"] = 1200;
         d["buffers"][1]["byteLength"] = 4000;
         d["accessors"][0]["count"] = 100;
       },
       ext0 + ": the ATTRIBUTES stream does not decode"},
      {"huge count",
       [](json& d, std::string&) {
         d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] =
             uint64_t{1000000000000};
         d["bufferViews"][0]["byteLength"] = uint64_t{12000000000000};
         d["buffers"][1]["byteLength"] = uint64_t{20000000000000};
       },
       ext0 + "/count: 1000000000000 vertices, more than the limit of 25165824"},
      {"compressed bytes in the fallback buffer",
       [](json& d, std::string&) {
         d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["buffer"] = 1;
       },
       "a fallback buffer has none"},
      {"filter on indices",
       [](json& d, std::string&) {
         d["bufferViews"][3]["extensions"]["EXT_meshopt_compression"]["filter"] = "OCTAHEDRAL";
       },
       "/bufferViews/3/extensions/EXT_meshopt_compression/filter: a filter applies only to mode "
       "ATTRIBUTES"},
      {"unknown mode",
       [](json& d, std::string&) {
         d["bufferViews"][3]["extensions"]["EXT_meshopt_compression"]["mode"] = "STRIPS";
       },
       "/bufferViews/3/extensions/EXT_meshopt_compression/mode"},
      {"odd stride",
       [](json& d, std::string&) {
         d["bufferViews"][2]["extensions"]["EXT_meshopt_compression"]["byteStride"] = 6;
       },
       "/bufferViews/2/extensions/EXT_meshopt_compression/byteStride"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    expect_one_line_error(write_meshopt(dir, m, {false, c.mutate}), c.expect);
  }
}

// ---- KHR_draco_mesh_compression ----

struct DracoFile {
  std::string stream;
  int pos_id, nrm_id, uv_id;
  size_t points, faces;
};

DracoFile draco_encode(const RefMesh& m, bool sequential) {
  draco::TriangleSoupMeshBuilder b;
  const int faces = static_cast<int>(m.idx.size() / 3);
  b.Start(faces);
  const int pa = b.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  const int na = b.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
  const int ua = b.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
  for (int f = 0; f < faces; ++f) {
    const uint32_t* t = &m.idx[3 * f];
    b.SetAttributeValuesForFace(pa, draco::FaceIndex(f), &m.pos[t[0]], &m.pos[t[1]], &m.pos[t[2]]);
    b.SetAttributeValuesForFace(na, draco::FaceIndex(f), &m.nrm[t[0]], &m.nrm[t[1]], &m.nrm[t[2]]);
    b.SetAttributeValuesForFace(ua, draco::FaceIndex(f), &m.uv[t[0]], &m.uv[t[1]], &m.uv[t[2]]);
  }
  std::unique_ptr<draco::Mesh> mesh = b.Finalize();
  EXPECT_TRUE(mesh);
  draco::Encoder enc;
  enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
  enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
  enc.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
  if (sequential) enc.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
  draco::EncoderBuffer out;
  const draco::Status st = enc.EncodeMeshToBuffer(*mesh, &out);
  EXPECT_TRUE(st.ok()) << st.error_msg_string();
  DracoFile f;
  f.stream.assign(out.data(), out.size());
  f.pos_id = mesh->attribute(pa)->unique_id();
  f.nrm_id = mesh->attribute(na)->unique_id();
  f.uv_id = mesh->attribute(ua)->unique_id();
  // The decoded counts, which the accessors state.
  draco::DecoderBuffer in;
  in.Init(f.stream.data(), f.stream.size());
  draco::Decoder dec;
  auto decoded = dec.DecodeMeshFromBuffer(&in);
  EXPECT_TRUE(decoded.ok());
  f.points = decoded.value()->num_points();
  f.faces = decoded.value()->num_faces();
  return f;
}

json draco_doc(const DracoFile& f, const std::string& bin_name) {
  json doc = base_doc();
  doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  json ext = {
      {"bufferView", 0},
      {"attributes", {{"POSITION", f.pos_id}, {"NORMAL", f.nrm_id}, {"TEXCOORD_0", f.uv_id}}}};
  doc["meshes"] = json::array(
      {{{"primitives",
         json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
                       {"indices", 3},
                       {"extensions", {{"KHR_draco_mesh_compression", ext}}}}})}}});
  doc["accessors"] = json::array({
      {{"componentType", kFloat}, {"count", f.points}, {"type", "VEC3"}},
      {{"componentType", kFloat}, {"count", f.points}, {"type", "VEC3"}},
      {{"componentType", kFloat}, {"count", f.points}, {"type", "VEC2"}},
      {{"componentType", kUShort}, {"count", 3 * f.faces}, {"type", "SCALAR"}},
  });
  doc["bufferViews"] = json::array({{{"buffer", 0}, {"byteLength", f.stream.size()}}});
  doc["buffers"] = json::array({{{"uri", bin_name}, {"byteLength", f.stream.size()}}});
  return doc;
}

TEST(GltfDraco, SequentialStreamMatchesTheMeshWithinTheQuantizationStep) {
  const fs::path dir = test::fresh_test_dir("gltf_draco");
  const RefMesh m = grid();
  const Corners ref = reference_corners(dir, m);
  const DracoFile f = draco_encode(m, true);
  write_file(dir / "d.bin", f.stream);
  write_file(dir / "d.gltf", draco_doc(f, "d.bin").dump());
  Result<Scene> s = load_scene((dir / "d.gltf").string());
  ASSERT_TRUE(s.ok()) << s.status().message();
  const Corners got = corners(*s);
  // 14 bits over the largest extent (1): half a step is 3.1e-5.
  EXPECT_LT(max_diff(got.p, ref.p), 0.5f / 16383.0f + 1e-6f);
  EXPECT_LT(max_diff(got.n, ref.n), 0.01f);  // 10-bit octahedral
  EXPECT_LT(max_diff(got.uv, ref.uv), 0.5f / 4095.0f + 1e-6f);
  // The same stream in a GLB's BIN chunk: the same mesh.
  json doc = draco_doc(f, "");
  doc["buffers"][0].erase("uri");
  write_file(dir / "d.glb", glb(doc, f.stream));
  Result<Scene> g = load_scene((dir / "d.glb").string());
  ASSERT_TRUE(g.ok()) << g.status().message();
  EXPECT_EQ(max_diff(corners(*g).p, got.p), 0.0f);
}

TEST(GltfDraco, EdgebreakerStreamHasTheMeshsCornersWithinTheStep) {
  const fs::path dir = test::fresh_test_dir("gltf_draco");
  const RefMesh m = grid();
  const DracoFile f = draco_encode(m, false);
  write_file(dir / "d.bin", f.stream);
  write_file(dir / "d.gltf", draco_doc(f, "d.bin").dump());
  Result<Scene> s = load_scene((dir / "d.gltf").string());
  ASSERT_TRUE(s.ok()) << s.status().message();
  const Corners got = corners(*s);
  ASSERT_EQ(got.p.size(), m.idx.size());  // the same triangles, in the coder's order
  for (size_t i = 0; i < got.p.size(); ++i) {
    float best = INFINITY;
    size_t v = 0;
    for (size_t k = 0; k < m.pos.size(); ++k)
      if (glm::length(got.p[i] - m.pos[k]) < best) best = glm::length(got.p[i] - m.pos[k]), v = k;
    EXPECT_LT(best, 1e-4f);
    EXPECT_LT(glm::length(got.uv[i] - m.uv[v]), 5e-4f);
  }
}

TEST(GltfDraco, HostileStreamsGiveOneErrorLine) {
  const fs::path dir = test::fresh_test_dir("gltf_draco");
  const DracoFile f = draco_encode(grid(), false);
  const std::string ep = "/meshes/0/primitives/0/extensions/KHR_draco_mesh_compression";
  struct Case {
    const char* what;
    std::function<void(json&, std::string&)> mutate;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {"truncated stream",
       [](json& d, std::string& s) {
         s.resize(s.size() / 2);
         d["bufferViews"][0]["byteLength"] = s.size();
         d["buffers"][0]["byteLength"] = s.size();
       },
       ep + "/bufferView: "},
      {"garbage stream",
       [](json& d, std::string& s) {
         for (size_t i = 8; i < s.size(); ++i) s[i] = static_cast<char>(i * 37);
       },
       ep + "/bufferView: "},
      {"not draco", [](json& d, std::string& s) { s.assign(s.size(), 'x'); },
       ep + "/bufferView: not a Draco triangle mesh stream"},
      {"lying point count",
       [&](json& d, std::string&) { d["accessors"][0]["count"] = f.points + 1; },
       "/accessors/0/count: "},
      {"lying index count",
       [&](json& d, std::string&) { d["accessors"][3]["count"] = 3 * f.faces - 3; },
       "/meshes/0/primitives/0/indices: "},
      {"huge count", [](json& d, std::string&) { d["accessors"][3]["count"] = 3e12; },
       "more than the limit"},
      {"unknown attribute id",
       [](json& d, std::string&) {
         d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]
          ["NORMAL"] = 99;
       },
       ep + "/attributes/NORMAL: the Draco stream has no attribute 99"},
      {"type mismatch", [](json& d, std::string&) { d["accessors"][2]["type"] = "VEC3"; },
       "TEXCOORD_0"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    json doc = draco_doc(f, "d.bin");
    std::string stream = f.stream;
    c.mutate(doc, stream);
    write_file(dir / "d.bin", stream);
    write_file(dir / "d.gltf", doc.dump());
    expect_one_line_error(dir / "d.gltf", c.expect);
  }
}

// ---- EXT_texture_webp ----

// A smooth 16 x 16 RGB gradient written with OpenImageIO as `file` (.webp or .png).
std::vector<uint8_t> gradient() {
  std::vector<uint8_t> px;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c : {x * 12 + 20, y * 12 + 30, 128 + (x - y) * 3}) px.push_back(uint8_t(c));
  return px;
}
void write_image(const fs::path& file, const std::vector<uint8_t>& px, int w = 16, int h = 16) {
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(file.string());
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("compression", "webp:100");
  ASSERT_TRUE(out->open(file.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
  out->close();
}
std::vector<uint8_t> read_image(const fs::path& file) {
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(file.string());
  EXPECT_TRUE(in);
  if (!in) return {};
  std::vector<uint8_t> px(in->spec().width * in->spec().height * 3);
  in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data());
  return px;
}

std::string base64(const std::string& bin) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bin.size(); i += 3) {
    uint32_t w = uint8_t(bin[i]) << 16;
    if (i + 1 < bin.size()) w |= uint8_t(bin[i + 1]) << 8;
    if (i + 2 < bin.size()) w |= uint8_t(bin[i + 2]);
    for (int s = 0; s < 4; ++s)
      out += i * 8 + s * 6 < bin.size() * 8 ? k[(w >> (18 - 6 * s)) & 63] : '=';
  }
  return out;
}

// A textured quad whose texture 0 reads image `fallback` and, with EXT_texture_webp, `webp`.
json webp_doc(const std::string& fallback_uri, const std::string& webp_uri, bool with_ext) {
  json doc = base_doc();
  const std::vector<float> v = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::vector<float> t = {0, 1, 1, 1, 1, 0, 0, 1, 1, 0, 0, 0};
  std::string bin = bytes_of(v) + bytes_of(t);
  const std::string b64 = base64(bin);
  doc["meshes"] = json::array(
      {{{"primitives",
         json::array({{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"material", 0}}})}}});
  doc["accessors"] = json::array({
      {{"bufferView", 0}, {"componentType", kFloat}, {"count", 6}, {"type", "VEC3"}},
      {{"bufferView", 1}, {"componentType", kFloat}, {"count", 6}, {"type", "VEC2"}},
  });
  doc["bufferViews"] = json::array({{{"buffer", 0}, {"byteLength", 72}},
                                    {{"buffer", 0}, {"byteOffset", 72}, {"byteLength", 48}}});
  doc["buffers"] = json::array(
      {{{"uri", "data:application/octet-stream;base64," + b64}, {"byteLength", bin.size()}}});
  doc["materials"] =
      json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  json tex = {{"source", 0}};
  if (with_ext) {
    tex["extensions"] = {{"EXT_texture_webp", {{"source", 1}}}};
    doc["extensionsUsed"] = {"EXT_texture_webp"};
  }
  doc["textures"] = json::array({tex});
  doc["images"] = json::array({{{"uri", fallback_uri}}, {{"uri", webp_uri}}});
  return doc;
}

const Texture& base_color(const Scene& s) {
  return *s.materials.at(s.instances.at(0).material).textures.at("base_color");
}
float max_texel_diff(const Texture& a, const Texture& b) {
  if (a.width() != b.width() || a.height() != b.height()) return INFINITY;
  float d = 0.0f;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      for (int c = 0; c < 4; ++c)
        d = std::max(d, std::abs(a.fetch(0, x, y)[c] - b.fetch(0, x, y)[c]));
  return d;
}

TEST(GltfWebp, ExtensionSourceIsDecodedLikeOpenImageIoAndFallbackIsUsedWithoutIt) {
  const fs::path dir = test::fresh_test_dir("gltf_webp");
  const std::vector<uint8_t> px = gradient();
  write_image(dir / "tex.webp", px);
  // The fallback is a different (black) image, so which one was read shows.
  write_image(dir / "fallback.png", std::vector<uint8_t>(px.size(), 0));
  // What OpenImageIO decodes from the WebP, stored losslessly.
  write_image(dir / "decoded.png", read_image(dir / "tex.webp"));
  write_file(dir / "webp.gltf", webp_doc("fallback.png", "tex.webp", true).dump());
  write_file(dir / "decoded.gltf", webp_doc("decoded.png", "decoded.png", false).dump());
  write_file(dir / "fallback.gltf", webp_doc("fallback.png", "tex.webp", false).dump());
  Result<Scene> webp = load_scene((dir / "webp.gltf").string());
  ASSERT_TRUE(webp.ok()) << webp.status().message();
  Result<Scene> decoded = load_scene((dir / "decoded.gltf").string());
  ASSERT_TRUE(decoded.ok()) << decoded.status().message();
  Result<Scene> fallback = load_scene((dir / "fallback.gltf").string());
  ASSERT_TRUE(fallback.ok()) << fallback.status().message();
  EXPECT_EQ(max_texel_diff(base_color(*webp), base_color(*decoded)), 0.0f);
  EXPECT_EQ(base_color(*fallback).fetch(0, 5, 5), glm::vec4(0, 0, 0, 1));
  // The lossy coding stays near the gradient (sRGB-decoded values, a few levels of 255).
  std::vector<uint8_t> back = read_image(dir / "tex.webp");
  double err = 0.0;
  for (size_t i = 0; i < px.size(); ++i) err += std::abs(int(back[i]) - int(px[i]));
  EXPECT_LT(err / px.size(), 3.0);
  // Embedded as a data URI: the same texels.
  std::ifstream f(dir / "tex.webp", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(f)), {});
  write_file(dir / "embedded.gltf",
             webp_doc("fallback.png", "data:image/webp;base64," + base64(bytes), true).dump());
  Result<Scene> embedded = load_scene((dir / "embedded.gltf").string());
  ASSERT_TRUE(embedded.ok()) << embedded.status().message();
  EXPECT_EQ(max_texel_diff(base_color(*embedded), base_color(*decoded)), 0.0f);
}

TEST(GltfWebp, TruncatedAndMissingWebpGiveOneErrorLine) {
  const fs::path dir = test::fresh_test_dir("gltf_webp");
  write_image(dir / "tex.webp", gradient());
  write_image(dir / "fallback.png", gradient());
  std::ifstream f(dir / "tex.webp", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), {});
  write_file(dir / "cut.webp", bytes.substr(0, bytes.size() / 2));
  write_file(dir / "cut.gltf", webp_doc("fallback.png", "cut.webp", true).dump());
  expect_one_line_error(dir / "cut.gltf", "/images/1/uri: ");
  json doc = webp_doc("fallback.png", "tex.webp", true);
  doc["textures"][0]["extensions"]["EXT_texture_webp"]["source"] = 7;
  write_file(dir / "bad.gltf", doc.dump());
  expect_one_line_error(dir / "bad.gltf", "/textures/0/extensions/EXT_texture_webp/source");
}

// ---- the CLI renders each kind of file ----

// `relief render FILE` to an EXR: exit 0 and every value finite.
void expect_renders(const fs::path& file) {
  const fs::path exr = file.parent_path() / (file.stem().string() + ".exr");
  const CliRun r = run_shell("timeout 60 " + std::string(RELIEF_CLI) + " render " + file.string() +
                             " --size 64x64 --threads 2 -o " + exr.string());
  ASSERT_EQ(r.code, 0) << r.out;
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(exr.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
  ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
  float lo = INFINITY, hi = -INFINITY;
  for (float v : px) {
    ASSERT_TRUE(std::isfinite(v));
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  EXPECT_GT(hi, lo) << "the mesh is drawn";
}

TEST(GltfDecodeCli, EachEncodingRenders) {
  const fs::path dir = test::fresh_test_dir("gltf_decode_cli");
  const RefMesh m = grid();
  {
    std::string bin;
    const json doc = quantized_doc(m, bin, true);
    write_file(dir / "q.bin", bin);
    write_file(dir / "q.gltf", doc.dump());
    SCOPED_TRACE("KHR_mesh_quantization");
    expect_renders(dir / "q.gltf");
  }
  {
    SCOPED_TRACE("EXT_meshopt_compression");
    expect_renders(write_meshopt(dir, m));
  }
  {
    const DracoFile f = draco_encode(m, false);
    write_file(dir / "d.bin", f.stream);
    write_file(dir / "d.gltf", draco_doc(f, "d.bin").dump());
    SCOPED_TRACE("KHR_draco_mesh_compression");
    expect_renders(dir / "d.gltf");
  }
  {
    write_image(dir / "tex.webp", gradient());
    write_image(dir / "fallback.png", gradient());
    write_file(dir / "w.gltf", webp_doc("fallback.png", "tex.webp", true).dump());
    SCOPED_TRACE("EXT_texture_webp");
    expect_renders(dir / "w.gltf");
  }
}

}  // namespace
}  // namespace relief
