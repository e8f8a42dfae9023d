// Small output helpers for the CLI: atomic text files, size parsing.
#pragma once

#include <string>

#include "rasterizer/status.h"

namespace relief::cli {

// Writes `text` to `path` through a temporary file in the same folder and a rename.
Status write_text_atomic(const std::string& path, const std::string& text);
// "WxH" -> width and height, each in 1..kMaxTargetSize, at most kMaxTargetPixels in all.
Status parse_size(const std::string& text, int& width, int& height);
inline constexpr long long kMaxTargetPixels = 64LL * 1024 * 1024;

}  // namespace relief::cli
