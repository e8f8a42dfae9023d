// Shadow passes (Williams, "Casting Curved Shadows on Curved Surfaces", SIGGRAPH 1978): where a
// light's depth map is taken from, the uniforms of its depth pass, and the view receivers read.
//
// A directional light gets an orthographic view along its direction, fitted in x and y to the
// bounds of the visible receivers (their world boxes clipped to the camera's view box) plus a
// filter margin, and in depth from the nearest caster to the farthest receiver. A spot light gets
// a perspective view down its axis covering its outer cone; a point light a cube of six 90 degree
// faces (+x, -x, +y, -y, +z, -z). Perspective near and far planes enclose every caster and
// receiver. In the depth pass the light is the "eye" of FrameUniforms (orthographic with view_dir
// for a directional light), so relief casters run their intersection from the light and write the
// corrected depth (quadric paper, Oliveira and Policarpo 2005, section 3.5 and figure 13).
#pragma once

#include <limits>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "base/status.h"
#include "plugins/plugin.h"
#include "rasterizer/image.h"
#include "scene/scene.h"
#include "shaders_cpp/shadow_lookup.h"

namespace relief {

// An axis-aligned world box; empty until a point is added.
struct Bounds {
  glm::vec3 lo{std::numeric_limits<float>::max()};
  glm::vec3 hi{-std::numeric_limits<float>::max()};
  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  void add(glm::vec3 p);
  void add(const Bounds& b);
  glm::vec3 corner(int i) const;  // i in 0..7
};

// World bounds of an instance's vertices (non-finite positions are skipped).
Bounds instance_bounds(const Scene& scene, int instance);
// Conservative: false only when the box lies wholly outside one plane of the clip volume.
bool bounds_in_view(const Bounds& b, const glm::mat4& view_proj);
// The world box of the view volume of `view_proj` (reversed-Z), intersected with `b`.
Bounds clip_to_view(const Bounds& b, const glm::mat4& view_proj);

// Where a light's depth pass looks from.
struct ShadowPassSetup {
  LightType type = LightType::kDirectional;
  int size = 0;   // texels per side (Light::shadow_resolution)
  int faces = 0;  // 1, or 6 for a point light
  bool orthographic = false;
  glm::vec3 position{0.0f};  // perspective: the light; orthographic: the view's origin
  glm::mat4 view[kMaxShadowFaces];
  glm::mat4 proj[kMaxShadowFaces];
  glm::vec3 forward[kMaxShadowFaces];  // direction each face looks
  float znear = 0.0f, zfar = 0.0f;
  float texel = 0.0f;  // see ShadowMapView::texel
};

// Fits the depth pass of `light` to the visible receivers' bounds and the casters' bounds (both
// non-empty). The light's shadow_resolution must be in 16..kMaxTargetSize (checked by the planner).
ShadowPassSetup fit_shadow_pass(const Light& light, const Bounds& receivers, const Bounds& casters,
                                const ShadowSettings& settings);

// How a shadow map's resolution is chosen (RenderOptions::shadow_size, `--shadow-size`).
//   kLight (the default): the light's shadow_resolution, whatever the view.
//   kView: the light's shadow_resolution is the most; fewer texels per side when the view cannot
//     resolve them: the smallest size at which one texel, at every point of the visible receivers'
//     polygons, covers no more world than one pixel of the view there (view_shadow_size). Not the
//     default: the depth bias and the PCF footprint are counted in texels, so a coarser map also
//     loses shadow detail finer than them, such as the shadows relief casters write into their
//     grooves (docs/performance.md, "A shadow map the view needs").
enum class ShadowSize { kLight, kView };

// The visible receivers' surfaces: each triangle of the instances in `instances`, clipped to the
// view volume of `view_proj` (reversed-Z), as a convex polygon in world space (the empty ones
// left out). Past `budget` triangles they are strided (every k-th), and the result samples the
// surface instead of covering it.
std::vector<std::vector<glm::vec3>> visible_receiver_polygons(const Scene& scene,
                                                              const std::vector<int>& instances,
                                                              const glm::mat4& view_proj,
                                                              size_t budget = 65536);

// The side of a shadow map framed as `setup` at which a texel covers, at each point of
// `polygons` the map sees, at most the world size of one pixel of a view `height` pixels high
// with projection `proj` (reversed-Z; orthographic or perspective) and view matrix `view`: a
// texel is setup.texel * setup.size / side at distance 1 from a perspective light (times the
// distance along the face's axis), everywhere for an orthographic one; a pixel is 2 w / (height *
// |proj[1][1]|) with w the point's clip w. Both are affine in the point, so their ratio is
// largest at a corner of each polygon's part inside a face's map, and the corners are where it
// is evaluated. Clamped to 16..max_side; max_side when no point is seen or one lies at the eye.
int view_shadow_size(const ShadowPassSetup& setup,
                     const std::vector<std::vector<glm::vec3>>& polygons, const glm::mat4& view,
                     const glm::mat4& proj, int height, int max_side);

// The uniforms of one face's depth pass: the light as the eye, no lights, no AOVs.
FrameUniforms shadow_face_frame(const ShadowPassSetup& setup, int face);

// What receivers read: `faces` holds setup.faces depth planes of setup.size squared (row by row),
// which must outlive the view.
ShadowMapView make_shadow_view(const ShadowPassSetup& setup, std::span<const float* const> faces,
                               const ShadowSettings& settings);

// One line: projection, resolution, planes (for --explain).
std::string describe_shadow_pass(const ShadowPassSetup& setup);

}  // namespace relief
