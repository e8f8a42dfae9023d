// `relief compare A B`: how far two images are apart (render/compare.h), with optional bounds
// that make it a check: exit 1 when a bound fails, 2 on usage errors.
#include <cmath>
#include <cstdio>

#include "apps/commands.h"
#include "apps/output.h"
#include "rasterizer/safe_file.h"
#include "render/compare.h"
#include "scene/image_io.h"

namespace relief::cli {
namespace {

struct CompareArgs {
  std::string a, b;
  std::string heatmap;
  double min_psnr = NAN;
  double max_rmse = NAN;
  double max_over = NAN;
  float threshold = 8.0f / 255.0f;
  bool linear = false;
};

int run_compare(const CompareArgs& args) {
  if (!(args.threshold >= 0.0f) || !std::isfinite(args.threshold))
    return fail("compare: --threshold must be a finite number >= 0", 2);
  if (!args.heatmap.empty()) {  // checked before any work, like every output
    OutputCheck check;
    Status s = check.add("--heatmap", args.heatmap, OutputCheck::Kind::kImage);
    if (!s.ok()) return fail(s.message(), s.exit_code());
  }
  Result<Image> a = read_image(args.a);
  if (!a.ok()) return fail(a.status().message(), 1);
  Result<Image> b = read_image(args.b);
  if (!b.ok()) return fail(b.status().message(), 1);
  if (a->width != b->width || a->height != b->height)
    return fail("compare: " + printable(args.a) + " is " + std::to_string(a->width) + "x" +
                    std::to_string(a->height) + " but " + printable(args.b) + " is " +
                    std::to_string(b->width) + "x" + std::to_string(b->height),
                1);
  if (a->width == 0 || a->height == 0) return fail("compare: empty image " + printable(args.a), 1);
  const DiffSpace space = args.linear ? DiffSpace::kLinear : DiffSpace::kSrgb;
  const ImageDiff d = compare_images(*a, *b, args.threshold, space);
  std::printf("size:      %dx%d (%s, RGB)\n", d.width, d.height,
              args.linear ? "linear" : "sRGB-encoded");
  std::printf("rmse:      %.6f\n", d.rmse);
  if (std::isinf(d.psnr_db))
    std::printf("psnr:      inf dB (identical)\n");
  else
    std::printf("psnr:      %.2f dB\n", d.psnr_db);
  std::printf("max error: %.6f (%.1f/255) at (%d, %d)\n", d.max_error, d.max_error * 255.0, d.max_x,
              d.max_y);
  std::printf("over %.4f: %.4f%% (%zu pixels)\n", d.threshold, 100.0 * d.over_fraction,
              d.over_count);
  if (!args.heatmap.empty()) {
    Status s = write_image(args.heatmap, diff_heatmap(*a, *b, args.threshold, space));
    if (!s.ok()) return fail(s.message(), 1);
  }
  char buf[200];
  if (!std::isnan(args.min_psnr) && !(d.psnr_db >= args.min_psnr)) {
    std::snprintf(buf, sizeof(buf), "compare: PSNR %.2f dB is below --min-psnr %.2f", d.psnr_db,
                  args.min_psnr);
    return fail(buf, 1);
  }
  if (!std::isnan(args.max_rmse) && !(d.rmse <= args.max_rmse)) {
    std::snprintf(buf, sizeof(buf), "compare: RMSE %.6f is above --max-rmse %.6f", d.rmse,
                  args.max_rmse);
    return fail(buf, 1);
  }
  if (!std::isnan(args.max_over) && !(d.over_fraction <= args.max_over)) {
    std::snprintf(buf, sizeof(buf),
                  "compare: %.4f%% of pixels differ by more than %.4f, above --max-over %.4f%%",
                  100.0 * d.over_fraction, d.threshold, 100.0 * args.max_over);
    return fail(buf, 1);
  }
  return 0;
}

}  // namespace

void register_compare(CLI::App& app, Action& action) {
  auto* sub = app.add_subcommand(
      "compare", "Compare two images: RMSE, PSNR, max error, pixels over a threshold");
  auto args = std::make_shared<CompareArgs>();
  sub->add_option("A", args->a, "First image (PNG, EXR, TIFF)")->required();
  sub->add_option("B", args->b, "Second image, same size")->required();
  sub->add_option("--heatmap", args->heatmap, "Write the per-pixel error as a colour ramp");
  sub->add_option("--min-psnr", args->min_psnr, "Fail (exit 1) when PSNR is lower (dB)");
  sub->add_option("--max-rmse", args->max_rmse, "Fail (exit 1) when RMSE is higher");
  sub->add_option("--max-over", args->max_over,
                  "Fail (exit 1) when more than this fraction of pixels exceed --threshold");
  sub->add_option("--threshold", args->threshold,
                  "Per-pixel error that counts as different (default 8/255)");
  sub->add_flag("--linear", args->linear,
                "Compare linear values instead of sRGB-encoded, clamped ones");
  sub->callback([&action, args] { action = [args] { return run_compare(*args); }; });
}

}  // namespace relief::cli
