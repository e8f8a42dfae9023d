#include "scene/scene.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace relief {

glm::mat4 perspective_reversed_z(float yfov_rad, float aspect, float znear, float zfar) {
  // Eye space looks down -z. z_clip = A z + B, w = -z: depth 1 at -znear, 0 at -zfar.
  const float f = 1.0f / std::tan(yfov_rad * 0.5f);
  const float a = znear / (zfar - znear);
  const float b = znear * zfar / (zfar - znear);
  glm::mat4 m(0.0f);
  m[0][0] = f / aspect;
  m[1][1] = f;
  m[2][2] = a;
  m[2][3] = -1.0f;
  m[3][2] = b;
  return m;
}

glm::mat4 ortho_reversed_z(float l, float r, float bottom, float top, float znear, float zfar) {
  glm::mat4 m(1.0f);
  m[0][0] = 2.0f / (r - l);
  m[1][1] = 2.0f / (top - bottom);
  m[3][0] = -(r + l) / (r - l);
  m[3][1] = -(top + bottom) / (top - bottom);
  // depth = (z + zfar) / (zfar - znear) for eye z in [-zfar, -znear]: 1 at near, 0 at far.
  m[2][2] = 1.0f / (zfar - znear);
  m[3][2] = zfar / (zfar - znear);
  return m;
}

glm::mat4 Camera::view() const {
  return glm::lookAt(position, target, up);
}

glm::mat4 Camera::projection(float aspect) const {
  if (orthographic) {
    const float h = ortho_half_height, w = h * aspect;
    return ortho_reversed_z(-w, w, -h, h, znear, zfar);
  }
  return perspective_reversed_z(glm::radians(yfov_deg), aspect, znear, zfar);
}

}  // namespace relief
