#version 450 core
// `exact`: GLSL twin of plugins/exact.cpp. The exact first hit on the bilinear height field, the
// accuracy reference (Tevs, Ihrke and Seidel, "Maximum Mipmaps for Fast, Accurate, and Scalable
// Dynamic Height Field Rendering", I3D 2008: max-mip traversal; per-cell closed-form patch solve),
// in the relief shell. The max-mip is the HeightFieldBuffer of exact.glsl.

#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kDepthScale = kParam_exact_depth_scale;
const int kBaseColorSlot = kSlot_exact_base_color;
const int kNormalSlot = kSlot_exact_normal;
const int kDepthSlot = kSlot_exact_depth;

#include "relief_shell.glsl"
#include "exact.glsl"

SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds) {
  if (hf_num_levels > 0) return exact_search(in_.uv, ds);
  return SearchHit(in_.uv, 0.0, 0.0, 0.0);
}

float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o) {
  if (hf_num_levels <= 0) return 1.0;
  float steps;
  float vis = exact_shadow(hit.uv, hit.depth, dl, lz, 1e-3, steps);
  o.shadow_steps += steps;
  return vis;
}
