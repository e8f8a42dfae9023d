// A strict pass over a glTF document's JSON, before tinygltf's model is read (scene/gltf.cpp):
// tinygltf 2.7 drops, defaults or coerces much of what it does not like (a string where an index
// belongs, a negative byteOffset, a wrap mode given as a word), so the schema is checked here on
// the text as the file has it. Limits: docs/errors.md, "Limits".
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

#include "base/status.h"

namespace relief {

// The deepest nesting of JSON arrays and objects a glTF document may have. glTF itself needs
// about 8; the rest is headroom for extras. Parsers and converters that recurse (tinygltf turns
// extras into its own values recursively) never see deeper text.
inline constexpr int kMaxJsonNesting = 512;

// `key` as one reference token of a JSON pointer (RFC 6901: '~' as "~0", '/' as "~1").
std::string pointer_token(std::string_view key);

// Message text kept on one line: bytes below 0x20 and 0x7f as \xNN; longer than `max` bytes,
// its first `max` bytes and "...".
std::string one_line_text(std::string_view s, size_t max);

// Scans JSON text without parsing it (strings and escapes skipped) and refuses nesting deeper than
// kMaxJsonNesting: "<path>: JSON nesting deeper than 512 levels (line 3, column 700)".
Status check_json_nesting(std::string_view text, const std::string& path);

// Checks the document against the glTF 2.0 schema for every property relief reads: types, ranges,
// enums (GL filter, wrap, component and mode values), indices into their arrays, asset.version
// ("2.x") and minVersion (<= 2.0), extensionsRequired (each used and supported), node matrices
// (affine, finite, invertible), buffer view / accessor extents and alignment; the node hierarchy
// (a forest, no cycle, at most kMaxNodeDepth deep, scene roots are roots); and the default
// scene's instances and triangles against kMaxSceneInstances and kMaxSceneTriangles, from the
// JSON counts, before anything is decoded. Errors: "<path>: <JSON pointer>: <what>", one line.
Status validate_gltf_document(const nlohmann::json& doc, const std::string& path);

// check_json_nesting, then validate_gltf_document on the parsed text. Text that does not parse is
// left to the caller's parser to report (ok here). load_gltf calls it before tinygltf sees the
// text, so that tinygltf's own messages (no JSON pointer) are not the ones a user meets.
Status validate_gltf_text(std::string_view text, const std::string& path);

}  // namespace relief
