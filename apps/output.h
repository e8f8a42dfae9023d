// Small output helpers for the CLI: atomic text files, checking outputs before work, size parsing.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "base/status.h"
#include "rasterizer/image.h"
#include "rasterizer/output_file.h"

namespace relief::cli {

// Writes `text` to `path` atomically (rasterizer/output_file.h: checked writes, fsync, rename).
Status write_text_atomic(const std::string& path, const std::string& text);

// The output files of one command, checked before anything is rendered or baked, so that a bad
// output fails in milliseconds: add() checks that `path` can be written (check_output_path:
// exit 1, "<path>: directory does not exist", "<path>: is a directory", ...), that an image has
// a known extension (exit 2, "<path>: unknown image extension '.x', ...") and that no other
// option names the same file (".", "..", symbolic links resolved; exit 2, "--aov uv: 'a.png' is
// the same file as --output 'a.png'").
class OutputCheck {
 public:
  enum class Kind { kImage, kAny };
  Status add(const std::string& option, const std::string& path, Kind kind);

 private:
  std::map<std::string, std::pair<std::string, std::string>> seen_;  // identity -> option, path
};

// `relief render --alpha`: what the image's alpha channel holds (docs/aovs.md, "Output alpha").
// The frame holds premultiplied linear colour; kNone writes RGB (the colour over black where the
// background is not opaque), kStraight RGBA with colour divided by alpha (0 where alpha is 0),
// kPremultiplied RGBA as held.
enum class OutputAlpha { kNone, kStraight, kPremultiplied };
// "none" | "straight" | "premultiplied"; else a usage error naming --alpha.
Status parse_output_alpha(const std::string& text, OutputAlpha& mode);
// The frame's colour in the form `mode` writes (alpha clamped to [0, 1]).
void apply_output_alpha(Image& image, OutputAlpha mode);
// The channel count `mode` writes: 3 for kNone, else 4.
inline int output_channels(OutputAlpha mode) {
  return mode == OutputAlpha::kNone ? 3 : 4;
}

// The value whose sRGB encoding (as write_image does for 8-bit colour) is exactly byte b: how a
// baker hands the PNG encoder linear bytes (a normal map's) to store as they are.
float srgb_decoded_byte(int b);

// Stages the bytes an encoder made for `file` (encode_image, encode_plane) in `out`, or passes on
// the encoder's error: the bakers that write several files together.
Status stage_encoded(StagedFiles& out, const std::string& file,
                     const Result<std::vector<unsigned char>>& bytes);

// "WxH" -> width and height, each in 1..kMaxTargetSize, at most kMaxTargetPixels in all.
Status parse_size(const std::string& text, int& width, int& height);
inline constexpr long long kMaxTargetPixels = 64LL * 1024 * 1024;

}  // namespace relief::cli
