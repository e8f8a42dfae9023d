// Derived maps baked from a material's depth map on first use, cached in memory and on disk
// (render/derived_maps.h). The cone maps are those of bake/cone_map.h: Dummer 2006 (conservative)
// and Policarpo & Oliveira, GPU Gems 3 ch. 18, 2007 (quad-directional, relaxed).
#include "render/derived_maps.h"

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "bake/cone_map.h"
#include "bake/normal_map.h"
#include "plugins/registry.h"
#include "rasterizer/output_file.h"
#include "rasterizer/safe_file.h"
#include "scene/image_io.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

// Bumped whenever a baker's answer changes, so stale cache files are never read.
constexpr uint32_t kBakeVersion = 2;
constexpr char kMagic[8] = {'R', 'L', 'F', 'C', 'O', 'N', 'E', '1'};

struct ConeSlot {
  const char* name;
  ConeKind kind;
};
constexpr ConeSlot kConeSlots[] = {{"cone_conservative", ConeKind::kConservative},
                                   {"cone_quad", ConeKind::kQuad},
                                   {"cone_relaxed", ConeKind::kRelaxed}};

const ConeSlot* find_cone_slot(const std::string& slot) {
  for (const ConeSlot& c : kConeSlots)
    if (slot == c.name) return &c;
  return nullptr;
}

// FNV-1a, 64 bits.
struct Hasher {
  uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, size_t n) {
    const auto* b = static_cast<const uint8_t*>(p);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
};

struct Header {
  char magic[8];
  uint32_t version, kind, wrap, width, height, channels;
  float max_ratio;
  uint32_t pad = 0;
  uint64_t key, payload_hash;
};

uint64_t payload_hash(const std::vector<float>& v) {
  Hasher h;
  h.bytes(v.data(), v.size() * sizeof(float));
  return h.h;
}

void warn(const std::string& what) {
  std::fprintf(stderr, "relief: warning: %s\n", what.c_str());
}

// Reads a cache file; false (with `why`) when it is missing or does not hold exactly `want`.
// Only a regular file of exactly the expected size is read (a FIFO or a device in its place is
// refused without blocking: rasterizer/safe_file.h).
bool read_cache(const fs::path& path, const Header& want, ConeRatios& out, std::string& why) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec)) && !fs::exists(path, ec)) {
    why.clear();  // simply not there yet
    return false;
  }
  const size_t n = static_cast<size_t>(want.width) * want.height * want.channels;
  const uint64_t expected = sizeof(Header) + static_cast<uint64_t>(n) * 4;
  uint64_t size = 0;
  Result<SafeFd> fd = open_regular_file(path.string(), &size, UINT64_MAX);
  if (!fd.ok()) {
    why = fd.status().message() + ", cone-map cache file ignored (rebaking)";
    return false;
  }
  if (size != expected) {
    why = printable(path.string()) + ": corrupt or stale cone-map cache file, ignored (rebaking)";
    return false;
  }
  Header h;
  out.values.resize(n);
  const auto read_all = [&](void* dst, size_t bytes) {
    size_t got = 0;
    while (got < bytes) {
      const ssize_t r = ::read(fd->get(), static_cast<char*>(dst) + got, bytes - got);
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) return false;
      got += static_cast<size_t>(r);
    }
    return true;
  };
  const bool complete = read_all(&h, sizeof h) && read_all(out.values.data(), n * 4);
  if (!complete || std::memcmp(h.magic, want.magic, 8) != 0 || h.version != want.version ||
      h.kind != want.kind || h.wrap != want.wrap || h.width != want.width ||
      h.height != want.height || h.channels != want.channels || h.max_ratio != want.max_ratio ||
      h.key != want.key || h.payload_hash != payload_hash(out.values)) {
    why = printable(path.string()) + ": corrupt or stale cone-map cache file, ignored (rebaking)";
    return false;
  }
  for (float v : out.values)
    if (!(v >= 0.0f && v <= want.max_ratio)) {
      why = printable(path.string()) +
            ": cone-map cache file holds out-of-range ratios, ignored (rebaking)";
      return false;
    }
  out.width = static_cast<int>(want.width);
  out.height = static_cast<int>(want.height);
  out.channels = static_cast<int>(want.channels);
  return true;
}

// Writes a cache file atomically (rasterizer/output_file.h: checked writes, fsync, rename); a
// warning on failure, never an error.
void write_cache(const fs::path& path, Header h, const ConeRatios& r) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  h.payload_hash = payload_hash(r.values);
  std::string bytes(sizeof h + r.values.size() * 4, '\0');
  std::memcpy(bytes.data(), &h, sizeof h);
  if (!r.values.empty()) std::memcpy(bytes.data() + sizeof h, r.values.data(), r.values.size() * 4);
  const Status s = write_file_atomic(path.string(), bytes);
  if (!s.ok()) warn(s.message() + " (the cone-map cache; continuing without)");
}

std::mutex g_mutex;  // guards the caches, the counters and the progress hook
DerivedMapCounters g_counters;
DerivedMapProgress g_progress;
std::map<uint64_t, TexturePtr>& memory_cache() {
  static auto* m = new std::map<uint64_t, TexturePtr>();
  return *m;
}

static_assert(kMaxEnvironmentTexels == kMaxEnvironmentBakeTexels);
// Bumped whenever the environment bake's answer changes.
constexpr uint32_t kEnvironmentBakeVersion = 1;
std::map<uint64_t, std::shared_ptr<const EnvironmentMaps>>& environment_cache() {
  static auto* m = new std::map<uint64_t, std::shared_ptr<const EnvironmentMaps>>();
  return *m;
}

bool periodic(Wrap w) {
  return w != Wrap::kClamp;
}

// A map kept in the memory cache only (built in milliseconds): the one cached under `key`, else
// build()'s, cached; its --explain note "<slot>: <what>, ..." says which, with the time since `t0`.
// `counted`: in DerivedMapCounters (the normal maps are not: --stats and the render summary count
// the bakes they counted when the glTF loader made the normal maps).
template <class Build>
DerivedMap memory_cached(uint64_t key, const std::string& slot, const std::string& what,
                         std::chrono::steady_clock::time_point t0, bool counted, Build build) {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (auto hit = memory_cache().find(key); hit != memory_cache().end()) {
    if (counted) ++g_counters.memory_hits;
    return DerivedMap{hit->second, slot + ": " + what + ", derived from depth (memory cache)"};
  }
  auto tex = std::make_shared<const Texture>(build());
  memory_cache()[key] = tex;
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (counted) {
    ++g_counters.baked;
    g_counters.bake_ms += ms;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", ms);
  return DerivedMap{tex, slot + ": " + what + ", built from depth in " + buf + " ms"};
}

// The max-mip chain of the material's depth (Texture::dilate_mips): level 0 as it is, then the
// min chain with every texel widened to its 3x3 neighbourhood under the material's wrap. Linear
// in the texel count (a 1024x1024 map takes milliseconds), so it is kept in memory only.
Result<DerivedMap> derive_max_mip(const Material& m, const Texture& depth) {
  const auto t0 = std::chrono::steady_clock::now();
  Hasher key;
  key.bytes(kMaxMipSlotName, std::strlen(kMaxMipSlotName));
  key.value(static_cast<uint32_t>(depth.format()));
  key.value(m.sampler.wrap_u);
  key.value(m.sampler.wrap_v);
  key.value(depth.width(0));
  key.value(depth.height(0));
  key.bytes(depth.level(0).data.data(), depth.level(0).data.size());
  const std::string what = "max-mip chain " + std::to_string(depth.width(0)) + "x" +
                           std::to_string(depth.height(0)) + " (min depth over each footprint)";
  return memory_cached(key.h, kMaxMipSlotName, what, t0, true,
                       [&] { return max_mip_chain(depth, m.sampler.wrap_u, m.sampler.wrap_v); });
}

// The normal map's bake parameters: the material's depth_scale, else its own technique's
// default, else 0.05; wrap when both sampler axes repeat.
float normal_depth_scale(const Material& m) {
  if (auto it = m.params.find("depth_scale"); it != m.params.end()) return it->second;
  if (const PluginDescriptor* p = PluginRegistry::global().find(m.technique)) {
    const int i = param_index(*p, "depth_scale");
    if (i >= 0) return p->params[i].default_value;
  }
  return 0.05f;
}
bool normal_wraps(const Material& m) {
  return m.sampler.wrap_u == Wrap::kRepeat && m.sampler.wrap_v == Wrap::kRepeat;
}

// The normal map of the material's depth (bake/normal_map.h), memory-cached by the depth texels,
// depth_scale and wrap.
Result<DerivedMap> derive_normal(const Material& m, const Texture& depth) {
  const auto t0 = std::chrono::steady_clock::now();
  const float depth_scale = normal_depth_scale(m);
  const bool wrap = normal_wraps(m);
  Hasher key;
  key.bytes("normal", 6);
  key.value(static_cast<uint32_t>(depth.format()));
  key.value(depth_scale);
  key.value(wrap);
  key.value(depth.width(0));
  key.value(depth.height(0));
  key.bytes(depth.level(0).data.data(), depth.level(0).data.size());
  char scale[32];
  std::snprintf(scale, sizeof scale, "%g", static_cast<double>(depth_scale));
  const std::string what = "normal map " + std::to_string(depth.width(0)) + "x" +
                           std::to_string(depth.height(0)) + (wrap ? " (wrap" : " (clamp") +
                           ", depth_scale " + scale + ")";
  return memory_cached(key.h, "normal", what, t0, false,
                       [&] { return normal_map_from_depth(depth, depth_scale, wrap); });
}

const Texture* usable_depth(const Material& m) {
  auto it = m.textures.find("depth");
  return it == m.textures.end() || !it->second || it->second->empty() ? nullptr : it->second.get();
}

bool same_texture(const Texture& a, const Texture& b) {
  if (a.format() != b.format() || a.levels() != b.levels() || a.color_space() != b.color_space())
    return false;
  for (int l = 0; l < a.levels(); ++l)
    if (a.level(l).data != b.level(l).data) return false;
  return true;
}

}  // namespace

bool derives_normal_map(const Material& m, const std::string& slot) {
  if (slot != "normal" || !m.normal_from_depth || !m.textures.count("depth")) return false;
  auto it = m.textures.find("normal");
  return it == m.textures.end() || !it->second;
}

Result<TexturePtr> derived_normal_map(const Material& m) {
  Result<DerivedMap> d = derive_map(m, "normal");
  if (!d.ok()) return d.status();
  return d->texture;
}

void drop_derivable_normal_maps(Scene& scene) {
  for (Material& m : scene.materials) {
    auto normal = m.textures.find("normal");
    const Texture* depth = usable_depth(m);
    if (normal == m.textures.end() || !normal->second || !depth || m.normal_scale != 1.0f ||
        m.uv_maps.count("normal"))
      continue;
    if (!same_texture(*normal->second,
                      normal_map_from_depth(*depth, normal_depth_scale(m), normal_wraps(m))))
      continue;
    m.textures.erase(normal);
    m.normal_from_depth = true;
  }
}

bool is_derived_slot(const std::string& slot) {
  return find_cone_slot(slot) != nullptr || slot == kMaxMipSlotName;
}

Texture max_mip_chain(const Texture& depth, Wrap wrap_u, Wrap wrap_v) {
  Texture t(depth.format(), depth.width(0), depth.height(0), depth.level(0).data.data(),
            depth.color_space());
  t.generate_mips(MipReduce::kMin);
  t.dilate_mips(MipReduce::kMin, wrap_u, wrap_v);
  return t;
}

std::string derived_map_cache_dir() {
  if (const char* e = std::getenv("RELIEF_CACHE_DIR"); e && *e)
    return std::strcmp(e, "none") == 0 ? "" : std::string(e);
  if (const char* e = std::getenv("XDG_CACHE_HOME"); e && *e) return std::string(e) + "/relief";
  if (const char* e = std::getenv("HOME"); e && *e) return std::string(e) + "/.cache/relief";
  return "";
}

DerivedMapCounters derived_map_counters() {
  std::lock_guard<std::mutex> lock(g_mutex);
  return g_counters;
}

void set_derived_map_progress(DerivedMapProgress progress) {
  std::lock_guard<std::mutex> lock(g_mutex);
  g_progress = std::move(progress);
}

void clear_derived_map_memory_cache() {
  std::lock_guard<std::mutex> lock(g_mutex);
  memory_cache().clear();
  environment_cache().clear();
}

Result<DerivedEnvironment> derived_environment(const Image& equirect,
                                               const EnvironmentBakeOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  Hasher key;
  key.value(kEnvironmentBakeVersion);
  key.value(equirect.width);
  key.value(equirect.height);
  for (int v : {options.specular_size, options.specular_levels, options.specular_samples,
                options.lut_size, options.lut_samples})
    key.value(v);
  key.bytes(equirect.pixels.data(), equirect.pixels.size() * sizeof(glm::vec4));
  const std::string what =
      "environment " + std::to_string(equirect.width) + "x" + std::to_string(equirect.height) +
      " (SH9, specular " + std::to_string(options.specular_size) + "x" +
      std::to_string(options.specular_size) + " in " + std::to_string(options.specular_levels) +
      " roughness levels, LUT " + std::to_string(options.lut_size) + "x" +
      std::to_string(options.lut_size) + ")";
  std::lock_guard<std::mutex> lock(g_mutex);
  if (auto hit = environment_cache().find(key.h); hit != environment_cache().end())
    return DerivedEnvironment{hit->second, what + " from the memory cache"};
  Result<EnvironmentMaps> baked = bake_environment(equirect, options);
  if (!baked.ok()) return baked.status();
  auto maps = std::make_shared<const EnvironmentMaps>(std::move(*baked));
  environment_cache()[key.h] = maps;
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", ms);
  return DerivedEnvironment{maps, what + " baked in " + std::string(buf) + " ms"};
}

Result<DerivedMap> derive_map(const Material& m, const std::string& slot) {
  const ConeSlot* cs = find_cone_slot(slot);
  CHECK(cs != nullptr || slot == kMaxMipSlotName || slot == "normal");
  const Texture* depth_map = usable_depth(m);
  if (!depth_map) return Status::error("'" + slot + "' map: no 'depth' texture to bake it from");
  const Texture& depth = *depth_map;
  if (slot == "normal") return derive_normal(m, depth);
  if (!cs) return derive_max_mip(m, depth);
  ConeBakeOptions o;
  o.kind = cs->kind;
  o.max_ratio = 1.0f;
  o.wrap = periodic(m.sampler.wrap_u) && periodic(m.sampler.wrap_v);
  o.bilinear = true;  // what the kernels need (shaders_cpp/cone.h)
  const int w = depth.width(0), h = depth.height(0);

  Header want{};
  std::memcpy(want.magic, kMagic, 8);
  want.version = kBakeVersion;
  want.kind = static_cast<uint32_t>(o.kind);
  want.wrap = o.wrap ? 1 : 0;
  want.width = static_cast<uint32_t>(w);
  want.height = static_cast<uint32_t>(h);
  want.channels = o.kind == ConeKind::kQuad ? 4 : 1;
  want.max_ratio = o.max_ratio;
  Hasher key;
  key.bytes(kMagic, 8);
  key.value(want.version);
  key.value(want.kind);
  key.value(want.wrap);
  key.value(want.width);
  key.value(want.height);
  key.value(want.max_ratio);
  key.value(o.bilinear);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) key.value(depth.fetch_r(0, x, y));
  want.key = key.h;

  const std::string what = std::string(cone_kind_name(o.kind)) + " cone map " + std::to_string(w) +
                           "x" + std::to_string(h) + (o.wrap ? " (wrap)" : " (clamp)");
  // One bake at a time: a second material with the same depth waits and then hits the cache.
  std::lock_guard<std::mutex> lock(g_mutex);
  if (auto hit = memory_cache().find(want.key); hit != memory_cache().end()) {
    ++g_counters.memory_hits;
    return DerivedMap{hit->second, slot + ": " + what + ", derived from depth (memory cache)"};
  }

  const std::string dir = derived_map_cache_dir();
  char name[64];
  std::snprintf(name, sizeof name, "cone-%s-%016llx.bin", cone_kind_name(o.kind),
                static_cast<unsigned long long>(want.key));
  const fs::path file = dir.empty() ? fs::path() : fs::path(dir) / name;
  ConeRatios ratios;
  std::string note;
  std::string why;
  const auto ms_since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
  };
  const auto t_read = std::chrono::steady_clock::now();
  if (!dir.empty() && read_cache(file, want, ratios, why)) {
    ++g_counters.disk_hits;
    g_counters.cache_ms += ms_since(t_read);
    note = slot + ": " + what + ", derived from depth (disk cache " + file.string() + ")";
  } else {
    if (!why.empty()) warn(why);
    const std::string shown = what + " of material '" + m.name + "'";
    if (g_progress) {
      g_progress(shown, 0.0f);
      o.progress = [&shown](float f) { g_progress(shown, f); };
    }
    const auto t0 = std::chrono::steady_clock::now();
    ratios = bake_cone_ratios(depth, o);
    const double ms = ms_since(t0);
    ++g_counters.baked;
    g_counters.bake_ms += ms;
    char secs[32];
    std::snprintf(secs, sizeof secs, "%.2f", ms / 1000.0);
    note = slot + ": " + what + ", baked from depth in " + secs + " s";
    if (!dir.empty()) {
      const auto t_write = std::chrono::steady_clock::now();
      write_cache(file, want, ratios);
      g_counters.cache_ms += ms_since(t_write);
      note += " (cached in " + dir + ")";
    }
  }
  auto tex = std::make_shared<const Texture>(cone_ratios_to_texture(ratios, true));
  memory_cache()[want.key] = tex;
  return DerivedMap{tex, note};
}

}  // namespace relief
