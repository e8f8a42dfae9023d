// glTF input, textures (scene/gltf_internal.h): glTF 2.0 specification section 3.8 (textures,
// images, samplers) and KHR_texture_transform. textureInfo references and their transforms,
// samplers as one SamplerState, images decoded through scene/image_io (an external file under
// the scene folder rule, else embedded PNG, JPEG or WebP bytes; EXT_texture_webp's source first),
// or a float texture's exact texels (RELIEF_relief_mapping, docs/scene-format.md).
#include <cmath>
#include <cstring>
#include <memory>

#include "scene/gltf.h"
#include "scene/gltf_decode.h"
#include "scene/gltf_internal.h"

namespace relief::gltf_detail {

// A float texture's exact texels (`relief export`, docs/scene-format.md, "Float textures"):
// the texture's RELIEF_relief_mapping {texels: buffer view, format, width, height}; null when
// the texture has none (its image is then decoded as usual).
Result<TexturePtr> Reader::exact_texels(const TexRef& r, TexUse use, bool mipmapped) {
  const std::string tp = "/textures/" + std::to_string(r.index);
  Result<json> ext = extension(m_.textures[r.index].extensions_json_string, kReliefExtension, tp);
  if (!ext.ok()) return ext.status();
  if (ext->is_null()) return TexturePtr();
  const auto key = std::make_tuple(-1 - r.index, static_cast<int>(use), mipmapped);
  if (auto it = textures_.find(key); it != textures_.end()) return it->second;
  const std::string ep = tp + "/extensions/" + kReliefExtension;
  RELIEF_RETURN_IF_ERROR(check_keys(*ext, ep, {"texels", "format", "width", "height"}));
  for (const char* k : {"texels", "format", "width", "height"})
    if (!ext->contains(k)) return fail(ep, std::string("missing '") + k + "'");
  int view = -1, w = 0, h = 0;
  RELIEF_RETURN_IF_ERROR(get_int(*ext, "texels", ep, view, 0, 1 << 30));
  RELIEF_RETURN_IF_ERROR(get_int(*ext, "width", ep, w, 1, kMaxImageSide));
  RELIEF_RETURN_IF_ERROR(get_int(*ext, "height", ep, h, 1, kMaxImageSide));
  if (static_cast<long long>(w) * h > kMaxTextureTexels)
    return fail(ep, std::to_string(w) + "x" + std::to_string(h) + " is more than " +
                        std::to_string(kMaxTextureTexels) + " texels");
  const json& f = (*ext)["format"];
  TexFormat format = TexFormat::kR32F;
  if (f == "R32F")
    format = TexFormat::kR32F;
  else if (f == "R16F")
    format = TexFormat::kR16F;
  else if (f == "RGBA16F")
    format = TexFormat::kRGBA16F;
  else
    return fail(ep + "/format", "expected R32F, R16F or RGBA16F, got " + f.dump());
  if (use == TexUse::kHeight)
    return fail(ep, "exact texels hold depth: depth_is_height does not apply to them");
  if (view >= static_cast<int>(m_.bufferViews.size()))
    return fail(ep + "/texels", "buffer view " + std::to_string(view) + " does not exist");
  const tinygltf::BufferView& bv = m_.bufferViews[view];
  const size_t bytes = static_cast<size_t>(w) * h * format_bytes_per_texel(format);
  if (bv.byteLength != bytes)
    return fail(ep + "/texels", "buffer view " + std::to_string(view) + " has " +
                                    std::to_string(bv.byteLength) + " bytes, " + std::to_string(w) +
                                    "x" + std::to_string(h) + " " + format_name(format) +
                                    " needs " + std::to_string(bytes));
  if (bv.buffer < 0 || bv.buffer >= static_cast<int>(m_.buffers.size()) ||
      bv.byteOffset + bv.byteLength > m_.buffers[bv.buffer].data.size())
    return fail(ep + "/texels", "buffer view " + std::to_string(view) + " lies outside its buffer");
  const uint8_t* src = m_.buffers[bv.buffer].data.data() + bv.byteOffset;
  // every value finite: a float's exponent below all ones, a half's (bits 10-14) likewise
  const size_t value_bytes = format == TexFormat::kR32F ? 4 : 2;
  for (size_t i = 0; i < bytes; i += value_bytes) {
    bool finite;
    if (value_bytes == 4) {
      float v;
      std::memcpy(&v, src + i, 4);
      finite = std::isfinite(v);
    } else {
      uint16_t h16;
      std::memcpy(&h16, src + i, 2);
      finite = (h16 & 0x7C00u) != 0x7C00u;
    }
    if (!finite)
      return fail(ep + "/texels", "value " + std::to_string(i / value_bytes) + " is not finite");
  }
  Texture t(format, w, h, src, use == TexUse::kColor ? ColorSpace::kSRGB : ColorSpace::kLinear);
  if (mipmapped) t.generate_mips(use == TexUse::kCone ? MipReduce::kMin : MipReduce::kAverage);
  TexturePtr ptr = std::make_shared<Texture>(std::move(t));
  textures_[key] = ptr;
  return ptr;
}

Result<TexRef> Reader::tex_ref_from_json(const json& j, const std::string& pointer) const {
  if (!j.is_object()) return fail(pointer, "expected a textureInfo object");
  RELIEF_RETURN_IF_ERROR(check_keys(j, pointer, {"index", "texCoord"}));
  TexRef r;
  r.pointer = pointer;
  if (!j.contains("index")) return fail(pointer, "missing 'index'");
  RELIEF_RETURN_IF_ERROR(get_int(j, "index", pointer, r.index, 0, 1 << 30));
  RELIEF_RETURN_IF_ERROR(get_int(j, "texCoord", pointer, r.tex_coord, 0, 1 << 30));
  if (j.contains("extensions") && j["extensions"].is_object() &&
      j["extensions"].contains(kTextureTransform))
    r.transform = j["extensions"][kTextureTransform];
  return r;
}

Result<TexRef> Reader::tex_ref(int index, int tex_coord, const std::string& extensions_json,
                               const std::string& pointer) const {
  TexRef r;
  r.pointer = pointer;
  r.index = index;
  r.tex_coord = tex_coord;
  Result<json> t = extension(extensions_json, kTextureTransform, pointer);
  if (!t.ok()) return t.status();
  r.transform = *t;
  return r;
}

Result<UvTransform> Reader::uv_transform(const TexRef& r) const {
  UvTransform t;
  int tex_coord = r.tex_coord;
  if (!r.transform.is_null()) {
    const std::string p = r.pointer + "/extensions/" + kTextureTransform;
    if (!r.transform.is_object()) return fail(p, "expected an object");
    RELIEF_RETURN_IF_ERROR(check_keys(r.transform, p, {"offset", "rotation", "scale", "texCoord"}));
    RELIEF_RETURN_IF_ERROR(get_vec<2>(r.transform, "offset", p, t.offset, -1e9, 1e9));
    RELIEF_RETURN_IF_ERROR(get_vec<2>(r.transform, "scale", p, t.scale, -1e9, 1e9));
    RELIEF_RETURN_IF_ERROR(get_number(r.transform, "rotation", p, t.rotation, -1e9, 1e9));
    RELIEF_RETURN_IF_ERROR(get_int(r.transform, "texCoord", p, tex_coord, 0, 1 << 30));
    if (t.scale.x == 0.0 || t.scale.y == 0.0) return fail(p + "/scale", "scale must not be 0");
  }
  if (tex_coord > 1)
    return fail(r.pointer + (r.transform.is_object() && r.transform.contains("texCoord")
                                 ? std::string("/extensions/") + kTextureTransform + "/texCoord"
                                 : std::string("/texCoord")),
                "TEXCOORD_" + std::to_string(tex_coord) +
                    " is not supported (only TEXCOORD_0 and TEXCOORD_1)");
  t.tex_coord = tex_coord;
  return t;
}

Result<SamplerState> Reader::sampler_of(const TexRef& r, bool& mipmapped) const {
  const tinygltf::Texture& tex = m_.textures[r.index];
  SamplerState s;
  mipmapped = true;
  if (tex.sampler < 0) return s;
  const std::string p = "/textures/" + std::to_string(r.index) + "/sampler";
  if (tex.sampler >= static_cast<int>(m_.samplers.size()))
    return fail(p, "sampler " + std::to_string(tex.sampler) + " does not exist");
  const tinygltf::Sampler& smp = m_.samplers[tex.sampler];
  const std::string sp = "/samplers/" + std::to_string(tex.sampler);
  // Our filters are GL's minification modes; magnification follows (nearest for kNearest).
  switch (smp.minFilter) {
    case -1:
      break;
    case kNearest:
      s.filter = Filter::kNearest;
      mipmapped = false;
      break;
    case kLinear:
      s.filter = Filter::kBilinear;
      mipmapped = false;
      break;
    case kNearestMipNearest:
      s.filter = Filter::kNearest;
      break;
    case kLinearMipNearest:
      s.filter = Filter::kBilinear;
      break;
    case kNearestMipLinear:
    case kLinearMipLinear:
      s.filter = Filter::kTrilinear;
      break;
    default:
      return fail(sp + "/minFilter", "unknown filter " + std::to_string(smp.minFilter));
  }
  if (smp.minFilter == -1 && smp.magFilter == kNearest) s.filter = Filter::kNearest;
  if (smp.magFilter != -1 && smp.magFilter != kNearest && smp.magFilter != kLinear)
    return fail(sp + "/magFilter", "unknown filter " + std::to_string(smp.magFilter));
  auto wrap = [&](int w, const char* key, Wrap& out) -> Status {
    switch (w) {
      case kRepeat:
        out = Wrap::kRepeat;
        return {};
      case kClampToEdge:
        out = Wrap::kClamp;
        return {};
      case kMirroredRepeat:
        out = Wrap::kMirror;
        return {};
      default:
        return fail(sp + "/" + key, "unknown wrap mode " + std::to_string(w));
    }
  };
  RELIEF_RETURN_IF_ERROR(wrap(smp.wrapS, "wrapS", s.wrap_u));
  RELIEF_RETURN_IF_ERROR(wrap(smp.wrapT, "wrapT", s.wrap_v));
  return s;
}

// Decodes image `index` for `use` (cached: one texture per image, use and mip choice).
Result<TexturePtr> Reader::texture(const TexRef& r, TexUse use, bool mipmapped) {
  if (Result<TexturePtr> t = exact_texels(r, use, mipmapped); !t.ok() || *t) return t;
  // EXT_texture_webp's source when the texture has one, else the core source (its fallback).
  std::string sp;
  const int source = texture_source(m_, r.index, &sp);
  if (source < 0 || source >= static_cast<int>(m_.images.size()))
    return fail(sp, source < 0 ? "texture has no source image"
                               : "image " + std::to_string(source) + " does not exist");
  const auto key = std::make_tuple(source, static_cast<int>(use), mipmapped);
  if (auto it = textures_.find(key); it != textures_.end()) return it->second;
  const tinygltf::Image& img = m_.images[source];
  const std::string ip = "/images/" + std::to_string(source);
  TextureLoadOptions opt;
  opt.color_space = use == TexUse::kColor ? ColorSpace::kSRGB : ColorSpace::kLinear;
  opt.first_channel_only = use == TexUse::kDepth || use == TexUse::kHeight;
  opt.height_to_depth = use == TexUse::kHeight;
  opt.unit_range = opt.first_channel_only;
  Result<Texture> t = Status::error("no image");
  if (!img.uri.empty() && img.uri.rfind("data:", 0) != 0) {
    // An external file: resolved in the scene's folder (safe_file.h), only a regular file is
    // read, then decoded from memory; errors name the path as the scene gives it.
    Result<ResolvedUri> file = resolve_scene_uri(folder_, img.uri);
    if (!file.ok()) return fail(ip + "/uri", file.status().message());
    Result<std::string> bytes = read_regular_file(file->real);
    if (!bytes.ok()) return fail(ip + "/uri", renamed(bytes.status().message(), *file));
    t = load_texture_from_memory(std::move(*bytes), printable(file->path), opt);
    if (!t.ok()) return fail(ip + "/uri", t.status().message());
  } else {
    t = decode_in_memory(img, opt);
    if (!t.ok())
      return fail(ip + (img.bufferView >= 0 ? "/bufferView" : "/uri"), t.status().message());
  }
  if (mipmapped) t->generate_mips(use == TexUse::kCone ? MipReduce::kMin : MipReduce::kAverage);
  TexturePtr ptr = std::make_shared<Texture>(std::move(*t));
  textures_[key] = ptr;
  return ptr;
}

// A message about `file.real` (symlinks resolved) made to name `file.path`, as the scene does.
std::string Reader::renamed(const std::string& message, const ResolvedUri& file) {
  const std::string real = printable(file.real) + ": ";
  if (message.rfind(real, 0) != 0) return message;
  return printable(file.path) + ": " + message.substr(real.size());
}

// Embedded images (GLB buffer views, data URIs), decoded from memory (nothing is written).
Result<Texture> Reader::decode_in_memory(const tinygltf::Image& img,
                                         const TextureLoadOptions& opt) {
  const std::vector<unsigned char>& bytes = img.image;
  if (bytes.empty()) return Status::error("image data is empty");
  const bool png = bytes.size() >= 8 && std::memcmp(bytes.data(), "\x89PNG\r\n\x1a\n", 8) == 0;
  const bool jpeg = bytes.size() >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff;
  const bool webp = bytes.size() >= 12 && std::memcmp(bytes.data(), "RIFF", 4) == 0 &&
                    std::memcmp(bytes.data() + 8, "WEBP", 4) == 0;  // EXT_texture_webp
  if (!png && !jpeg && !webp) return Status::error("embedded image is neither PNG, JPEG nor WebP");
  return load_texture_from_memory(std::string(bytes.begin(), bytes.end()), "embedded image", opt);
}

}  // namespace relief::gltf_detail
