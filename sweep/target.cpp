// Adaptive quality (sweep/sweep.h): the view angles a scene's camera sees a material under, and
// the cheapest measured setting whose p99 hit error stays under a target at all of them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "sweep/sweep.h"

namespace relief::sweep {

std::vector<double> scene_view_angles(const Scene& scene, int material, int camera, int width,
                                      int height) {
  const Camera& cam = scene.cameras.at(camera);
  const glm::mat4 vp = cam.projection(static_cast<float>(width) / height) * cam.view();
  const glm::vec3 forward = glm::normalize(cam.target - cam.position);
  const bool two_sided = scene.materials.at(material).double_sided;
  // (angle, weight): each sample weighted by the screen area it stands for, cos / distance^2
  // under perspective (cos under orthographic), so the percentiles are over pixels, not over
  // world area
  std::vector<std::pair<double, double>> samples;
  size_t triangles = 0;
  for (const Instance& inst : scene.instances)
    if (inst.material == material) triangles += scene.meshes.at(inst.mesh).indices.size() / 3;
  const int grid =
      std::clamp(static_cast<int>(200.0 / std::sqrt(std::max<size_t>(triangles, 1))), 3, 40);
  for (const Instance& inst : scene.instances) {
    if (inst.material != material) continue;
    const Mesh& m = scene.meshes.at(inst.mesh);
    const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(inst.transform)));
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      const uint32_t k[3] = {m.indices[t], m.indices[t + 1], m.indices[t + 2]};
      // a grid of barycentric samples inside the triangle
      for (int a = 0; a < grid; ++a)
        for (int b = 0; a + b < grid; ++b) {
          const float w1 = (a + 0.33f) / (grid + 0.5f), w2 = (b + 0.33f) / (grid + 0.5f);
          const float w0 = 1.0f - w1 - w2;
          const glm::vec3 p =
              w0 * m.positions[k[0]] + w1 * m.positions[k[1]] + w2 * m.positions[k[2]];
          const glm::vec3 n = w0 * m.normals[k[0]] + w1 * m.normals[k[1]] + w2 * m.normals[k[2]];
          const glm::vec3 wp = glm::vec3(inst.transform * glm::vec4(p, 1.0f));
          const glm::vec4 c = vp * glm::vec4(wp, 1.0f);
          if (!(c.w > 0.0f) || std::fabs(c.x) > c.w || std::fabs(c.y) > c.w || c.z < 0.0f ||
              c.z > c.w)
            continue;
          const glm::vec3 wn = glm::normalize(nm * n);
          const glm::vec3 to_eye = cam.orthographic ? -forward : glm::normalize(cam.position - wp);
          double cosv = glm::dot(wn, to_eye);
          if (two_sided) cosv = std::fabs(cosv);
          if (!(cosv > 0.0)) continue;  // back-facing
          const double d2 = cam.orthographic ? 1.0 : glm::dot(cam.position - wp, cam.position - wp);
          samples.emplace_back(glm::degrees(std::acos(std::min(cosv, 1.0))),
                               cosv / std::max(d2, 1e-12));
        }
    }
  }
  if (samples.empty()) return {};
  std::sort(samples.begin(), samples.end());
  double total = 0.0;
  for (const auto& s : samples) total += s.second;
  std::set<double> out;
  for (double q : {0.10, 0.50, 0.90}) {
    double acc = 0.0;
    for (const auto& [angle, w] : samples) {
      acc += w;
      if (acc >= q * total) {
        out.insert(std::min(89.0, std::round(angle)));
        break;
      }
    }
  }
  out.insert(std::min(89.0, std::round(samples.back().first)));
  return {out.begin(), out.end()};
}

namespace {

std::string row_line(const Row& r) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "    %5.0f deg: %7.0f ns/frag, p99 %.4f texel, mean %.4f, wrong layer %.4f",
                r.angle, r.ns_median, r.hit_err_p99, r.hit_err_mean, r.wrong_layer_frac);
  return buf;
}

}  // namespace

Pick pick_cheapest(const std::vector<Row>& rows, const std::string& field,
                   const std::vector<double>& angles, double target) {
  struct Candidate {
    std::string technique, setting;
    std::vector<const Row*> rows;  // one per angle, in `angles` order
    double ns = 0.0, worst = 0.0;
    const Row* failed = nullptr;  // the first angle over the target
  };
  std::vector<Candidate> cands;
  std::map<std::string, size_t> by_setting;
  for (const Row& r : rows) {
    if (r.field != field) continue;
    auto it = by_setting.find(r.setting);
    if (it == by_setting.end()) {
      it = by_setting.emplace(r.setting, cands.size()).first;
      cands.push_back({r.technique, r.setting, {}, 0.0, 0.0, nullptr});
    }
    cands[it->second].rows.push_back(&r);
  }
  std::vector<Candidate> complete;
  for (Candidate& c : cands) {
    std::vector<const Row*> ordered;
    for (double a : angles)
      for (const Row* r : c.rows)
        if (std::fabs(r->angle - a) < 1e-9) {
          ordered.push_back(r);
          break;
        }
    if (ordered.size() != angles.size() || angles.empty()) continue;  // not measured at every angle
    c.rows = ordered;
    for (const Row* r : c.rows) {
      c.ns += r->ns_median / static_cast<double>(c.rows.size());
      c.worst = std::max(c.worst, r->hit_err_p99);
      if (!c.failed && !(r->hit_err_p99 < target)) c.failed = r;
    }
    complete.push_back(c);
  }
  std::sort(complete.begin(), complete.end(),
            [](const Candidate& a, const Candidate& b) { return a.ns < b.ns; });
  Pick p;
  std::ostringstream why;
  char buf[256];
  for (const Candidate& c : complete) {
    if (c.failed) {
      std::snprintf(buf, sizeof buf,
                    "  rejected %-20s %7.0f ns/frag: p99 %.4f texel >= %.4g at %.0f deg\n",
                    c.setting.c_str(), c.ns, c.failed->hit_err_p99, target, c.failed->angle);
      why << buf;
      continue;
    }
    p.found = true;
    p.technique = c.technique;
    p.setting = c.setting;
    p.ns = c.ns;
    p.worst_p99 = c.worst;
    std::snprintf(
        buf, sizeof buf,
        "  chose    %-20s %7.0f ns/frag (mean over the angles): the cheapest with p99 < %.4g "
        "texel at every angle; its rows:\n",
        c.setting.c_str(), c.ns, target);
    why << buf;
    for (const Row* r : c.rows) why << row_line(*r) << "\n";
    break;
  }
  if (!p.found) {
    std::snprintf(buf, sizeof buf, "  no measured setting has p99 < %.4g texel at every angle\n",
                  target);
    why << buf;
  }
  p.why = why.str();
  return p;
}

}  // namespace relief::sweep
