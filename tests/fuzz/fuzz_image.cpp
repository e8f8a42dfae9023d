// libFuzzer target: the image loader path (scene/image_io.h: load_texture with each option and
// read_image, through OpenImageIO). The first byte picks the file extension and the load
// options; the rest is the file. Any input must give an image or a one-line error.
#include <string>

#include "fuzz_util.h"
#include "scene/image_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* const kExt[] = {".png", ".exr", ".tif", ".jpg",
                                     ".hdr", ".tga", ".bmp", ".ppm"};
  const uint8_t sel = data[0];
  relief::fuzz::TempFile file(data + 1, size - 1, kExt[sel & 7]);
  relief::TextureLoadOptions opts;
  opts.first_channel_only = sel & 8;
  opts.height_to_depth = sel & 16;
  opts.color_space =
      (sel & 32) && !opts.height_to_depth ? relief::ColorSpace::kSRGB : relief::ColorSpace::kLinear;
  relief::Result<relief::Texture> t = relief::load_texture(file.path(), opts);
  if (t.ok() && (sel & 64)) t->generate_mips(relief::MipReduce::kAverage);
  if (!t.ok() && t.status().message().find('\n') != std::string::npos) __builtin_trap();
  relief::Result<relief::Image> im = relief::read_image(file.path());
  if (!im.ok() && im.status().message().find('\n') != std::string::npos) __builtin_trap();
  return 0;
}
