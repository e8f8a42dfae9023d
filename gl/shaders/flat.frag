#version 450 core
// `flat`: GLSL twin of plugins/flat.cpp. Lambert and Blinn-Phong over the interpolated normal
// and a base colour (texture or constant). The baseline every relief technique is compared
// against.
#include "common.glsl"

const int kBaseColorSlot = 0;

float visibility(int i, vec3 l) { return 1.0; }  // NoShadow

ShadeOut shade(FragIn in_) {
  ShadeOut o = shade_out_default();
  vec3 n = normalize_safe(in_.normal);
  if (!in_.front_facing) n = -n;
  vec3 albedo = material.base_color.rgb;
  if (has_texture[kBaseColorSlot]) {
    vec4 c = textureGrad(textures[kBaseColorSlot], in_.uv, in_.duv_dx, in_.duv_dy);
    albedo = albedo * c.xyz;
    o.fetches = 1.0;
  }
  vec3 v = normalize_safe(frame.eye - in_.position);
  o.color = blinn_phong(in_.position, n, v, albedo);
  o.alpha = material.base_color.a;
  o.hit_uv = in_.uv;
  o.shading_normal = n;
  return o;
}

void main() { store_out(shade(load_fragment())); }
