#include "apps/output.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <regex>

#include "rasterizer/output_file.h"
#include "rasterizer/pipeline.h"
#include "rasterizer/safe_file.h"
#include "scene/image_io.h"

namespace relief::cli {

float srgb_decoded_byte(int b) {
  const double c = b / 255.0;
  return static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

Status stage_encoded(StagedFiles& out, const std::string& file,
                     const Result<std::vector<unsigned char>>& bytes) {
  if (!bytes.ok()) return bytes.status();
  return out.stage(file,
                   std::string_view(reinterpret_cast<const char*>(bytes->data()), bytes->size()));
}

Status write_text_atomic(const std::string& path, const std::string& text) {
  return write_file_atomic(path, text);
}

Status OutputCheck::add(const std::string& option, const std::string& path, Kind kind) {
  struct stat st;  // "dir/" names a folder, not a file: say so when it is one
  if (!path.empty() && path.back() == '/' && ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
    return Status::error(printable(path) + ": is a directory (" + option + " takes a file name)");
  RELIEF_RETURN_IF_ERROR(check_output_path(path));
  if (kind == Kind::kImage) RELIEF_RETURN_IF_ERROR(check_image_extension(path));
  const std::string id = output_identity(path);
  auto [it, fresh] = seen_.emplace(id, std::make_pair(option, path));
  if (!fresh)
    return Status::usage(option + ": '" + printable(path) + "' is the same file as " +
                         it->second.first + " '" + printable(it->second.second) + "'");
  return {};
}

Status parse_output_alpha(const std::string& text, OutputAlpha& mode) {
  if (text == "none")
    mode = OutputAlpha::kNone;
  else if (text == "straight")
    mode = OutputAlpha::kStraight;
  else if (text == "premultiplied")
    mode = OutputAlpha::kPremultiplied;
  else
    return Status::usage("--alpha: expected none, straight or premultiplied, got '" +
                         printable(text) + "'");
  return {};
}

void apply_output_alpha(Image& image, OutputAlpha mode) {
  for (glm::vec4& p : image.pixels) {
    const float a = p.a >= 0.0f ? std::min(p.a, 1.0f) : 0.0f;  // NaN: 0
    if (mode == OutputAlpha::kStraight) {
      const float inv = a > 0.0f ? 1.0f / a : 0.0f;
      p = glm::vec4(glm::vec3(p) * inv, a);
    } else {
      p.a = mode == OutputAlpha::kNone ? 1.0f : a;
    }
  }
}

Status parse_size(const std::string& text, int& width, int& height) {
  static const std::regex re("^([0-9]{1,6})x([0-9]{1,6})$");
  std::smatch m;
  if (!std::regex_match(text, m, re))
    return Status::usage("--size: expected WxH (e.g. 800x600), got '" + text + "'");
  const long w = std::stol(m[1]), h = std::stol(m[2]);
  if (w < 1 || h < 1 || w > kMaxTargetSize || h > kMaxTargetSize)
    return Status::usage("--size: each side must be in 1.." + std::to_string(kMaxTargetSize) +
                         ", got '" + text + "'");
  if (static_cast<long long>(w) * h > kMaxTargetPixels)
    return Status::usage("--size: " + text + " is more than " + std::to_string(kMaxTargetPixels) +
                         " pixels (the documented limit)");
  width = static_cast<int>(w);
  height = static_cast<int>(h);
  return {};
}

}  // namespace relief::cli
