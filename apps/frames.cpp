#include "apps/frames.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <regex>

namespace relief::cli {

Result<FrameList> parse_frames(const std::string& text) {
  static const std::regex item_re("^([0-9]{1,7})(-([0-9]{1,7})(:([0-9]{1,7}))?)?$");
  const std::string expected =
      "--frames: expected N, A-B or A-B:S, comma-separated (e.g. 1,5,10-20,30-90:3), with 0 <= "
      "A <= B <= " +
      std::to_string(kMaxFrame) + " and S >= 1, got '" + text + "'";
  FrameList list;
  size_t begin = 0;
  while (true) {
    const size_t comma = text.find(',', begin);
    const std::string item =
        text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    std::smatch m;
    if (!std::regex_match(item, m, item_re)) return Status::usage(expected);
    const int a = std::stoi(m[1]);
    const int b = m[3].matched ? std::stoi(m[3]) : a;
    const int step = m[5].matched ? std::stoi(m[5]) : 1;
    if (b < a || step < 1) return Status::usage(expected);
    const long long n = (static_cast<long long>(b) - a) / step + 1;
    if (static_cast<long long>(list.frames.size()) + n > kMaxFrameCount)
      return Status::usage("--frames: more than " + std::to_string(kMaxFrameCount) +
                           " frames in '" + text + "'");
    for (long long f = a; f <= b; f += step) list.frames.push_back(static_cast<int>(f));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  std::sort(list.frames.begin(), list.frames.end());
  const auto twice = std::adjacent_find(list.frames.begin(), list.frames.end());
  if (twice != list.frames.end())
    return Status::usage("--frames: frame " + std::to_string(*twice) + " is named twice in '" +
                         text + "'");
  return list;
}

Result<Shard> parse_shard(const std::string& text) {
  static const std::regex re("^([0-9]{1,6})/([0-9]{1,6})$");
  std::smatch m;
  const std::string expected =
      "--shard: expected I/N with 0 <= I < N <= 100000 (I counts from 0), got '" + text + "'";
  if (!std::regex_match(text, m, re)) return Status::usage(expected);
  Shard s;
  s.index = std::stoi(m[1]);
  s.count = std::stoi(m[2]);
  if (s.count < 1 || s.count > 100000 || s.index >= s.count) return Status::usage(expected);
  return s;
}

std::vector<int> shard_frames(const FrameList& list, const Shard& s) {
  const long long n = list.count();
  const long long begin = n * s.index / s.count, end = n * (s.index + 1) / s.count;
  return std::vector<int>(list.frames.begin() + begin, list.frames.begin() + end);
}

namespace {

// Walks `name`, calling literal(c) for every plain character (a %% gives one '%') and
// conversion(zero_pad, width) for the frame conversion. Returns false on a bad '%'.
template <class Literal, class Conversion>
bool walk_pattern(const std::string& name, Literal&& literal, Conversion&& conversion) {
  for (size_t i = 0; i < name.size(); ++i) {
    if (name[i] != '%') {
      literal(name[i]);
      continue;
    }
    size_t j = i + 1;
    if (j < name.size() && name[j] == '%') {
      literal('%');
      i = j;
      continue;
    }
    const bool zero = j < name.size() && name[j] == '0';
    if (zero) ++j;
    int width = 0;
    if (j < name.size() && name[j] >= '1' && name[j] <= '9') width = name[j++] - '0';
    if (j >= name.size() || name[j] != 'd' || (zero && width == 0)) return false;
    conversion(zero, width);
    i = j;
  }
  return true;
}

}  // namespace

Status check_frame_pattern(const std::string& name, const std::string& flag, bool& has_pattern) {
  int conversions = 0;
  const bool ok = walk_pattern(
      name, [](char) {}, [&](bool, int) { ++conversions; });
  if (!ok || conversions > 1)
    return Status::usage(flag + ": '" + name +
                         "': a frame name takes one %d, %Nd or %0Nd (N 1..9) and %% for a "
                         "literal %");
  has_pattern = conversions == 1;
  return {};
}

std::string format_frame_name(const std::string& name, int frame) {
  std::string out;
  walk_pattern(
      name, [&](char c) { out += c; },
      [&](bool zero, int width) {
        std::string digits = std::to_string(frame);
        if (static_cast<int>(digits.size()) < width)
          digits.insert(0, width - digits.size(), zero ? '0' : ' ');
        out += digits;
      });
  return out;
}

Result<int> parse_spp(const std::string& text) {
  static const std::regex re("^[0-9]{1,3}$");
  const std::string expected =
      "--spp: expected a square number of samples per pixel (1, 4, 9, ..., 256), got '" + text +
      "'";
  if (!std::regex_match(text, re)) return Status::usage(expected);
  const int n = std::stoi(text);
  for (int k = 1; k <= 16; ++k)
    if (k * k == n) return n;
  return Status::usage(expected);
}

Result<float> parse_exposure(const std::string& text) {
  static const std::regex re("^[-+]?([0-9]+\\.?[0-9]*|\\.[0-9]+)$");
  const std::string expected =
      "--exposure: expected a number of stops in [-24, 24], got '" + text + "'";
  if (!std::regex_match(text, re)) return Status::usage(expected);
  const double ev = std::strtod(text.c_str(), nullptr);
  if (!(ev >= -24.0 && ev <= 24.0)) return Status::usage(expected);
  return static_cast<float>(ev);
}

Image box_downsample(const Image& image, int k) {
  if (k == 1) return image;
  Image out(image.width / k, image.height / k);
  const float inv = 1.0f / static_cast<float>(k * k);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      glm::vec4 sum(0.0f);
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) sum += image.at(x * k + i, y * k + j);
      out.at(x, y) = sum * inv;
    }
  return out;
}

namespace {

template <class Grid>
Grid point_downsample_grid(const Grid& in, int k) {
  if (k == 1) return in;
  Grid out(in.width / k, in.height / k);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) out.at(x, y) = in.at(x * k + k / 2, y * k + k / 2);
  return out;
}

}  // namespace

Image point_downsample(const Image& image, int k) {
  return point_downsample_grid(image, k);
}
Plane point_downsample(const Plane& plane, int k) {
  return point_downsample_grid(plane, k);
}

void apply_exposure(Image& image, float scale) {
  for (glm::vec4& p : image.pixels) {
    p.r *= scale;
    p.g *= scale;
    p.b *= scale;
  }
}

}  // namespace relief::cli
