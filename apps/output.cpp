#include "apps/output.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>

#include "rasterizer/pipeline.h"

namespace relief::cli {

Status write_text_atomic(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) return Status::error(path + ": cannot write (check the directory exists and is writable)");
    f << text;
    f.flush();
    if (!f) {
      std::remove(tmp.c_str());
      return Status::error(path + ": write failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    return Status::error(path + ": cannot rename into place: " + ec.message());
  }
  return {};
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
