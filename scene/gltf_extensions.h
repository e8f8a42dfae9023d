// The glTF extensions relief knows, in one table (docs/scene-format.md, "Support table"), and the
// scan that finds what a file uses that relief does not render: extensions it lacks (listed in
// extensionsUsed or present on any object) and material features it ignores. load_gltf prints
// one warning line per finding (or, with GltfLoadOptions::strict, fails on the first);
// `relief render --explain` lists each material's.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace relief {

enum class ExtensionStatus {
  kSupported,  // read and rendered
  kIgnored,    // ignored with one warning line naming it (an error when extensionsRequired)
  kRefused,    // an error wherever it appears
};

struct ExtensionInfo {
  const char* name;
  ExtensionStatus status;
  const char* note;  // one line: what relief does with it
};

// Every extension relief has an opinion on; any other is ignored with a warning.
std::span<const ExtensionInfo> gltf_extensions();
// The table's entry, or null for an extension not in it.
const ExtensionInfo* find_gltf_extension(std::string_view name);
// Whether relief reads `name` (a required extension must be).
bool gltf_extension_supported(std::string_view name);
// "supported", "ignored with a warning", "refused".
const char* extension_status_text(ExtensionStatus s);

// One thing in a file that relief does not render.
struct GltfIgnored {
  std::string pointer;   // JSON pointer of its first use ("/materials/0/extensions/KHR_...")
  std::string feature;   // extension or property name ("KHR_materials_clearcoat", "magFilter")
  std::string what;      // the warning's text after the pointer
  int material = -1;     // the material it belongs to (-1: none)
  bool refused = false;  // an extension the table refuses: an error, not a warning
  bool warn = true;      // false: another material's share of a line printed once
};

// The scan, on a document validate_gltf_document accepted: one entry per extension relief does
// not support (at its first use: materials first, then nodes, meshes, textures, ..., else
// /extensionsUsed/i), one per material and ignored core property (metallic-roughness), one per
// sampler setting relief cannot honour (per material that uses it), one per primitive attribute
// set relief does not read (TEXCOORD_2.., COLOR_1..). Ordered by pointer, deterministic.
std::vector<GltfIgnored> find_ignored_features(const nlohmann::json& doc);

// Whether a material's RELIEF_relief_mapping object `ext` lights it with Blinn-Phong:
// "shading": "blinn_phong", or no "shading" and specular or shininess given (files relief wrote
// before metallic-roughness). The one rule of the loader and of the ignored-property scan.
bool relief_extension_is_blinn_phong(const nlohmann::json& ext);

// "<path>: <pointer>: <what>" on one line (the loader's warning and --strict error text).
std::string ignored_line(const std::string& path, const GltfIgnored& g);

}  // namespace relief
