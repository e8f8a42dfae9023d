// Compressed and quantized glTF (docs/scene-format.md, "Compression and quantization"):
// KHR_mesh_quantization component types, EXT_meshopt_compression buffer views (libmeshoptimizer),
// KHR_draco_mesh_compression primitives (libdraco) and EXT_texture_webp images. load_gltf hands
// tinygltf a copy of the JSON it can read (tinygltf_json), then decodes into the model it built
// (decode_compressed), so the Reader sees plain accessors over plain buffer views.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/status.h"

namespace tinygltf {
class Model;
}

namespace relief {

inline constexpr const char* kMeshQuantization = "KHR_mesh_quantization";
inline constexpr const char* kMeshoptCompression = "EXT_meshopt_compression";
inline constexpr const char* kDracoCompression = "KHR_draco_mesh_compression";
inline constexpr const char* kTextureWebp = "EXT_texture_webp";

// glTF's name of an accessor component type (5120 "BYTE" ... 5126 "FLOAT"); null for another.
const char* gltf_component_type_name(int component_type);

// The component types glTF allows for vertex attribute `semantic` (POSITION, NORMAL, TANGENT,
// TEXCOORD_n; in a morph target when `morph_target`), with KHR_mesh_quantization's when
// `quantized`: positive as stored, negative normalized. Empty for any other semantic.
std::vector<int> attribute_component_types(std::string_view semantic, bool morph_target,
                                           bool quantized);
// "FLOAT, normalized BYTE, ..." for such a list.
std::string component_types_text(const std::vector<int>& ctypes);

// The JSON text to give tinygltf in place of `json_text`, or nullopt when it can read it as it
// is: a meshopt fallback buffer without a uri gets one placeholder byte (tinygltf would read the
// GLB's BIN chunk or fail), a Draco primitive's indices accessor without a buffer view gets the
// primitive's (tinygltf refuses it otherwise; decode_compressed replaces it), and an image data
// URI of image/webp is handed over as one tinygltf decodes. `json_text` passed validation.
std::optional<std::string> tinygltf_json(const std::string& json_text);

// A GLB with its JSON chunk replaced by `json_text` (the other chunks kept). `glb` has a checked
// header and a JSON chunk.
std::string glb_with_json(const std::string& glb, const std::string& json_text);

// Decodes, in `model` as tinygltf built it from tinygltf_json's text: every buffer view with
// EXT_meshopt_compression (into a new buffer the view then points at), then every primitive with
// KHR_draco_mesh_compression (its accessors then point at new buffer views of the decoded,
// dequantized data). Every count and size is checked against the limits (docs/errors.md) before
// anything is allocated; an error is one line, "<shown>: <JSON pointer>: <what>".
Status decode_compressed(tinygltf::Model& model, const std::string& shown);

// The image a texture reads: EXT_texture_webp's source when the texture has the extension, else
// its source (-1 for none). Sets `pointer` to the JSON pointer of the index used.
int texture_source(const tinygltf::Model& model, int texture, std::string* pointer);

}  // namespace relief
