// Derived maps: the maps a technique needs that the scene does not supply, made from the
// material's depth map during preparation and cached (DESIGN.md, "One frame, as data", step 2:
// "Prepare (cached): ... the maps each technique needs (cone map, normal map)").
//
// A plugin asks for one by naming a texture slot after it (docs/plugins.md):
//   "cone_conservative", "cone_quad", "cone_relaxed": bake/cone_map.h's conservative and
//   quad-directional cone maps safe for the bilinear surface (`bilinear`, what the cone kernels
//   need never to pass the first hit) and relaxed cone maps, of the material's "depth" texture
//   (level 0, ratios clamped at 1, min-mips; wrap when both sampler axes repeat or mirror --
//   mirror is baked as repeat -- and clamp otherwise).
//   "depth_max_mip": the material's depth level 0 with a min chain widened for bilinear reads
//   (rasterizer/texture.h Texture::dilate_mips), what the searches' `lod=max-mip` reads: at any
//   LOD it never lies below the level-0 surface over the read's footprint. Built in
//   milliseconds, so cached in memory only.
//   "normal", for a material that asks for it (Material::normal_from_depth: glTF files unless
//   they say normal_from_depth false) and has no normal texture: bake/normal_map.h's
//   normal_map_from_depth of the depth texture, with the material's depth_scale (else the default
//   of its own technique, Material::technique, whatever --technique says; else 0.05) and wrapping
//   when both sampler axes repeat (mirror clamps). Cached in memory only, like the max-mips, and
//   not counted in DerivedMapCounters (--stats counts the bakes it did when the glTF loader made
//   these maps).
// A material that supplies a texture under that name is used as it is. Otherwise the map comes
// from, in order: the process's memory cache; the disk cache; a bake (all cores), which is then
// stored in both. The caches are keyed by a 64-bit hash of the depth texels, their size, the kind
// and the bake parameters, and a version of the baker. The disk cache lives in
// $RELIEF_CACHE_DIR (the value "none" turns it off), else $XDG_CACHE_HOME/relief, else
// $HOME/.cache/relief. A missing, corrupt or unwritable cache file is a one-line warning on
// stderr and a rebake, never an error.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "bake/environment_bake.h"
#include "base/status.h"
#include "rasterizer/texture.h"
#include "scene/scene.h"

namespace relief {

struct DerivedMap {
  TexturePtr texture;
  std::string note;  // one line for --explain: where the map came from and what it cost
};

inline constexpr const char* kMaxMipSlotName = "depth_max_mip";

// Whether `slot` names a map derive_map() can make for any material with a depth map (the cone
// maps and "depth_max_mip").
bool is_derived_slot(const std::string& slot);
// Whether `material` gets slot `slot` from derive_map() as its normal map: "normal", asked for
// (normal_from_depth), a depth texture and no normal texture of its own.
bool derives_normal_map(const Material& material, const std::string& slot);

// The derived map for `slot` of `material`. Error: the material has no usable "depth" texture.
Result<DerivedMap> derive_map(const Material& material, const std::string& slot);

// The "depth_max_mip" chain of a depth map: level 0 of `depth` in its own format, then
// generate_mips(kMin) and dilate_mips(kMin, wrap_u, wrap_v) (rasterizer/texture.h).
Texture max_mip_chain(const Texture& depth, Wrap wrap_u, Wrap wrap_v);

// The normal map derive_map() makes for `material` (derives_normal_map), from the memory cache.
// Error: the material has no usable "depth" texture.
Result<TexturePtr> derived_normal_map(const Material& material);

// Each material whose normal map is the one derive_map() would make (normal_scale 1, no uv map of
// its own, the same texels) drops it and asks for the derived one (normal_from_depth): what
// `relief export` does before save_gltf, so that the file leaves the derived map out.
void drop_derivable_normal_maps(Scene& scene);

// The disk-cache folder as the environment sets it ("" when there is none).
std::string derived_map_cache_dir();

// What derive_map() did since the process started (`relief render` reports each frame's share).
struct DerivedMapCounters {
  int baked = 0;          // maps baked
  int memory_hits = 0;    // maps the memory cache held
  int disk_hits = 0;      // maps read from the disk cache
  double bake_ms = 0.0;   // wall time of the bakes (not of cache reads)
  double cache_ms = 0.0;  // wall time of disk-cache reads and writes
};
DerivedMapCounters derived_map_counters();

// Called around every bake, on the thread calling derive_map, one bake at a time: fraction 0
// before it starts, non-decreasing fractions while it runs, 1 at its end. `what` names the map
// and the material ("relaxed cone map 512x512 (wrap) of material 'bricks'"). Empty: none.
using DerivedMapProgress = std::function<void(const std::string& what, float fraction)>;
void set_derived_map_progress(DerivedMapProgress progress);

// The image-based light of an equirectangular environment (bake/environment_bake.h), baked once
// per content and kept in the memory cache, keyed by a 64-bit hash of the texels, their size, the
// options and the baker's version. Not on disk: the disk format holds cone ratios, and the bake
// of a 2048x1024 map takes about 1 s on two cores (docs/environment.md).
struct DerivedEnvironment {
  std::shared_ptr<const EnvironmentMaps> maps;
  std::string note;  // one line for --explain: baked (and in how many ms) or from the cache
};
Result<DerivedEnvironment> derived_environment(const Image& equirect,
                                               const EnvironmentBakeOptions& options = {});

// Forgets the memory cache (tests).
void clear_derived_map_memory_cache();

}  // namespace relief
