// The shell every height-field technique shares (parallax, steep_parallax, pom, relief, exact and
// the cone family): the per-fragment tangent frame, the view ray in texture space, the constant
// LOD per quad, depth correction of the hit, shading at the hit with the normal and base-colour
// maps, and the visibility hook: the technique's self-shadow ray, then (kEffectReceiveShadow) the
// light's shadow map (shaders_cpp/shadow_lookup.h) looked up at the displaced hit point. With
// kEffectShadowPass the kernel stops after the intersection and the corrected depth: the frame's
// "eye" is then the light (orthographic with view_dir for a directional light). Policarpo,
// Oliveira and Comba, "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces", I3D 2005
// (figure 10 for the shadow ray, section 2 for the depth correction) describe the frame the
// techniques differ inside of: only the search and the shadow ray change from one plugin to the
// next.
//
// A technique is a policy struct:
//   static constexpr int kDepthScale;  // schema index of "depth_scale"
//   static constexpr bool kSamplesDepthMap = false;  // optional: search and shadow never sample
//                                                    // `depth` (no per-quad LOD is computed)
//   static constexpr int kLodParam, kMaxMipSlot;     // optional: the `lod` parameter's index
//                                                    // and the max-mip slot (material_depth)
//   // first hit of the ray uv + t * (ds, 1) in depth units; active = covered lanes
//   template <class F> static SearchHit<F> search(const ShadeContext&, const FragIn<F>&,
//       const TextureDepth& depth, const V3<F>& view_tangent, const V2<F>& ds, mask_t<F> active);
//   // visibility in [0, 1] of the hit towards a light whose tangent-space direction has z = lz and
//   // texture-space step dl; adds its steps and fetches to `o`
//   template <class F> static F shadow(const ShadeContext&, const TextureDepth& depth,
//       const SearchHit<F>& hit, const V2<F>& dl, const F& lz, mask_t<F> lit, ShadeOut<F>& o);
//   // optional: the factor of the indirect light at the hit while self-shadow is on (a shadow
//   // that darkens with depth instead of tracing rays also darkens the ambient light)
//   template <class F> static F self_occlusion(const ShadeContext&, const SearchHit<F>& hit);
// (MarchedShadow<index> supplies `shadow` for the plain marched ray) and the plugin's descriptor
// takes `&select_relief_variant<Policy>` and `&relief_depth_output`.
// Texture slots 0, 1, 2 are base_color, normal and depth in every plugin built on the shell.

#if defined(RELIEF_PLUGINS_RELIEF_SHELL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_PLUGINS_RELIEF_SHELL_H_
#undef RELIEF_PLUGINS_RELIEF_SHELL_H_
#else
#define RELIEF_PLUGINS_RELIEF_SHELL_H_
#endif

#include "plugins/surface.h"
#include "shaders_cpp/height_ao.h"
#include "shaders_cpp/ray.h"
#include "shaders_cpp/search.h"
#include "shaders_cpp/shadow.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

enum ReliefSlot { kBaseColorSlot = 0, kNormalSlot = 1, kDepthSlot = 2 };

inline constexpr TextureSlotSpec kDepthSlotSpec = {
    "depth", true, "depth map: 0 at the reference surface, 1 deepest, linear"};
inline constexpr TextureSlotSpec kReliefSlots[] = {kBaseColorSlotSpec, kNormalSlotSpec,
                                                   kDepthSlotSpec};

// The LOD the searches read the depth map at (parameter `lod`, an enum of kSearchLodSpec):
// `quad` the per-quad LOD of the material's depth map and its mips (GL's, what the papers' shaders
// get), `zero` level 0 only (the true surface at every distance, at the cost of aliasing where a
// texel is smaller than a pixel), `max-mip` the per-quad LOD of the derived max-mip chain (slot
// kMaxMipSlotSpec, render/derived_maps.h): the minimum depth over the read's footprint, a surface
// that never lies below the true one, so a distant search cannot pass through thin walls the
// averaged mips thin out; its hits sit up to the footprint's relief above the level-0 surface.
enum class SearchLod { kQuad = 0, kZero = 1, kMaxMip = 2 };
inline constexpr ParamSpec kSearchLodSpec = {
    "lod",
    ParamType::kEnum,
    0.0f,
    0.0f,
    2.0f,
    "quad|zero|max-mip",
    "depth LOD of the search and the self-shadow ray: quad (per-quad LOD, the map's mips), zero "
    "(level 0), max-mip (min depth over the footprint, never below the surface)"};
inline constexpr TextureSlotSpec kMaxMipSlotSpec = {
    "depth_max_mip", false,
    "min-depth chain of depth for lod=max-mip (derived from depth if absent)"};
// The slots of relief, pom and steep_parallax: the shell's three and the max-mip chain.
inline constexpr int kReliefMaxMipSlot = 3;
inline constexpr TextureSlotSpec kReliefSearchSlots[] = {kBaseColorSlotSpec, kNormalSlotSpec,
                                                         kDepthSlotSpec, kMaxMipSlotSpec};

inline SearchLod search_lod(const float* params, int lod_param) {
  return static_cast<SearchLod>(static_cast<int>(params[lod_param]));
}
// PluginDescriptor::reads_texture of a technique whose `lod` parameter is params[kLod] and whose
// max-mip slot is kSlot: the chain is read (and derived) only with lod=max-mip.
template <int kLod, int kSlot>
bool reads_max_mip_slot(const float* params, int slot) {
  return slot != kSlot || search_lod(params, kLod) == SearchLod::kMaxMip;
}

inline constexpr ParamSpec kDepthScaleSpec = {
    "depth_scale", ParamType::kFloat, 0.05f, 0.0f, 1.0f, nullptr, "relief height in uv units"};
// The search parameters of the linear + binary family (relief, pom, relief_dual, relief_quadric).
inline constexpr ParamSpec kLinearStepsSpec = {"steps",
                                               ParamType::kInt,
                                               32.0f,
                                               1.0f,
                                               256.0f,
                                               nullptr,
                                               "linear search steps at grazing angles"};
inline constexpr ParamSpec kBinaryStepsSpec = {"binary_steps",
                                               ParamType::kInt,
                                               8.0f,
                                               0.0f,
                                               32.0f,
                                               nullptr,
                                               "binary search halvings after the linear search"};
inline constexpr ParamSpec kMinStepsSpec = {
    "min_steps",
    ParamType::kInt,
    8.0f,
    1.0f,
    256.0f,
    nullptr,
    "linear steps facing the surface (steps at grazing angles; mixed by |V.z|)"};
inline constexpr ParamSpec kShadowStepsSpec = {
    "shadow_steps",
    ParamType::kInt,
    32.0f,
    1.0f,
    256.0f,
    nullptr,
    "self-shadow ray steps over the full depth (self_shadow effect)"};

// The schema of the linear + binary search with a marched self-shadow ray (relief, relief_dual):
// their kernels index params[] with Param.
namespace relief_schema {
enum Param { kSteps, kBinarySteps, kMinSteps, kDepthScaleParam, kShadowStepsParam };
inline constexpr ParamSpec kParams[] = {kLinearStepsSpec, kBinaryStepsSpec, kMinStepsSpec,
                                        kDepthScaleSpec, kShadowStepsSpec};
}  // namespace relief_schema

// Lanes of this group that are real, covered fragments.
template <class F>
mask_t<F> covered_lanes(const FragIn<F>& in) {
  mask_t<F> m = false_mask<F>();
  for (int i = 0; i < lane_width<F>; ++i) {
    const int ln = in.lane0 + i;
    if ((ln >> 2) < in.packet->num_quads && in.packet->lane_covered(ln)) set_lane(m, i, true);
  }
  return m;
}

// The hit of a search that does not move: the fragment's own uv at depth 0, no work.
template <class F>
SearchHit<F> unmoved_hit(const FragIn<F>& in) {
  return {in.uv, F(0.0f), F(0.0f), F(0.0f)};
}

// The material's depth map (slot kDepthSlot) at a constant LOD per quad: the derivatives are per
// quad, so the LOD is computed at a quad's first lane and copied to the other three. No LOD when
// the slot is empty (the source must then not be sampled). With a `lod` parameter (params index
// lod_param >= 0): `zero` reads level 0, `max-mip` the chain in slot max_mip_slot at the quad's
// LOD (the depth map's own when the chain is missing, which the planner never lets happen).
template <class F>
TextureDepth material_depth(const MaterialUniforms& m, const FragIn<F>& in, int lod_param = -1,
                            int max_mip_slot = -1) {
  TextureDepth depth;
  depth.texture = m.textures[kDepthSlot];
  depth.sampler = &m.samplers[kDepthSlot];
  const SearchLod mode = lod_param >= 0 ? search_lod(m.params, lod_param) : SearchLod::kQuad;
  if (mode == SearchLod::kZero || !depth.texture) return depth;  // lod[] = 0: level 0
  if (mode == SearchLod::kMaxMip && m.textures[max_mip_slot]) {
    depth.texture = m.textures[max_mip_slot];
    depth.sampler = &m.samplers[max_mip_slot];
  }
  for (int i = 0; i < lane_width<F>; ++i)
    depth.lod[i] = (i > 0 && ((in.lane0 + i) & 3) != 0)
                       ? depth.lod[i - 1]
                       : compute_lod(*depth.texture, {lane(in.duv_dx.x, i), lane(in.duv_dx.y, i)},
                                     {lane(in.duv_dy.x, i), lane(in.duv_dy.y, i)});
  return depth;
}

// The fragment's tangent frame tf, the unit world direction w from the eye to the fragment
// (shaders_cpp/ray.h world_view_dir) and V, w in tangent space. Callers bind references to the
// members, not a structured binding: clang before 16 cannot capture one in a lambda.
template <class F>
struct ShellView {
  TangentFrame<F> tf;
  V3<F> w, V;
};
template <class F>
ShellView<F> shell_view(const ShadeContext& ctx, const FragIn<F>& in) {
  const TangentFrame<F> tf = fragment_frame(in);
  const V3<F> w = world_view_dir(in.position, ctx.frame->eye, ctx.frame->orthographic,
                                 ctx.frame->view_dir, -tf.n);
  return {tf, w, tf.to_tangent(w)};
}

// The relief's full depth in world units: depth_scale uv units at the fragment's tile scale
// (world units per uv along T and B, scene/mesh_prep.cpp).
template <class F>
F relief_world_height(const F& depth_scale, const FragIn<F>& in) {
  return depth_scale * (in.tile_scale.x + in.tile_scale.y) * F(0.5f);
}

// The depth a relief fragment writes for the point `pos` it shows: pos's reversed-Z depth, never
// nearer than the fragment's own (relief only moves the surface away from the viewer).
template <class F>
F corrected_depth(const ShadeContext& ctx, const FragIn<F>& in, const V3<F>& pos) {
  return vmin(reversed_z_depth(ctx.frame->view_proj, pos, in.frag_z), in.frag_z);
}

// Records a search's hit in `o` (hit uv and depth, counters) and returns the hit's world point on
// the eye ray: hit.depth times the relief's world height below the fragment.
template <class F>
V3<F> record_hit(const FragIn<F>& in, const ShellView<F>& view, const F& depth_scale,
                 const SearchHit<F>& hit, ShadeOut<F>& o) {
  o.hit_uv = hit.uv;
  o.hit_depth = hit.depth;
  o.steps = hit.steps;
  o.fetches = hit.fetches;
  return hit_world_position(in.position, view.w, view.V.z, hit.depth,
                            relief_world_height(depth_scale, in));
}

// A technique policy's `lod` parameter index and max-mip slot (kLodParam, kMaxMipSlot), both -1
// when it has none.
struct SearchLodIndex {
  int param = -1, slot = -1;
};
template <class Search>
constexpr SearchLodIndex search_lod_of() {
  if constexpr (requires { Search::kLodParam; })
    return {Search::kLodParam, Search::kMaxMipSlot};
  else
    return {};
}

// Whether a technique policy samples the depth map it is handed (true unless it says otherwise).
template <class Search>
constexpr bool samples_depth_map() {
  if constexpr (requires { Search::kSamplesDepthMap; })
    return Search::kSamplesDepthMap;
  else
    return true;
}

// The factor height-field AO (shaders_cpp/height_ao.h) multiplies the hit's occlusion by, its
// fetches added to `o`: through the search's depth source, or for a technique that never samples
// it (the cone family) the depth map at the per-quad LOD, as the GLSL twin reads it.
template <class Search, class F>
F shell_height_ao(const MaterialUniforms& m, const FragIn<F>& in, const TextureDepth& depth,
                  const SearchHit<F>& hit, mask_t<F> active, ShadeOut<F>& o) {
  const float depth_scale = m.params[Search::kDepthScale];
  HeightAoResult<F> r;
  if constexpr (samples_depth_map<Search>())
    r = height_field_ao(depth, hit.uv, m.height_ao.rays, m.height_ao.radius, depth_scale, active);
  else
    r = height_field_ao(material_depth(m, in), hit.uv, m.height_ao.rays, m.height_ao.radius,
                        depth_scale, active);
  o.fetches += r.fetches;
  return height_ao_factor(r.ao, m.height_ao.strength);
}

// The colour of the surface point `pos` (shading normal n, unit eye-to-point direction w, uv in
// varying space) through finish_surface and shade_direct: light i's visibility is
// ray_visibility(i, l, lit) and then, with kReceive, the light's shadow map at pos where that left
// the point lit. Fetches and shadow steps are added to `o`.
template <bool kReceive, class F, class RayVisibility>
V3<F> shade_point(const ShadeContext& ctx, const FragIn<F>& in, const V2<F>& uv, const V3<F>& pos,
                  const V3<F>& n, const V3<F>& w, SurfaceColor<F>& sc, mask_t<F> active,
                  ShadeOut<F>& o, RayVisibility&& ray_visibility) {
  auto visibility = [&](int i, V3<F> l, mask_t<F> lit) -> F {
    F vis = ray_visibility(i, l, lit);
    if constexpr (kReceive) {
      if (const ShadowMapView* sm = ctx.frame->lights[i].shadow)
        vis =
            vis * shadow_map_visibility(*sm, pos, n, l, active & lit & (vis > F(0.0f)), o.fetches);
    }
    return vis;
  };
  return finish_surface(ctx, in, uv, sc, o.fetches, [&] {
    return shade_direct(*ctx.frame, *ctx.material, pos, n, -w, sc, visibility);
  });
}

// A self-shadow ray of Search::shadow_pair: Search::shadow's arguments but the context and the
// output.
template <class F>
struct ShadowQuery {
  const TextureDepth& depth;
  const SearchHit<F>& hit;
  V2<F> dl;
  F lz;
  mask_t<F> lit;
};

template <class Search, EffectMask kEffects>
struct ReliefKernel {
  static constexpr bool kShadow = (kEffects & kEffectSelfShadow) != 0;
  static constexpr bool kDepth = (kEffects & (kEffectDepthWrite | kEffectShadowPass)) != 0;
  static constexpr bool kShadowPass = (kEffects & kEffectShadowPass) != 0;
  static constexpr bool kReceive = (kEffects & kEffectReceiveShadow) != 0;

  // What the kernel knows before the search: the view, the ray's texture-space step, the covered
  // lanes and the depth source at its per-quad LODs.
  template <class F>
  struct Ray {
    // User-provided, as ShadeOut's (plugins/shading.h): compiled for this namespace's target.
    Ray(const ShadeContext& ctx, const FragIn<F>& in)
        : view(shell_view(ctx, in)),
          depth_scale(ctx.material->params[Search::kDepthScale]),
          ds(texture_step(view.V, depth_scale)),
          active(covered_lanes(in)),
          depth(samples_depth_map<Search>()
                    ? material_depth(*ctx.material, in, search_lod_of<Search>().param,
                                     search_lod_of<Search>().slot)
                    : TextureDepth{ctx.material->textures[kDepthSlot],
                                   &ctx.material->samplers[kDepthSlot],
                                   {},
                                   {}}) {}
    ShellView<F> view;
    F depth_scale;
    V2<F> ds;
    mask_t<F> active;
    TextureDepth depth;
  };

  // The hit of the ray, or the fragment's own uv at depth 0 without a depth map.
  template <class F>
  static SearchHit<F> search(const ShadeContext& ctx, const FragIn<F>& in, const Ray<F>& r) {
    if (!r.depth.texture) return unmoved_hit(in);
    return Search::search(ctx, in, r.depth, r.view.V, r.ds, r.active);
  }

  // The hit recorded in `o` (uv, depth, counters; the corrected depth when the variant writes
  // one); returns its world point.
  template <class F>
  static V3<F> record(const ShadeContext& ctx, const FragIn<F>& in, const Ray<F>& r,
                      const SearchHit<F>& hit, ShadeOut<F>& o) {
    const V3<F> pos = record_hit(in, r.view, r.depth_scale, hit, o);
    if constexpr (kDepth) o.depth = corrected_depth(ctx, in, pos);
    return pos;
  }

  // The surface at the hit before it is lit: its world point, shading normal and colour.
  template <class F>
  struct Surface {
    V3<F> pos, n;
    SurfaceColor<F> sc;
  };
  template <class F>
  static Surface<F> surface(const ShadeContext& ctx, const FragIn<F>& in, const Ray<F>& r,
                            const SearchHit<F>& hit, ShadeOut<F>& o) {
    const MaterialUniforms& m = *ctx.material;
    const V3<F> pos = record(ctx, in, r, hit, o);
    const V3<F> n = sample_normal_map(m, kNormalSlot, r.view.tf, hit.uv, in, F(1.0f), o.fetches);
    SurfaceColor<F> sc = sample_surface(m, kBaseColorSlot, hit.uv, in, o.fetches, &o.alpha);
    if (m.height_ao.rays > 0 && r.depth.texture)  // kEffectHeightAo: uniform, no work when off
      sc.occlusion = sc.occlusion * shell_height_ao<Search>(m, in, r.depth, hit, r.active, o);
    if constexpr (kShadow && requires { Search::self_occlusion(ctx, hit); })
      sc.occlusion = sc.occlusion * Search::self_occlusion(ctx, hit);
    return {pos, n, sc};
  }

  // The self-shadow ray of the hit towards world direction l (a light's, from light_toward) on
  // the lit lanes: its texture-space step and tangent-space z.
  template <class F>
  struct LightRayOf {
    V2<F> dl;
    F lz;
  };
  template <class F>
  static LightRayOf<F> light_ray_of(const Ray<F>& r, const V3<F>& l) {
    const V3<F> lt = r.view.tf.to_tangent(l);
    return {light_step(lt, r.depth_scale), lt.z};
  }

  // The self-shadow visibility of the hit towards world direction l on the lanes `lit`
  // (Search::shadow); 1 without self-shadow or a depth map.
  template <class F>
  static F self_shadow(const ShadeContext& ctx, const Ray<F>& r, const SearchHit<F>& hit,
                       const V3<F>& l, mask_t<F> lit, ShadeOut<F>& o) {
    if constexpr (kShadow) {
      if (r.depth.texture) {
        const LightRayOf<F> lr = light_ray_of(r, l);
        return Search::shadow(ctx, r.depth, hit, lr.dl, lr.lz, r.active & lit, o);
      }
    }
    return F(1.0f);
  }

  // Each light's self-shadow visibility at the hit, traced before the lighting: vis[i] for light
  // i, on the lanes light_toward says it reaches (what sum_lights hands the visibility); 1 where no
  // lane faces it, and for every light without self-shadow or a depth map.
  template <class F>
  static void self_shadows(const ShadeContext& ctx, const Ray<F>& r, const SearchHit<F>& hit,
                           const Surface<F>& s, ShadeOut<F>& o, F* vis) {
    const FrameUniforms& frame = *ctx.frame;
    for (int i = 0; i < frame.num_lights; ++i) vis[i] = F(1.0f);
    if constexpr (kShadow) {
      for (int i = 0; i < frame.num_lights; ++i) {
        const LightToward<F> lt = light_toward(frame.lights[i], s.pos, s.n);
        if (any(lt.lit)) vis[i] = self_shadow(ctx, r, hit, lt.ls.l, lt.lit, o);
      }
    }
  }

  // The lit colour of surface s, light i's self-shadow visibility ray_visibility(i, l, lit).
  template <class F, class RayVisibility>
  static void light_with(const ShadeContext& ctx, const FragIn<F>& in, const Ray<F>& r,
                         const SearchHit<F>& hit, const Surface<F>& s, ShadeOut<F>& o,
                         RayVisibility&& ray_visibility) {
    SurfaceColor<F> sc = s.sc;
    o.color = shade_point<kReceive>(ctx, in, hit.uv, s.pos, s.n, r.view.w, sc, r.active, o,
                                    ray_visibility);
    o.shading_normal = s.n;
  }
  // light_with the visibilities self_shadows traced, vis[i] for light i.
  template <class F>
  static void light(const ShadeContext& ctx, const FragIn<F>& in, const Ray<F>& r,
                    const SearchHit<F>& hit, const Surface<F>& s, const F* vis, ShadeOut<F>& o) {
    light_with(ctx, in, r, hit, s, o, [&](int i, const V3<F>&, mask_t<F>) { return vis[i]; });
  }

  // Everything after the search: the corrected depth, and outside the shadow pass the surface
  // shaded at the hit, each light's self-shadow ray traced as the lighting asks for it (one
  // group; a pair traces them first, finish_pair).
  template <class F>
  static ShadeOut<F> finish(const ShadeContext& ctx, const FragIn<F>& in, const Ray<F>& r,
                            const SearchHit<F>& hit) {
    ShadeOut<F> o;
    if constexpr (kShadowPass) {
      record(ctx, in, r, hit, o);
      // MASK casters cut their shadow where the base colour at the hit is below the cutoff
      if (ctx.material->alpha_mode == AlphaMode::kMask)
        o.alpha = sample_alpha(*ctx.material, kBaseColorSlot, hit.uv, in, o.fetches);
      return o;
    } else {
      const Surface<F> s = surface(ctx, in, r, hit, o);
      light_with(ctx, in, r, hit, s, o, [&](int, const V3<F>& l, mask_t<F> lit) {
        return self_shadow(ctx, r, hit, l, lit, o);
      });
      return o;
    }
  }

  // Two groups of lanes at once where the technique searches two side by side
  // (Search::search_pair; shade_lanes in plugins/shading.h walks a packet two groups at a time):
  // the same outputs as shade() of each. With Search::shadow_pair the two groups' self-shadow
  // rays of each light are traced side by side too.
  static constexpr bool kPaired = requires { Search::kPairedSearch; };
  static constexpr bool kPairedShadow = kShadow && requires { Search::kPairedShadow; };

  // A paired kernel's lane loop (both groups of a pair, and a packet's odd last group) calls the
  // surface and the lighting out of line, each compiled once: the lighting is most of a kernel's
  // code, and a copy of it inlined at each call doubled the plugin's compile time.
  template <class F>
  RELIEF_LANE_FLATTEN __attribute__((noinline)) static Surface<F> surface_out_of_line(
      const ShadeContext& ctx, const FragIn<F>& in, const Ray<F>& r, const SearchHit<F>& hit,
      ShadeOut<F>& o) {
    return surface(ctx, in, r, hit, o);
  }
  template <class F>
  RELIEF_LANE_FLATTEN __attribute__((noinline)) static void light_out_of_line(
      const ShadeContext& ctx, const FragIn<F>& in, const Ray<F>& r, const SearchHit<F>& hit,
      const Surface<F>& s, const F* vis, ShadeOut<F>& o) {
    light(ctx, in, r, hit, s, vis, o);
  }
  // finish(), from the out-of-line parts in a paired kernel's lane loop (the shadow pass's
  // finish, the hit and its depth, is small enough to inline).
  template <class F>
  static ShadeOut<F> finish_once(const ShadeContext& ctx, const FragIn<F>& in, const Ray<F>& r,
                                 const SearchHit<F>& hit) {
    if constexpr (kPaired && is_lanes_v<F> && !kShadowPass) {
      ShadeOut<F> o;
      const Surface<F> s = surface_out_of_line(ctx, in, r, hit, o);
      F vis[kMaxLights];
      self_shadows(ctx, r, hit, s, o, vis);
      light_out_of_line(ctx, in, r, hit, s, vis, o);
      return o;
    } else {
      return finish(ctx, in, r, hit);
    }
  }

  // self_shadows() of two groups, each light's rays traced side by side (Search::shadow_pair; a
  // group no lane of which faces the light traces nothing and counts nothing there).
  template <class F>
  static void self_shadows_pair(const ShadeContext& ctx, const Ray<F>& ra, const Ray<F>& rb,
                                const SearchHit<F>& hit_a, const SearchHit<F>& hit_b,
                                const Surface<F>& sa, const Surface<F>& sb, ShadeOut<F>& oa,
                                ShadeOut<F>& ob, F* vis_a, F* vis_b) {
    const FrameUniforms& frame = *ctx.frame;
    for (int i = 0; i < frame.num_lights; ++i) vis_a[i] = vis_b[i] = F(1.0f);
    if (!ra.depth.texture) return;
    for (int i = 0; i < frame.num_lights; ++i) {
      const LightToward<F> ta = light_toward(frame.lights[i], sa.pos, sa.n);
      const LightToward<F> tb = light_toward(frame.lights[i], sb.pos, sb.n);
      if (none(ta.lit) && none(tb.lit)) continue;
      const LightRayOf<F> la = light_ray_of(ra, ta.ls.l), lb = light_ray_of(rb, tb.ls.l);
      Search::shadow_pair(ctx, {ra.depth, hit_a, la.dl, la.lz, ra.active & ta.lit},
                          {rb.depth, hit_b, lb.dl, lb.lz, rb.active & tb.lit}, oa, ob, vis_a[i],
                          vis_b[i]);
    }
  }

  template <class F>
  static void finish_pair(const ShadeContext& ctx, const FragIn<F>& in_a, const FragIn<F>& in_b,
                          const Ray<F>& ra, const Ray<F>& rb, const SearchHit<F>& hit_a,
                          const SearchHit<F>& hit_b, ShadeOut<F>& out_a, ShadeOut<F>& out_b) {
    if constexpr (kPairedShadow && !kShadowPass) {
      ShadeOut<F> oa, ob;
      const Surface<F> sa = surface_out_of_line(ctx, in_a, ra, hit_a, oa);
      const Surface<F> sb = surface_out_of_line(ctx, in_b, rb, hit_b, ob);
      F vis_a[kMaxLights], vis_b[kMaxLights];
      self_shadows_pair(ctx, ra, rb, hit_a, hit_b, sa, sb, oa, ob, vis_a, vis_b);
      light_out_of_line(ctx, in_a, ra, hit_a, sa, vis_a, oa);
      light_out_of_line(ctx, in_b, rb, hit_b, sb, vis_b, ob);
      out_a = oa;
      out_b = ob;
    } else {
      out_a = finish_once(ctx, in_a, ra, hit_a);
      out_b = finish_once(ctx, in_b, rb, hit_b);
    }
  }

  template <class F>
  static ShadeOut<F> shade(const ShadeContext& ctx, const FragIn<F>& in) {
    const Ray<F> r(ctx, in);
    return finish_once(ctx, in, r, search(ctx, in, r));
  }

  template <class F>
  static void shade_pair(const ShadeContext& ctx, const FragIn<F>& in_a, const FragIn<F>& in_b,
                         ShadeOut<F>& out_a, ShadeOut<F>& out_b) {
    const Ray<F> ra(ctx, in_a), rb(ctx, in_b);
    SearchHit<F> hit_a = unmoved_hit(in_a), hit_b = unmoved_hit(in_b);
    if (ra.depth.texture)
      Search::search_pair(ctx, in_a, in_b, ra.depth, rb.depth, ra.ds, rb.ds, ra.active, rb.active,
                          hit_a, hit_b);
    finish_pair(ctx, in_a, in_b, ra, rb, hit_a, hit_b, out_a, out_b);
  }
};

// The effects every plugin built on the shell supports.
inline constexpr EffectMask kReliefShellEffects = kEffectSelfShadow | kEffectDepthWrite |
                                                  kEffectShadowPass | kEffectReceiveShadow |
                                                  kEffectHeightAo;

// The main-pass packet shader of `Search` with the effects kR (0 or kEffectReceiveShadow) and
// self-shadow / depth write from `e`.
template <class Search, EffectMask kR>
ShadeFn select_lit_relief_variant(EffectMask e) {
  constexpr EffectMask kS = kEffectSelfShadow, kD = kEffectDepthWrite;
  if (e & kD)
    return (e & kS) ? &shade_packet<ReliefKernel<Search, kS | kD | kR>>
                    : &shade_packet<ReliefKernel<Search, kD | kR>>;
  return (e & kS) ? &shade_packet<ReliefKernel<Search, kS | kR>>
                  : &shade_packet<ReliefKernel<Search, kR>>;
}

// The packet shader of `Search` for a combination of effects (one instantiation each).
template <class Search>
ShadeFn select_relief_variant(EffectMask e) {
  if (e & kEffectShadowPass) return &shade_packet<ReliefKernel<Search, kEffectShadowPass>>;
  return (e & kEffectReceiveShadow) ? select_lit_relief_variant<Search, kEffectReceiveShadow>(e)
                                    : select_lit_relief_variant<Search, 0>(e);
}

// Relief depth only moves away from the viewer: the conservative early test holds.
inline DepthOutput relief_depth_output(EffectMask e) {
  return (e & (kEffectDepthWrite | kEffectShadowPass)) ? DepthOutput::kFarther : DepthOutput::kNone;
}

// The marched self-shadow ray of shaders_cpp/shadow.h with a start offset `bias` in depth units.
template <class F>
F marched_shadow(const TextureDepth& depth, const SearchHit<F>& hit, const V2<F>& dl, const F& lz,
                 int steps, float bias, mask_t<F> lit, ShadeOut<F>& o) {
  const ShadowResult<F> sr = self_shadow(depth, hit.uv, hit.depth, dl, lz, steps, bias, lit);
  o.shadow_steps += sr.steps;
  o.fetches += sr.fetches;
  return sr.visibility;
}

// The marched shadow as a policy's `shadow` member, for techniques whose ray starts 0.01 depth
// units above the hit and takes the schema's shadow_steps (at index kStepsParam).
template <int kStepsParam>
struct MarchedShadow {
  template <class F>
  static F shadow(const ShadeContext& ctx, const TextureDepth& depth, const SearchHit<F>& hit,
                  const V2<F>& dl, const F& lz, mask_t<F> lit, ShadeOut<F>& o) {
    const int steps = static_cast<int>(ctx.material->params[kStepsParam]);
    return marched_shadow(depth, hit, dl, lz, steps, 0.01f, lit, o);
  }
};

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_PLUGINS_RELIEF_SHELL_H_
