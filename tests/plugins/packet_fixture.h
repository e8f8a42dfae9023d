// The packet the plugin tests shade: the plane z = 0 with N = +z, T = +x, B = +y and uv = world
// (x, y); an 8 x 8 pixel patch of fragments `spacing` apart around (0.4, 0.6), seen at an angle
// from an eye at (-0.3, 0.1, 0.8) through an infinite reversed-Z projection (near 0.1), lit by one
// directional light.
#pragma once

#include <glm/gtc/matrix_transform.hpp>

#include "plugins/plugin.h"

namespace relief::testing {

inline void set_oblique_frame(FrameUniforms& frame) {
  frame.eye = glm::vec3(-0.3f, 0.1f, 0.8f);
  glm::mat4 proj(0.0f);
  proj[0][0] = 1.0f;
  proj[1][1] = 1.0f;
  proj[2][3] = -1.0f;
  proj[3][2] = 0.1f;
  frame.view = glm::lookAt(frame.eye, glm::vec3(0.4f, 0.6f, 0.0f), glm::vec3(0, 0, 1));
  frame.view_proj = proj * frame.view;
  frame.num_lights = 1;
  frame.lights[0].type = LightType::kDirectional;
  frame.lights[0].direction = glm::normalize(glm::vec3(0.6f, 0.2f, -0.5f));
}

// kPacketQuads quads in 4 columns; every quad fully covered except `partial_quad` (lanes 1 and 2).
inline void fill_plane_packet(FragmentPacket& packet, const FrameUniforms& frame, float spacing,
                              int partial_quad = -1) {
  packet.num_quads = kPacketQuads;
  packet.num_varyings = varying::kCount;
  packet.front_facing = true;
  for (int q = 0; q < kPacketQuads; ++q) {
    packet.coverage[q] = q == partial_quad ? 0x6 : 0xF;
    for (int l = 0; l < 4; ++l) {
      const int ln = q * 4 + l;
      const float x = 0.4f + spacing * ((q % 4) * 2 + (l & 1));
      const float y = 0.6f + spacing * ((q / 4) * 2 + (l >> 1));
      const float vals[varying::kCount] = {x, y, 0, 0, 0, 1, 1, 0, 0, 1, x, y, 0, 0, 1, 1};
      for (int k = 0; k < varying::kCount; ++k) packet.varyings[k][ln] = vals[k];
      const glm::vec4 c = frame.view_proj * glm::vec4(x, y, 0.0f, 1.0f);
      packet.frag_x[ln] = static_cast<float>(ln);
      packet.frag_y[ln] = 0.0f;
      packet.frag_z[ln] = c.z / c.w;
      packet.inv_w[ln] = 1.0f / c.w;
    }
  }
}

}  // namespace relief::testing
