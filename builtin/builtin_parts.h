// Small parts the built-in scenes (builtin/builtin*.cpp) share: a camera aimed at a point, a
// directional light and a shadow-casting spot light.
#pragma once

#include <string>

#include <glm/geometric.hpp>

#include "scene/scene.h"

namespace relief {

// A perspective camera at `eye` aimed at `target` (up +y), near plane 0.05.
inline Camera look_at(const std::string& name, glm::vec3 eye, glm::vec3 target, float yfov_deg,
                      float zfar) {
  Camera c;
  c.name = name;
  c.position = eye;
  c.target = target;
  c.yfov_deg = yfov_deg;
  c.znear = 0.05f;
  c.zfar = zfar;
  return c;
}

// A directional light travelling along `direction` (normalised here); casts no shadows.
inline Light directional_light(const std::string& name, glm::vec3 direction, glm::vec3 color,
                               float intensity = 1.0f) {
  Light l;
  l.name = name;
  l.type = LightType::kDirectional;
  l.direction = glm::normalize(direction);
  l.color = color;
  l.intensity = intensity;
  return l;
}

// The spot light "spot" at `position` aimed at `target`, casting shadows into a 1024^2 map.
inline Light shadow_spot(glm::vec3 position, glm::vec3 target, glm::vec3 color, float intensity,
                         float inner_cone_deg, float outer_cone_deg) {
  Light l;
  l.name = "spot";
  l.type = LightType::kSpot;
  l.position = position;
  l.direction = glm::normalize(target - position);
  l.color = color;
  l.intensity = intensity;
  l.inner_cone_deg = inner_cone_deg;
  l.outer_cone_deg = outer_cone_deg;
  l.casts_shadows = true;
  l.shadow_resolution = 1024;
  return l;
}

}  // namespace relief
