// glTF input, accessors and meshes (scene/gltf_internal.h): glTF 2.0 specification sections
// 3.6.2 (accessors, buffer views), 3.7.2 (meshes: TRIANGLES primitives, their attributes and
// indices, morph targets) and 3.7.3 (skins: JOINTS_0, WEIGHTS_0), KHR_mesh_quantization's
// component types. Every element is bounds-checked and finite; missing normals and tangents are
// made by scene/mesh_prep.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "scene/gltf_decode.h"
#include "scene/gltf_internal.h"
#include "scene/mesh_prep.h"

namespace relief::gltf_detail {
namespace {

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "an unknown type";
  }
}
const char* component_name(int c) {
  const char* n = gltf_component_type_name(c);
  return n ? n : "an unknown component type";
}

}  // namespace

Result<Reader::View> Reader::view(int index, const std::string& where) const {
  if (index < 0 || index >= static_cast<int>(m_.accessors.size()))
    return fail(where, "accessor " + std::to_string(index) + " does not exist");
  const tinygltf::Accessor& a = m_.accessors[index];
  const std::string ap = "/accessors/" + std::to_string(index);
  if (a.sparse.isSparse) return fail(ap + "/sparse", "sparse accessors are not supported");
  if (a.count == 0) return fail(ap + "/count", "accessor has no elements");
  View v;
  v.count = a.count;
  v.comps = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
  v.ctype = a.componentType;
  v.normalized = a.normalized;
  const int csize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
  if (v.comps <= 0) return fail(ap + "/type", "unknown accessor type");
  if (csize <= 0) return fail(ap + "/componentType", "unknown component type");
  const size_t elem = static_cast<size_t>(v.comps) * csize;
  if (a.bufferView < 0 || a.bufferView >= static_cast<int>(m_.bufferViews.size()))
    return fail(ap + "/bufferView",
                "buffer view " + std::to_string(a.bufferView) + " does not exist");
  const tinygltf::BufferView& bv = m_.bufferViews[a.bufferView];
  const std::string bp = "/bufferViews/" + std::to_string(a.bufferView);
  if (bv.buffer < 0 || bv.buffer >= static_cast<int>(m_.buffers.size()))
    return fail(bp + "/buffer", "buffer " + std::to_string(bv.buffer) + " does not exist");
  const tinygltf::Buffer& buf = m_.buffers[bv.buffer];
  if (bv.byteOffset > buf.data.size() || bv.byteLength > buf.data.size() - bv.byteOffset)
    return fail(bp, "bytes " + std::to_string(bv.byteOffset) + ".." +
                        std::to_string(bv.byteOffset + bv.byteLength) + " exceed buffer " +
                        std::to_string(bv.buffer) + " (" + std::to_string(buf.data.size()) +
                        " bytes)");
  v.stride = bv.byteStride ? bv.byteStride : elem;
  if (v.stride < elem)
    return fail(bp + "/byteStride", "stride " + std::to_string(v.stride) +
                                        " is smaller than an element (" + std::to_string(elem) +
                                        " bytes)");
  const size_t need = a.byteOffset + v.stride * (a.count - 1) + elem;
  if (a.byteOffset > bv.byteLength || need > bv.byteLength)
    return fail(ap, std::to_string(a.count) + " elements of " + std::to_string(elem) +
                        " bytes at offset " + std::to_string(a.byteOffset) + " need " +
                        std::to_string(need) + " bytes; buffer view " +
                        std::to_string(a.bufferView) + " has " + std::to_string(bv.byteLength));
  v.data = buf.data.data() + bv.byteOffset + a.byteOffset;
  return v;
}

float Reader::component(const uint8_t* p, int ctype, bool normalized) {
  switch (ctype) {
    case kFloat: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case kUByte:
      return normalized ? p[0] / 255.0f : p[0];
    case kUShort: {
      uint16_t u;
      std::memcpy(&u, p, 2);
      return normalized ? u / 65535.0f : u;
    }
    case kByte: {
      const int8_t b = static_cast<int8_t>(p[0]);
      return normalized ? std::max(b / 127.0f, -1.0f) : b;
    }
    case kShort: {
      int16_t u;
      std::memcpy(&u, p, 2);
      return normalized ? std::max(u / 32767.0f, -1.0f) : u;
    }
    default:
      return 0.0f;
  }
}

// Reads a float attribute: VEC<comps> of FLOAT (or normalised unsigned bytes / shorts where
// allowed), every value finite. POSITION, NORMAL, TANGENT and TEXCOORD_n (the last token of
// `where`) take the component types glTF lists for them, KHR_mesh_quantization's too when the
// file uses it (gltf_decode.h); quantized normals and tangents are renormalized.
template <int N>
Status Reader::read_attr(int index, const std::string& where, bool allow_normalized,
                         std::vector<glm::vec<N, float>>& out) const {
  Result<View> v = view(index, where);
  if (!v.ok()) return v.status();
  const std::string semantic = where.substr(where.rfind('/') + 1);
  const bool target = where.find("/targets/") != std::string::npos;
  const std::vector<int> allowed =
      attribute_component_types(semantic, target, uses_extension(kMeshQuantization));
  const int signed_ctype = v->normalized ? -v->ctype : v->ctype;
  const bool ok_ctype =
      allowed.empty() ? !(v->ctype != kFloat && !(allow_normalized && v->normalized &&
                                                  (v->ctype == kUByte || v->ctype == kUShort)))
                      : std::find(allowed.begin(), allowed.end(), signed_ctype) != allowed.end();
  if (!ok_ctype || v->comps != N || m_.accessors[index].type != N)
    return fail(
        where,
        "accessor " + std::to_string(index) + " is " + type_name(m_.accessors[index].type) +
            " of " + (v->normalized ? "normalized " : "") + component_name(v->ctype) +
            ", expected VEC" + std::to_string(N) + " of " +
            (allowed.empty() ? std::string("FLOAT") +
                                   (allow_normalized ? " (or normalized UNSIGNED_BYTE/SHORT)" : "")
                             : component_types_text(allowed)) +
            (!allowed.empty() && !uses_extension(kMeshQuantization)
                 ? " (other types need KHR_mesh_quantization)"
                 : ""));
  const int csize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(v->ctype));
  out.resize(v->count);
  for (size_t i = 0; i < v->count; ++i) {
    const uint8_t* e = v->data + i * v->stride;
    for (int c = 0; c < N; ++c) {
      const float f = component(e + c * csize, v->ctype, v->normalized);
      if (!std::isfinite(f))
        return fail(where, "element " + std::to_string(i) + " is not finite (" +
                               (std::isnan(f) ? "NaN" : "Inf") + ")");
      out[i][c] = f;
    }
  }
  if constexpr (N >= 3) {
    if (v->ctype != kFloat && !target && (semantic == "NORMAL" || semantic == "TANGENT"))
      for (glm::vec<N, float>& e : out) {
        const float len = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
        if (len > 0.0f)
          for (int c = 0; c < 3; ++c) e[c] /= len;
      }
  }
  return {};
}

bool Reader::uses_extension(const char* name) const {
  return std::find(m_.extensionsUsed.begin(), m_.extensionsUsed.end(), name) !=
         m_.extensionsUsed.end();
}

Status Reader::read_indices(int index, const std::string& where, std::vector<uint32_t>& out) const {
  Result<View> v = view(index, where);
  if (!v.ok()) return v.status();
  if (v->comps != 1 || (v->ctype != kUByte && v->ctype != kUShort && v->ctype != kUInt))
    return fail(where, "accessor " + std::to_string(index) + " is " +
                           type_name(m_.accessors[index].type) + " of " + component_name(v->ctype) +
                           ", expected SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  out.resize(v->count);
  for (size_t i = 0; i < v->count; ++i) {
    const uint8_t* e = v->data + i * v->stride;
    if (v->ctype == kUByte) {
      out[i] = e[0];
    } else if (v->ctype == kUShort) {
      uint16_t u;
      std::memcpy(&u, e, 2);
      out[i] = u;
    } else {
      std::memcpy(&out[i], e, 4);
    }
  }
  return {};
}

// A primitive's mesh: shared by the nodes that use it, except on a node with a skin or morph
// targets (`deform_node` >= 0), which gets its own mesh and a Deformer.
Result<int> Reader::primitive_mesh(int mesh, int prim, int material_index, int deform_node) {
  const PrimitiveKey key{mesh, prim};
  if (deform_node < 0)
    if (auto it = meshes_.find(key); it != meshes_.end()) return it->second;
  const tinygltf::Primitive& p = m_.meshes[mesh].primitives[prim];
  const std::string pp = "/meshes/" + std::to_string(mesh) + "/primitives/" + std::to_string(prim);
  const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES) {
    static const char* names[] = {"POINTS",    "LINES",          "LINE_LOOP",   "LINE_STRIP",
                                  "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};
    return fail(pp + "/mode",
                std::string("mode ") +
                    (mode >= 0 && mode <= 6 ? names[mode] : std::to_string(mode).c_str()) +
                    " is not supported (only TRIANGLES)");
  }
  Mesh out;
  out.name = m_.meshes[mesh].name.empty() ? "mesh" + std::to_string(mesh) : m_.meshes[mesh].name;
  if (m_.meshes[mesh].primitives.size() > 1) out.name += "/" + std::to_string(prim);
  const std::string ap = pp + "/attributes";
  RELIEF_RETURN_IF_ERROR(read_vertices(p, ap, material_index, out));
  const size_t n = out.positions.size();
  RELIEF_RETURN_IF_ERROR(read_triangles(p, pp, out));
  if (material_index >= 0 && materials_[material_index].bake_uv) {
    for (glm::vec2& uv : out.uvs) uv = materials_[material_index].uv.apply(uv);
    out.tangents.clear();  // the frame follows the rotated uv
  }
  prepare_mesh(out);
  if (deform_node >= 0 && out.positions.size() != n)
    return fail(pp + "/attributes",
                "a skinned or morphed mesh whose uv mirrors (tangent handedness split by "
                "mesh preparation) needs a TANGENT attribute");
  scene_.meshes.push_back(out);
  const int id = static_cast<int>(scene_.meshes.size()) - 1;
  if (deform_node < 0) {
    meshes_[key] = id;
    return id;
  }
  Deformer d;
  d.mesh = id;
  d.node = deform_node;
  d.skin = m_.nodes[deform_node].skin;
  d.rest = std::move(out);
  RELIEF_RETURN_IF_ERROR(read_deformation(p, pp, d));
  deformers_.push_back(std::move(d));
  return id;
}

// The vertex attributes of primitive `p` (`ap`: its attributes' pointer): POSITION, then
// NORMAL, TEXCOORD_0, TEXCOORD_1 (which the material may need), COLOR_0 and TANGENT, each with
// as many elements as POSITION.
Status Reader::read_vertices(const tinygltf::Primitive& p, const std::string& ap,
                             int material_index, Mesh& out) const {
  auto attr = [&](const char* name) {
    auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
  };
  if (attr("POSITION") < 0) return fail(ap, "no POSITION attribute");
  RELIEF_RETURN_IF_ERROR(read_attr<3>(attr("POSITION"), ap + "/POSITION", false, out.positions));
  const size_t n = out.positions.size();
  auto same_count = [&](const char* name, size_t count) -> Status {
    if (count == n) return {};
    return fail(ap + "/" + name, "accessor " + std::to_string(attr(name)) + " has " +
                                     std::to_string(count) + " elements, POSITION has " +
                                     std::to_string(n));
  };
  if (attr("NORMAL") >= 0) {
    RELIEF_RETURN_IF_ERROR(read_attr<3>(attr("NORMAL"), ap + "/NORMAL", false, out.normals));
    RELIEF_RETURN_IF_ERROR(same_count("NORMAL", out.normals.size()));
  }
  if (attr("TEXCOORD_0") >= 0) {
    RELIEF_RETURN_IF_ERROR(read_attr<2>(attr("TEXCOORD_0"), ap + "/TEXCOORD_0", true, out.uvs));
    RELIEF_RETURN_IF_ERROR(same_count("TEXCOORD_0", out.uvs.size()));
  }
  if (attr("TEXCOORD_1") >= 0) {
    RELIEF_RETURN_IF_ERROR(read_attr<2>(attr("TEXCOORD_1"), ap + "/TEXCOORD_1", true, out.uvs1));
    RELIEF_RETURN_IF_ERROR(same_count("TEXCOORD_1", out.uvs1.size()));
  }
  if (material_index >= 0 && !materials_[material_index].needs_uv1.empty() && out.uvs1.empty())
    return fail(
        ap, "no TEXCOORD_1 attribute, which " + materials_[material_index].needs_uv1 + " reads");
  if (attr("COLOR_0") >= 0) {
    const int ci = attr("COLOR_0");
    const std::string cp = ap + "/COLOR_0";
    if (ci < static_cast<int>(m_.accessors.size()) && m_.accessors[ci].type == 3) {
      std::vector<glm::vec3> rgb;
      RELIEF_RETURN_IF_ERROR(read_attr<3>(ci, cp, true, rgb));
      out.colors.reserve(rgb.size());
      for (const glm::vec3& c : rgb) out.colors.push_back(glm::vec4(c, 1.0f));
    } else {
      RELIEF_RETURN_IF_ERROR(read_attr<4>(ci, cp, true, out.colors));
    }
    RELIEF_RETURN_IF_ERROR(same_count("COLOR_0", out.colors.size()));
  }
  if (attr("TANGENT") >= 0) {
    RELIEF_RETURN_IF_ERROR(read_attr<4>(attr("TANGENT"), ap + "/TANGENT", false, out.tangents));
    RELIEF_RETURN_IF_ERROR(same_count("TANGENT", out.tangents.size()));
    // glTF's bitangent w * cross(N, T) points to the image top (-v); ours points along +v
    for (glm::vec4& t : out.tangents) t.w = -t.w;
  }
  return {};
}

// The triangles of primitive `p`: its indices, each below the vertex count, else the vertices
// in order, three by three.
Status Reader::read_triangles(const tinygltf::Primitive& p, const std::string& pp,
                              Mesh& out) const {
  const size_t n = out.positions.size();
  if (p.indices >= 0) {
    RELIEF_RETURN_IF_ERROR(read_indices(p.indices, pp + "/indices", out.indices));
    if (out.indices.size() % 3)
      return fail(pp + "/indices",
                  std::to_string(out.indices.size()) + " indices do not make whole triangles");
    for (uint32_t i : out.indices)
      if (i >= n)
        return fail(pp + "/indices", "index " + std::to_string(i) + " out of range (" +
                                         std::to_string(n) + " vertices)");
  } else {
    if (n % 3)
      return fail(pp + "/attributes/POSITION",
                  std::to_string(n) + " vertices without indices do not make whole triangles");
    out.indices.resize(n);
    for (size_t i = 0; i < n; ++i) out.indices[i] = static_cast<uint32_t>(i);
  }
  return {};
}

// Morph targets and skin attributes of a deformed primitive (glTF 3.7.2.2, 3.7.3).
Status Reader::read_deformation(const tinygltf::Primitive& p, const std::string& pp,
                                Deformer& d) const {
  const size_t n = d.rest.positions.size();
  for (size_t t = 0; t < p.targets.size(); ++t) {
    MorphTarget mt;
    const std::string tp = pp + "/targets/" + std::to_string(t);
    for (const auto& [name, index] : p.targets[t]) {
      std::vector<glm::vec3>* dst = name == "POSITION"  ? &mt.positions
                                    : name == "NORMAL"  ? &mt.normals
                                    : name == "TANGENT" ? &mt.tangents
                                                        : nullptr;
      if (!dst)
        return fail(tp + "/" + name,
                    "morph target attribute not supported (POSITION, NORMAL, TANGENT)");
      RELIEF_RETURN_IF_ERROR(read_attr<3>(index, tp + "/" + name, false, *dst));
      if (dst->size() != n)
        return fail(tp + "/" + name, "accessor " + std::to_string(index) + " has " +
                                         std::to_string(dst->size()) + " elements, POSITION has " +
                                         std::to_string(n));
    }
    d.targets.push_back(std::move(mt));
  }
  const std::string ap = pp + "/attributes";
  for (const char* extra : {"JOINTS_1", "WEIGHTS_1"})
    if (p.attributes.count(extra))
      return fail(ap + "/" + extra, "at most four joint influences are supported (JOINTS_0)");
  if (d.skin < 0) return {};
  const auto j = p.attributes.find("JOINTS_0"), w = p.attributes.find("WEIGHTS_0");
  if (j == p.attributes.end() || w == p.attributes.end())
    return fail(ap, "a skinned mesh needs JOINTS_0 and WEIGHTS_0");
  const size_t joint_count = m_.skins[d.skin].joints.size();
  std::vector<float> joints;
  RELIEF_RETURN_IF_ERROR(
      read_floats(j->second, ap + "/JOINTS_0", TINYGLTF_TYPE_VEC4, {kUByte, kUShort}, joints));
  std::vector<float> weights;
  RELIEF_RETURN_IF_ERROR(read_floats(w->second, ap + "/WEIGHTS_0", TINYGLTF_TYPE_VEC4,
                                     {kFloat, -kUByte, -kUShort}, weights));
  if (joints.size() != 4 * n || weights.size() != 4 * n)
    return fail(ap + (joints.size() != 4 * n ? "/JOINTS_0" : "/WEIGHTS_0"),
                "expected " + std::to_string(n) + " elements, as POSITION");
  d.joints.resize(n);
  d.weights.resize(n);
  for (size_t v = 0; v < n; ++v)
    for (int c = 0; c < 4; ++c) {
      const float jf = joints[4 * v + c], wf = weights[4 * v + c];
      if (wf < 0.0f)
        return fail(ap + "/WEIGHTS_0", "element " + std::to_string(v) + " has a negative weight");
      if (wf > 0.0f && jf >= joint_count)
        return fail(ap + "/JOINTS_0", "element " + std::to_string(v) + " names joint " +
                                          std::to_string(static_cast<long>(jf)) +
                                          " (the skin has " + std::to_string(joint_count) + ")");
      d.joints[v][c] = static_cast<uint16_t>(wf > 0.0f ? jf : 0.0f);
      d.weights[v][c] = wf;
    }
  return {};
}

// Reads every component of an accessor of `type` as float. `ctypes` lists the accepted
// component types: positive as stored (integers as their value), negative normalised.
Status Reader::read_floats(int index, const std::string& where, int type, std::vector<int> ctypes,
                           std::vector<float>& out) const {
  Result<View> v = view(index, where);
  if (!v.ok()) return v.status();
  const bool ok_ctype =
      std::find(ctypes.begin(), ctypes.end(), v->normalized ? -v->ctype : v->ctype) !=
          ctypes.end() ||
      (v->ctype == kFloat && std::find(ctypes.begin(), ctypes.end(), kFloat) != ctypes.end());
  if (m_.accessors[index].type != type || !ok_ctype) {
    std::string list;
    for (int c : ctypes)
      list += (list.empty() ? "" : ", ") + std::string(c < 0 ? "normalized " : "") +
              component_name(std::abs(c));
    return fail(where, "accessor " + std::to_string(index) + " is " +
                           type_name(m_.accessors[index].type) + " of " + component_name(v->ctype) +
                           (v->normalized ? " (normalized)" : "") + ", expected " +
                           type_name(type) + " of " + list);
  }
  const int csize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(v->ctype));
  out.resize(v->count * v->comps);
  for (size_t i = 0; i < v->count; ++i)
    for (int c = 0; c < v->comps; ++c) {
      const float f = component(v->data + i * v->stride + c * csize, v->ctype, v->normalized);
      if (!std::isfinite(f)) return fail(where, "element " + std::to_string(i) + " is not finite");
      out[i * v->comps + c] = f;
    }
  return {};
}

}  // namespace relief::gltf_detail
