// Running the sweep (sweep/sweep.h): renders each view with `exact` and with every setting, times
// the main pass, counts the work per fragment and measures the hits against exact's.
#include "sweep/sweep.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <set>
#include <string>

#include "gl/appendix_relief.h"
#include "gl/gl_backend.h"
#include "plugins/registry.h"
#include "render/compare.h"
#include "render/render.h"
#include "render/renderer.h"
#include "shaders_cpp/exact_trace.h"

namespace relief::sweep {
namespace {

// ---- per-fragment work: a counting wrapper around the plugin's packet shader ----
// The counting pass shades every covered fragment alone (a one-quad packet whose coverage holds
// only that lane, so the quad's derivatives are the same) and keeps its WorkCounters per pixel;
// the real packet is shaded as well, so the frame itself is unchanged. One counting pass at a
// time per process (the wrapper's target is a global), guarded by a mutex.
struct PixelWork {
  int width = 0;
  std::vector<float> fetches, steps;
};
std::mutex g_counting_mutex;
const PluginDescriptor* g_inner = nullptr;
ShadeFn g_inner_fn = nullptr;
PixelWork* g_sink = nullptr;

void counting_shade(const ShadeContext& ctx, const FragmentPacket& in, FragmentOutput& out,
                    WorkCounters& wc) {
  g_inner_fn(ctx, in, out, wc);
  for (int q = 0; q < in.num_quads; ++q)
    for (int l = 0; l < kQuadLanes; ++l) {
      if (!((in.coverage[q] >> l) & 1)) continue;
      FragmentPacket one{};
      one.num_quads = 1;
      one.num_varyings = in.num_varyings;
      one.front_facing = in.front_facing;
      one.coverage[0] = static_cast<uint8_t>(1u << l);
      for (int k = 0; k < kQuadLanes; ++k) {
        const int src = q * kQuadLanes + k;
        one.frag_x[k] = in.frag_x[src];
        one.frag_y[k] = in.frag_y[src];
        one.frag_z[k] = in.frag_z[src];
        one.inv_w[k] = in.inv_w[src];
        for (int v = 0; v < in.num_varyings; ++v) one.varyings[v][k] = in.varyings[v][src];
      }
      auto o = std::make_unique<FragmentOutput>();
      WorkCounters w;
      g_inner_fn(ctx, one, *o, w);
      const int lane_index = q * kQuadLanes + l;
      const size_t px = static_cast<size_t>(std::floor(in.frag_y[lane_index])) * g_sink->width +
                        static_cast<size_t>(std::floor(in.frag_x[lane_index]));
      g_sink->fetches[px] += static_cast<float>(w.texture_fetches);
      g_sink->steps[px] += static_cast<float>(w.search_steps);
    }
}
ShadeFn counting_select(EffectMask effects) {
  g_inner_fn = g_inner->select(effects);
  return &counting_shade;
}

double percentile99(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t rank = static_cast<size_t>(std::ceil(0.99 * static_cast<double>(v.size())));
  return v[std::max<size_t>(rank, 1) - 1];
}
double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}
double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void set_times(const std::vector<double>& ns, double& med, double& lo, double& hi) {
  med = median(ns);
  lo = ns.empty() ? 0.0 : *std::min_element(ns.begin(), ns.end());
  hi = ns.empty() ? 0.0 : *std::max_element(ns.begin(), ns.end());
}

// Of the pixels both cover (CPU depth > 0, GL hit alpha > 0), the fraction whose hit uv lie within
// one texel of a w x h map of each other (uv compared modulo the map's repeat).
double same_hit_fraction(const Framebuffer& cpu, const Image& gl_hits, int w, int h) {
  long both = 0, same = 0;
  for (int y = 0; y < cpu.height; ++y)
    for (int x = 0; x < cpu.width; ++x) {
      const glm::vec4& g = gl_hits.at(x, y);
      if (!(cpu.depth.at(x, y) > 0.0f) || !(g.w > 0.0f)) continue;
      const float* a = cpu.aov_at(x, y);
      double du = a[kAovOffset[0]] - g.x, dv = a[kAovOffset[0] + 1] - g.y;
      du -= std::round(du);
      dv -= std::round(dv);
      ++both;
      same += std::hypot(du * w, dv * h) <= 1.0;
    }
  return both ? static_cast<double>(same) / static_cast<double>(both) : 0.0;
}

float luminance(const glm::vec4& c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

const PassStats* main_pass(const RenderResult& r) {
  for (const PassStats& p : r.passes)
    if (p.kind == PassPlan::Kind::kMain) return &p;
  return nullptr;
}

// Everything measured of one setting on one view.
struct Measured {
  Framebuffer on;            // self-shadow on, AOVs
  std::vector<int> visible;  // per pixel: -1 not compared, 0 lit, 1 shadowed
  PixelWork work;
  std::vector<double> ns;  // per repeat
  long fragments = 0;
};

class Runner {
 public:
  Runner(const Options& o) : opt_(o), cpu_(make_cpu_backend({.threads = o.threads})) {}

  RenderOptions render_options(const Setting& s, bool aovs) const {
    RenderOptions r;
    r.width = opt_.width;
    r.height = opt_.height;
    r.technique = s.technique;
    r.params = s.params;
    r.shadows = false;
    r.self_shadow = opt_.self_shadow;
    if (aovs) r.aovs = aov_bit(Aov::kHitUv) | aov_bit(Aov::kHitDepth);
    return r;
  }

  Result<RenderResult> render(Renderer& r, const Scene& scene, const RenderOptions& ro,
                              const PluginDescriptor* wrap = nullptr) {
    Result<Plan> plan = r.plan(scene, ro);
    if (!plan.ok()) return plan.status();
    if (wrap)
      for (BoundMaterial& m : plan->materials) m.plugin = wrap;
    return r.execute(scene, *plan);
  }

  Result<Measured> measure(const Scene& scene, const Setting& s) {
    Measured m;
    const RenderOptions ro = render_options(s, true);
    std::vector<double> ms;
    for (int i = 0; i < opt_.warmup + opt_.repeats; ++i) {
      Result<RenderResult> r = render(cpu_, scene, ro);
      if (!r.ok()) return r.status();
      const PassStats* p = main_pass(*r);
      if (!p || p->raster.work.fragments == 0)
        return Status::error("no fragment covered (" + s.label + ")");
      if (i >= opt_.warmup) ms.push_back(p->ms);
      cpu_device_ = r->device;
      if (i + 1 == opt_.warmup + opt_.repeats)
        m.on = std::move(r->framebuffer);
      else
        cpu_.recycle(std::move(r).value());  // the next repeat reuses its buffers
    }
    // Per covered pixel: a one-layer technique shades each once; shells shade every layer that
    // covers it, and that work is the pixel's cost.
    m.fragments = static_cast<long>(std::count_if(
        m.on.depth.values.begin(), m.on.depth.values.end(), [](float d) { return d > 0.0f; }));
    if (m.fragments == 0) return Status::error("no pixel covered (" + s.label + ")");
    for (double t : ms) m.ns.push_back(t * 1e6 / static_cast<double>(m.fragments));
    // self-shadow off, and no lights: the sun's share of each pixel and whether it is shadowed
    Scene off = scene, dark = scene;
    off.materials[0].self_shadow = false;
    dark.lights.clear();
    Result<RenderResult> r_off = render(cpu_, off, render_options(s, false));
    if (!r_off.ok()) return r_off.status();
    RenderOptions dark_options = render_options(s, false);
    dark_options.studio_environment = false;  // the ambient term alone, as lit frames have it
    Result<RenderResult> r_dark = render(cpu_, dark, dark_options);
    if (!r_dark.ok()) return r_dark.status();
    const size_t n = m.on.color.pixels.size();
    m.visible.assign(n, -1);
    for (size_t i = 0; i < n; ++i) {
      if (!(m.on.depth.values[i] > 0.0f)) continue;
      const float base = luminance(r_dark->framebuffer.color.pixels[i]);
      const float sun = luminance(r_off->framebuffer.color.pixels[i]) - base;
      if (!(sun >= 0.05f)) continue;
      if (opt_.self_shadow) m.visible[i] = (luminance(m.on.color.pixels[i]) - base) / sun < 0.5f;
    }
    // the counting pass
    const PluginDescriptor* plugin = PluginRegistry::global().find(s.technique);
    if (!plugin) return Status::error("unknown technique '" + s.technique + "'");
    PluginDescriptor wrapper = *plugin;
    wrapper.select = &counting_select;
    m.work.width = opt_.width;
    m.work.fetches.assign(n, 0.0f);
    m.work.steps.assign(n, 0.0f);
    {
      std::lock_guard<std::mutex> lock(g_counting_mutex);
      g_inner = plugin;
      g_sink = &m.work;
      Result<RenderResult> r = render(cpu_, scene, render_options(s, false), &wrapper);
      g_sink = nullptr;
      g_inner = nullptr;
      if (!r.ok()) return r.status();
    }
    return m;
  }

  // GL timing of the setting: ns per fragment of the main pass, per repeat; empty with `note`
  // set when it cannot run.
  std::vector<double> gl_times(const Scene& scene, const Setting& s, long fragments,
                               std::string& note) {
    if (!gl_has_twin(s.technique)) {
      note = "no GLSL twin of " + s.technique + " in gl/shaders";
      return {};
    }
    if (!gl_) {
      if (!gl_error_.empty()) {
        note = gl_error_;
        return {};
      }
      // llvmpipe's threads: as many as the CPU backend's unless the caller set them
      if (opt_.threads > 0) setenv("LP_NUM_THREADS", std::to_string(opt_.threads).c_str(), 0);
      Result<std::unique_ptr<Backend>> b =
          make_gl_backend({.gl_interpolation = opt_.gl_interpolation});
      if (!b.ok()) {
        gl_error_ = "no GL context: " + b.status().message();
        note = gl_error_;
        return {};
      }
      gl_ = std::make_unique<Renderer>(std::move(b).value());
    }
    std::vector<double> ns;
    const RenderOptions ro = render_options(s, false);
    for (int i = 0; i < opt_.warmup + opt_.repeats; ++i) {
      Result<RenderResult> r = render(*gl_, scene, ro);
      if (!r.ok()) {
        note = "gl: " + r.status().message();
        return {};
      }
      gl_device_ = r->device;
      const PassStats* p = main_pass(*r);
      if (p && i >= opt_.warmup) ns.push_back(p->ms * 1e6 / static_cast<double>(fragments));
      gl_->recycle(std::move(r).value());
    }
    return ns;
  }

  // The appendix yardstick of one view (sweep.h AppendixRow).
  AppendixRow appendix(const Scene& scene, const Field& field, double angle) {
    AppendixRow row;
    row.field = field.name;
    row.angle = angle;
    AppendixLean a = appendix_lean(scene, opt_.width, opt_.height);
    const Scene& lean = a.scene;
    RenderOptions& ro = a.options;
    if (!appendix_gl_ && appendix_error_.empty()) {
      if (opt_.threads > 0) setenv("LP_NUM_THREADS", std::to_string(opt_.threads).c_str(), 0);
      Result<std::unique_ptr<gl::AppendixRelief>> a = gl::AppendixRelief::create();
      if (a.ok())
        appendix_gl_ = std::move(a).value();
      else
        appendix_error_ = "no GL context: " + a.status().message();
    }
    Status prepared = appendix_gl_
                          ? appendix_gl_->prepare(lean, opt_.width, opt_.height,
                                                  kAppendixLinearSteps, kAppendixBinarySteps)
                          : Status::error(appendix_error_);
    // the driver compiles at the first draw (llvmpipe's JIT), which the GL backend's frames
    // report apart from the pass (compile_ms): an untimed draw whatever the warm-up count
    if (prepared.ok())
      if (Result<double> first = appendix_gl_->draw(); !first.ok()) prepared = first.status();
    if (!prepared.ok()) row.note = prepared.message();
    Result<Plan> plan = cpu_.plan(lean, ro);
    if (!plan.ok()) {
      row.note = plan.status().message();
      return row;
    }
    // warm-up frames of both, then the timed pairs, one side after the other
    std::vector<double> cpu_ms, gl_ms;
    Framebuffer last;
    for (int i = 0; i < opt_.warmup + opt_.repeats; ++i) {
      Result<RenderResult> r = cpu_.execute(lean, *plan);
      if (!r.ok()) {
        row.note = r.status().message();
        return row;
      }
      const PassStats* p = main_pass(*r);
      if (i >= opt_.warmup && p) cpu_ms.push_back(p->ms);
      if (i + 1 == opt_.warmup + opt_.repeats)
        last = std::move(r->framebuffer);
      else
        cpu_.recycle(std::move(r).value());
      if (!prepared.ok()) continue;
      Result<double> g = appendix_gl_->draw();
      if (!g.ok()) {
        row.note = g.status().message();
        prepared = g.status();
        continue;
      }
      if (i >= opt_.warmup) gl_ms.push_back(*g);
    }
    row.fragments = static_cast<long>(std::count_if(
        last.depth.values.begin(), last.depth.values.end(), [](float d) { return d > 0.0f; }));
    if (row.fragments == 0) {
      row.note = "no pixel covered";
      return row;
    }
    const double per = 1e6 / static_cast<double>(row.fragments);
    for (double& t : cpu_ms) t *= per;
    set_times(cpu_ms, row.cpu_ns_median, row.cpu_ns_min, row.cpu_ns_max);
    if (!prepared.ok() || gl_ms.empty()) return row;
    for (double& t : gl_ms) t *= per;
    set_times(gl_ms, row.gl_ns_median, row.gl_ns_min, row.gl_ns_max);
    row.speedup = row.cpu_ns_median > 0.0 ? row.gl_ns_median / row.cpu_ns_median : -1.0;
    // the hits of both searches
    ro.aovs = aov_bit(Aov::kHitUv);
    Result<RenderResult> with_hits = render(cpu_, lean, ro);
    Image color, hits;
    if (!with_hits.ok() || !appendix_gl_->draw_hits(color, hits).ok()) return row;
    row.same_hit_frac = same_hit_fraction(with_hits->framebuffer, hits, field.depth().width(),
                                          field.depth().height());
    return row;
  }

  const std::string& cpu_device() const { return cpu_device_; }
  const std::string& gl_device() const { return gl_device_; }

 private:
  Options opt_;
  Renderer cpu_;
  std::unique_ptr<Renderer> gl_;
  std::unique_ptr<gl::AppendixRelief> appendix_gl_;
  std::string gl_error_, appendix_error_, cpu_device_, gl_device_;
};

// The view's constants the accuracy needs: the level-0 field, the ray and light steps, the
// air/below tolerance.
struct ViewRef {
  const HeightField* hf = nullptr;
  glm::dvec2 ds{0.0}, dl{0.0};
  double lz = 0.0;
  double tol = 0.0;  // half a texel of height, depth units
};

// Accuracy of `m` against the reference `e` on the pixels both cover.
void accuracy(const Measured& m, const Measured& e, const ViewRef& v, Row& row) {
  const Framebuffer& a = m.on;
  const Framebuffer& b = e.on;
  const HeightField& hf = *v.hf;
  const glm::dvec2 ds = v.ds;
  const double w = hf.width(), h = hf.height();
  std::vector<double> hit, depth;
  long wrong = 0, air = 0, below = 0, occlusion = 0, compared = 0, disagree = 0, ray_compared = 0,
       ray_disagree = 0;
  for (size_t i = 0; i < a.color.pixels.size(); ++i) {
    if (!(a.depth.values[i] > 0.0f) || !(b.depth.values[i] > 0.0f)) continue;
    const float* pa = &a.aov[i * kAovTotalChannels];
    const float* pb = &b.aov[i * kAovTotalChannels];
    const double ua = pa[kAovOffset[0]], va = pa[kAovOffset[0] + 1];
    const double du = (ua - pb[kAovOffset[0]]) * w;
    const double dv = (va - pb[kAovOffset[0] + 1]) * h;
    hit.push_back(std::hypot(du, dv));
    const double ta = pa[kAovOffset[1]], te = pb[kAovOffset[1]];
    depth.push_back(std::fabs(ta - te));
    // wrong layer: past exact's hit with air between them (sampled every 1/16 texel)
    bool wrong_layer = false;
    if (ta > te + 1e-4) {
      const double texels = (ta - te) * std::hypot(ds.x * w, ds.y * h);
      const int samples = static_cast<int>(std::clamp(std::ceil(texels * 16.0), 1.0, 1e5));
      const double u0 = pb[kAovOffset[0]], v0 = pb[kAovOffset[0] + 1];
      for (int k = 1; k <= samples; ++k) {
        const double t = te + (ta - te) * k / (samples + 1.0);
        if (hf.depth_at(u0 + (t - te) * ds.x, v0 + (t - te) * ds.y) - t > 1e-3) {
          wrong_layer = true;
          break;
        }
      }
    }
    // the hit against the level-0 surface at its own uv: in the air, or inside
    const double gap = hf.depth_at(ua, va) - ta;
    wrong += wrong_layer;
    air += gap > v.tol;
    below += -gap > v.tol;
    occlusion += wrong_layer || gap > v.tol;
    if (m.visible[i] >= 0 && e.visible[i] >= 0) {
      ++compared;
      disagree += m.visible[i] != e.visible[i];
    }
    if (m.visible[i] >= 0 && v.lz > 0.0) {
      ++ray_compared;
      const bool truth = hf.shadowed(ua, va, ta, v.dl.x, v.dl.y, 1e-3);
      ray_disagree += (m.visible[i] == 1) != truth;
    }
  }
  const double n = static_cast<double>(hit.size());
  row.hit_err_mean = mean(hit);
  row.hit_err_p99 = percentile99(hit);
  row.hit_err_over1_frac = hit.empty()
                               ? 0.0
                               : static_cast<double>(std::count_if(
                                     hit.begin(), hit.end(), [](double e) { return e > 1.0; })) /
                                     n;
  row.depth_err_mean = mean(depth);
  row.depth_err_p99 = percentile99(depth);
  row.wrong_layer_frac = hit.empty() ? 0.0 : static_cast<double>(wrong) / n;
  row.air_frac = hit.empty() ? 0.0 : static_cast<double>(air) / n;
  row.below_frac = hit.empty() ? 0.0 : static_cast<double>(below) / n;
  row.wrong_occlusion_frac = hit.empty() ? 0.0 : static_cast<double>(occlusion) / n;
  row.shadow_compared = compared;
  row.shadow_err = compared ? static_cast<double>(disagree) / compared : 0.0;
  row.shadow_ray_err = ray_compared ? static_cast<double>(ray_disagree) / ray_compared : 0.0;
  const ImageDiff d = compare_images(a.color, b.color);
  row.rmse = d.rmse;
  row.psnr_db = std::isfinite(d.psnr_db) ? std::min(d.psnr_db, kPsnrCap) : kPsnrCap;
}

// The report's thumbnails: `color` box-filtered by k = ceil(width / max_width), and of the heat
// map, per k x k block, the pixel whose colour differs most from exact's (so a one-pixel error
// still shows).
void thumbnails(const Image& color, const Image& ref, int max_width, RowImages& out) {
  const Image heat = diff_heatmap(color, ref);
  const int k = std::max(1, (color.width + std::max(max_width, 1) - 1) / std::max(max_width, 1));
  if (k == 1) {
    out.color = color;
    out.heat = heat;
    return;
  }
  const int w = std::max(1, color.width / k), h = std::max(1, color.height / k);
  out.color = Image(w, h);
  out.heat = Image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::vec4 sum(0.0f);
      float worst = -1.0f;
      glm::vec4 hot(0.0f);
      int count = 0;
      for (int j = y * k; j < std::min((y + 1) * k, color.height); ++j)
        for (int i = x * k; i < std::min((x + 1) * k, color.width); ++i) {
          const glm::vec4 c = color.at(i, j), r = ref.at(i, j);
          sum += c;
          ++count;
          const float e = std::max({std::fabs(c.r - r.r), std::fabs(c.g - r.g),
                                    std::fabs(c.b - r.b), std::fabs(c.a - r.a)});
          if (e > worst) {
            worst = e;
            hot = heat.at(i, j);
          }
        }
      out.color.at(x, y) = sum / static_cast<float>(std::max(count, 1));
      out.heat.at(x, y) = hot;
    }
}

void work_stats(const Measured& m, Row& row) {
  std::vector<double> f, s;
  for (size_t i = 0; i < m.on.depth.values.size(); ++i) {
    if (!(m.on.depth.values[i] > 0.0f)) continue;
    f.push_back(m.work.fetches[i]);
    s.push_back(m.work.steps[i]);
  }
  row.fetches_mean = mean(f);
  row.fetches_p99 = percentile99(f);
  row.steps_mean = mean(s);
  row.steps_p99 = percentile99(s);
}

}  // namespace

AppendixLean appendix_lean(const Scene& view, int width, int height) {
  AppendixLean a{view, {}};
  for (Material& m : a.scene.materials) {
    m.self_shadow = false;
    m.depth_write = false;
  }
  RenderOptions& r = a.options;
  r.width = width;
  r.height = height;
  r.technique = "relief";
  r.params = {{"steps", std::to_string(kAppendixLinearSteps)},
              {"min_steps", std::to_string(kAppendixLinearSteps)},
              {"binary_steps", std::to_string(kAppendixBinarySteps)},
              {"lod", "zero"}};
  r.shadows = false;
  r.self_shadow = false;
  return a;
}

Result<SweepResult> run_sweep(const std::vector<Field>& fields,
                              const std::vector<Setting>& settings, const Options& options) {
  if (options.repeats < 1 || options.warmup < 0)
    return Status::usage("--repeats: expected at least 1 (and --warmup at least 0)");
  if (options.lods.empty()) return Status::usage("--lod: expected level0, as-rendered or both");
  for (const std::string& l : options.lods)
    if (l != kLodLevel0 && l != kLodAsRendered)
      return Status::usage("--lod: expected level0, as-rendered or both, got '" + l + "'");
  SweepResult out;
  Runner runner(options);
  const Setting exact_setting{"exact", {}, "exact", 0};
  const bool appendix = options.gl && options.appendix &&
                        std::any_of(settings.begin(), settings.end(),
                                    [](const Setting& s) { return s.technique == "relief"; });
  const int total = static_cast<int>(fields.size() * options.angles.size() *
                                     (options.lods.size() * settings.size() + 1 + appendix));
  int done = 0;
  auto tick = [&](const std::string& what) {
    ++done;
    if (options.progress) options.progress(done, total, what);
  };
  for (const Field& field : fields) {
    const HeightField hf = HeightField::from_texture(field.depth(), field.material.sampler);
    ViewRef vr;
    vr.hf = &hf;
    vr.dl = view_light_step(field, &vr.lz);
    vr.tol = half_texel_depth(field);
    for (double angle : options.angles) {
      const Scene scene = view_scene(field, angle, options.width, options.height);
      vr.ds = view_ray_step(field, angle);
      const std::string view =
          field.name + " @ " + std::to_string(static_cast<int>(angle)) + " deg";
      Result<Measured> ref = runner.measure(scene, exact_setting);
      if (!ref.ok()) return ref.status().with_context(view + ", exact");
      tick(view + ": exact reference");
      for (const std::string& lod : options.lods) {
        const bool level0 = lod == kLodLevel0;
        const Scene lod_scene =
            level0 ? scene : view_scene(field, angle, options.width, options.height, true);
        for (size_t si = 0; si < settings.size(); ++si) {
          const Setting& s = settings[si];
          const std::string what = view + ", " + s.label + (level0 ? "" : ", " + lod);
          // exact's own level-0 row reuses the reference (same renders)
          Result<Measured> m = level0 && s.technique == "exact" && s.params.empty()
                                   ? ref
                                   : runner.measure(lod_scene, s);
          if (!m.ok()) return m.status().with_context(what);
          Row row;
          row.field = field.name;
          row.technique = s.technique;
          row.setting = s.label;
          row.steps = s.steps;
          row.angle = angle;
          row.lod = lod;
          row.fragments = m->fragments;
          set_times(m->ns, row.ns_median, row.ns_min, row.ns_max);
          work_stats(*m, row);
          accuracy(*m, *ref, vr, row);
          if (options.gl) {
            const std::vector<double> g = runner.gl_times(lod_scene, s, m->fragments, row.gl_note);
            if (!g.empty()) {
              set_times(g, row.gl_ns_median, row.gl_ns_min, row.gl_ns_max);
              row.cpu_gl_ratio = row.gl_ns_median > 0 ? row.ns_median / row.gl_ns_median : -1.0;
            }
          }
          if (options.keep_images) {
            RowImages im;
            im.row = out.rows.size();
            thumbnails(m->on.color, ref->on.color, options.thumbnail, im);
            out.images.push_back(std::move(im));
          }
          out.rows.push_back(std::move(row));
          tick(what);
        }
      }
      if (appendix) {
        out.appendix.push_back(runner.appendix(scene, field, angle));
        tick(view + ": appendix yardstick");
      }
    }
  }
  out.cpu_device = runner.cpu_device();
  out.gl_device = runner.gl_device();
  if (options.gl) {
    std::map<std::string, std::string> skipped;
    for (const Row& r : out.rows)
      if (!r.gl_note.empty()) skipped[r.technique] = r.gl_note;
    for (const auto& [t, why] : skipped) out.notes.push_back("gl skipped " + t + ": " + why);
    std::set<std::string> appendix_notes;
    for (const AppendixRow& a : out.appendix)
      if (!a.note.empty()) appendix_notes.insert(a.note);
    for (const std::string& n : appendix_notes)
      out.notes.push_back("appendix yardstick on gl skipped: " + n);
  }
  return out;
}

}  // namespace relief::sweep
