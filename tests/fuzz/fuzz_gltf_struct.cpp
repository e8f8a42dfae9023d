// libFuzzer target, structure-aware: the input drives a generator of valid-JSON glTF documents
// whose fields are random, deep, of the wrong type or out of range (asset versions, required
// extensions, buffers, views, accessors, meshes, materials with RELIEF_relief_mapping parameters,
// samplers, images, node hierarchies up to 20,000 deep, projective matrices, scene indices), and
// whose URIs name what an attacker would: special files (a FIFO, /dev/zero, /dev/urandom, a
// folder), paths out of the scene's folder (`../`, absolute, percent-encoded, `file:`, a symlink
// that leaves it) and data URIs of random bytes. load_scene must give a Scene or a one-line error,
// never crash, hang (libFuzzer's -timeout) or leak; and it must not read the file outside the
// scene's folder: a scene that loads holds no vertex whose bytes come from that file.
#include <fuzzer/FuzzedDataProvider.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/validate.h"
#include "scene/gltf.h"
#include "scene/image_io.h"

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// The outside file's bytes: floats no scene of ours holds, so a vertex made of them was read
// from outside the folder.
constexpr float kOutsideValue = 12345.678f;

struct Fixture {
  fs::path root, scene_dir;
  Fixture() {
    root = fs::temp_directory_path() / ("relief_fuzz_struct_" + std::to_string(::getpid()));
    scene_dir = root / "scene";
    fs::create_directories(scene_dir / "dir");
    std::vector<float> outside(256, kOutsideValue);
    std::ofstream(root / "outside.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(outside.data()), outside.size() * sizeof(float));
    std::vector<float> inside(256);
    for (size_t i = 0; i < inside.size(); ++i) inside[i] = static_cast<float>(i % 7) * 0.25f;
    std::ofstream(scene_dir / "buf.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(inside.data()), inside.size() * sizeof(float));
    if (!relief::write_image((scene_dir / "ok.png").string(),
                             relief::Image(2, 2, glm::vec4(0.5f, 0.5f, 0.5f, 1.0f)))
             .ok())
      __builtin_trap();
    ::mkfifo((scene_dir / "fifo").c_str(), 0600);
    std::error_code ec;
    fs::create_symlink("../outside.bin", scene_dir / "link_out", ec);
    fs::create_symlink("/dev/zero", scene_dir / "link_zero.png", ec);
  }
};

const Fixture& fixture() {
  static const Fixture* f = new Fixture();
  return *f;
}

const char* const kUris[] = {"buf.bin",
                             "ok.png",
                             "../outside.bin",
                             "%2e%2e/outside.bin",
                             "%2E%2E%2Foutside.bin",
                             "link_out",
                             "link_zero.png",
                             "fifo",
                             "dir",
                             "dir/",
                             "/dev/zero",
                             "/dev/urandom",
                             "/dev/null",
                             "/etc/passwd",
                             "file:///etc/passwd",
                             "http://example.invalid/a.bin",
                             "missing.bin",
                             "a%00b.bin",
                             "\x01\x1b[31m.png",
                             "./buf.bin",
                             "dir/../buf.bin",
                             "dir/../../outside.bin",
                             "",
                             "%",
                             "%zz",
                             "ok.png?x=1",
                             "ok.png#frag"};

class Gen {
 public:
  explicit Gen(FuzzedDataProvider& p) : p_(p) {}

  // An exhausted provider gives 0 for every draw: 0 is always the ordinary choice.
  int pick(int n) { return p_.ConsumeIntegralInRange<int>(0, n - 1); }
  bool coin() { return p_.ConsumeBool(); }
  bool rare() { return pick(8) == 7; }

  // A number: mostly small and valid-looking, sometimes negative, huge, fractional or extreme.
  json number(int typical_max) {
    switch (pick(24)) {
      case 23:
        return -p_.ConsumeIntegralInRange<int>(1, 1000);
      case 22:
        return p_.ConsumeIntegral<int64_t>();
      case 21:
        return p_.ConsumeFloatingPoint<double>();
      case 20:
        return 1e308;
      case 19:
        return p_.ConsumeProbability<double>() * typical_max;
      default:
        return p_.ConsumeIntegralInRange<int>(0, typical_max);
    }
  }
  // Any JSON value, wrong types included.
  json anything(int depth = 0) {
    switch (pick(depth > 2 ? 6 : 8)) {
      case 0:
        return nullptr;
      case 1:
        return coin();
      case 2:
        return p_.ConsumeRandomLengthString(16);
      case 3:
      case 4:
        return number(100);
      case 5:
        return p_.ConsumeFloatingPoint<double>();
      case 6: {
        json a = json::array();
        for (int i = pick(4); i > 0; --i) a.push_back(anything(depth + 1));
        return a;
      }
      default: {
        json o = json::object();
        for (int i = pick(3); i > 0; --i) o[p_.ConsumeRandomLengthString(8)] = anything(depth + 1);
        return o;
      }
    }
  }
  // A valid-looking value most of the time, anything else sometimes.
  json mostly(json good) { return rare() ? anything() : std::move(good); }
  json index(int n) { return mostly(n > 0 && !rare() ? json(pick(n)) : number(n + 2)); }

  std::string uri() {
    if (pick(5) == 4) {
      std::string bytes = p_.ConsumeRandomLengthString(64);
      return "data:application/octet-stream;base64," + base64(bytes);
    }
    return kUris[pick(static_cast<int>(sizeof kUris / sizeof kUris[0]))];
  }

  json document() {
    json d = json::object();
    static const char* const kVersions[] = {"2.0", "2.1", "1.0", "3.0", "banana", "2", "2.0.1"};
    json asset = {{"version", mostly(kVersions[pick(7)])}};
    if (pick(4) == 0) asset["minVersion"] = mostly(kVersions[pick(7)]);
    d["asset"] = mostly(asset);
    static const char* const kExt[] = {"RELIEF_relief_mapping",   "KHR_texture_transform",
                                       "KHR_lights_punctual",     "KHR_materials_clearcoat",
                                       "EXT_meshopt_compression", "KHR_draco_mesh_compression"};
    if (coin()) {
      json used = json::array();
      for (int i = pick(4); i > 0; --i) used.push_back(kExt[pick(6)]);
      d["extensionsUsed"] = mostly(used);
    }
    if (pick(3) == 0)
      d["extensionsRequired"] = coin() ? json(kExt[pick(6)]) : json::array({kExt[pick(6)]});

    const int nbuf = 1 + pick(2) - (rare() ? 1 : 0);
    for (int i = 0; i < nbuf; ++i)
      d["buffers"].push_back(
          rare() || coin() ? json{{"uri", mostly(uri())}, {"byteLength", mostly(number(1024))}}
                           : json{{"uri", "buf.bin"}, {"byteLength", 1024}});
    const int nview = pick(5);
    for (int i = 0; i < nview; ++i) {
      json v = {{"buffer", index(nbuf)}, {"byteLength", mostly(number(1024))}};
      if (coin()) v["byteOffset"] = number(512);
      if (pick(3) == 0) v["byteStride"] = number(64);
      d["bufferViews"].push_back(mostly(v));
    }
    static const int kComponents[] = {5120, 5121, 5122, 5123, 5125, 5126, 5124, 0};
    static const char* const kTypes[] = {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT4", "VEC5"};
    const int nacc = pick(6);
    for (int i = 0; i < nacc; ++i) {
      json a = {{"componentType", mostly(kComponents[pick(8)])},
                {"count", mostly(number(64))},
                {"type", mostly(kTypes[pick(6)])}};
      if (pick(4)) a["bufferView"] = index(nview);
      if (coin()) a["byteOffset"] = number(256);
      if (pick(4) == 0) a["normalized"] = anything();
      if (pick(6) == 0) a["sparse"] = anything();
      d["accessors"].push_back(mostly(a));
    }
    const int nimg = pick(3);
    for (int i = 0; i < nimg; ++i) d["images"].push_back(mostly({{"uri", mostly(uri())}}));
    const int nsamp = pick(2);
    static const int kFilters[] = {9728, 9729, 9984, 9985, 9986, 9987, -1, 0, 33071};
    static const int kWraps[] = {33071, 33648, 10497, 9729, -5};
    for (int i = 0; i < nsamp; ++i) {
      json s = json::object();
      if (coin()) s["magFilter"] = mostly(kFilters[pick(9)]);
      if (coin()) s["minFilter"] = mostly(kFilters[pick(9)]);
      if (coin()) s["wrapS"] = pick(3) ? json(kWraps[pick(5)]) : json("REPEAT");
      if (coin()) s["wrapT"] = mostly(kWraps[pick(5)]);
      d["samplers"].push_back(s);
    }
    const int ntex = pick(3);
    for (int i = 0; i < ntex; ++i)
      d["textures"].push_back(mostly({{"source", index(nimg)}, {"sampler", index(nsamp)}}));
    const int nmat = pick(3);
    static const char* const kTech[] = {
        "relief", "relaxed_cone", "relief_quadric", "parallax", "exact", "cone", "nope"};
    static const char* const kParams[] = {"steps",    "binary_steps",    "depth_scale",
                                          "distance", "offset_limiting", "self_shadow",
                                          "tiling"};
    for (int i = 0; i < nmat; ++i) {
      json m = json::object();
      if (coin()) m["pbrMetallicRoughness"] = {{"baseColorTexture", {{"index", index(ntex)}}}};
      if (coin()) m["normalTexture"] = {{"index", index(ntex)}, {"scale", mostly(1.0)}};
      if (coin()) m["alphaMode"] = mostly("MASK");
      if (coin()) {
        json r = {{"technique", mostly(kTech[pick(7)])},
                  {"depth_texture", {{"index", index(ntex)}}}};
        for (int k = pick(4); k > 0; --k) r[kParams[pick(7)]] = anything();
        m["extensions"]["RELIEF_relief_mapping"] = r;
      }
      d["materials"].push_back(m);
    }
    const int nmesh = pick(3);
    static const char* const kAttr[] = {"POSITION", "NORMAL",     "TEXCOORD_0",
                                        "TANGENT",  "TEXCOORD_1", "COLOR_0"};
    for (int i = 0; i < nmesh; ++i) {
      json mesh = {{"primitives", json::array()}};
      for (int k = pick(3); k > 0; --k) {
        json prim = {{"attributes", json::object()}};
        for (int a = pick(4) + (coin() ? 1 : 0); a > 0; --a)
          prim["attributes"][kAttr[pick(6)]] = index(nacc);
        if (coin()) prim["indices"] = index(nacc);
        if (pick(3) == 0) prim["mode"] = mostly(pick(7));
        if (coin()) prim["material"] = index(nmat);
        if (pick(8) == 0) prim["targets"] = anything();
        mesh["primitives"].push_back(mostly(prim));
      }
      d["meshes"].push_back(mostly(mesh));
    }
    const int ncam = pick(2);
    for (int i = 0; i < ncam; ++i)
      d["cameras"].push_back(
          mostly({{"type", "perspective"},
                  {"perspective", {{"yfov", mostly(0.8)}, {"znear", mostly(0.1)}}}}));
    nodes(d, nmesh, ncam);
    if (pick(4)) d["scenes"] = json::array({{{"nodes", json::array({index(1)})}}});
    if (coin()) d["scene"] = index(2);
    return d;
  }

 private:
  // A chain (each node the parent of the next, up to 20,000 deep), a random forest, or cycles.
  void nodes(json& d, int nmesh, int ncam) {
    const int shape = pick(4);
    const int n = shape == 0 ? p_.ConsumeIntegralInRange<int>(1, 20000) : pick(8) + 1;
    for (int i = 0; i < n; ++i) {
      json node = json::object();
      if (shape == 0) {
        if (i + 1 < n) node["children"] = json::array({i + 1});
      } else {
        for (int k = pick(3); k > 0; --k) node["children"].push_back(index(n + 1));
      }
      if (shape != 0 || i + 1 == n) {
        if (coin()) node["mesh"] = index(nmesh);
        if (pick(4) == 0) node["camera"] = index(ncam);
      }
      if (shape != 0) transform(node);
      d["nodes"].push_back(std::move(node));
    }
  }
  void transform(json& node) {
    switch (pick(5)) {
      case 0: {
        json m = json::array();
        for (int k = 0; k < 16; ++k) m.push_back(k % 5 == 0 ? 1.0 : 0.0);
        if (coin()) m[pick(16)] = number(3);  // projective, singular or NaN-free odd values
        node["matrix"] = mostly(m);
        break;
      }
      case 1:
        node["rotation"] = mostly(json::array({0.0, 0.0, 0.0, pick(2)}));
        break;
      case 2:
        node["scale"] = mostly(json::array({number(2), 1.0, 1.0}));
        break;
      case 3:
        node["translation"] = json::array({number(10), number(10), number(10)});
        break;
      default:
        break;
    }
  }

  static std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
      const unsigned v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8) | uint8_t(in[i + 2]);
      out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
    }
    if (i + 1 == in.size()) {
      const unsigned v = uint8_t(in[i]) << 16;
      out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == in.size()) {
      const unsigned v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8);
      out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
    }
    return out;
  }

  FuzzedDataProvider& p_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const Fixture& fx = fixture();
  FuzzedDataProvider provider(data, size);
  Gen gen(provider);
  const json doc = gen.document();
  const fs::path file = fx.scene_dir / "scene.gltf";
  {
    std::ofstream f(file, std::ios::binary | std::ios::trunc);
    f << doc.dump(-1, ' ', false, json::error_handler_t::replace);
  }
  relief::Result<relief::Scene> scene = relief::load_scene(file.string());
  if (!scene.ok()) {
    const std::string& m = scene.status().message();
    if (m.empty() || m.find('\n') != std::string::npos) __builtin_trap();
    return 0;
  }
  for (const relief::Mesh& mesh : scene->meshes)
    for (const auto& v : mesh.positions)
      if (v.x == kOutsideValue || v.y == kOutsideValue || v.z == kOutsideValue)
        __builtin_trap();  // vertex data read from outside the scene's folder
  return 0;
}
