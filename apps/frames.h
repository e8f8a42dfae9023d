// Multi-frame rendering for `relief render`: the frame range, its split into shards for a batch
// scheduler, per-frame output names, supersampling and exposure. Every parser returns a usage
// error (exit 2) naming its flag.
#pragma once

#include <string>
#include <vector>

#include "rasterizer/image.h"
#include "rasterizer/status.h"

namespace relief::cli {

// `--frames A-B` (or `--frames N`, one frame): 0 <= A <= B <= kMaxFrame.
struct FrameRange {
  int first = 0;
  int last = 0;
  int count() const { return last - first + 1; }
};
inline constexpr int kMaxFrame = 9999999;
Result<FrameRange> parse_frames(const std::string& text);

// `--shard I/N`: 0 <= I < N <= 100000 (I is 0-based, as SLURM_ARRAY_TASK_ID with --array=0-(N-1)
// and JOB_COMPLETION_INDEX of a Kubernetes indexed job are).
struct Shard {
  int index = 0;
  int count = 1;
};
Result<Shard> parse_shard(const std::string& text);

// The frames shard `s` renders: a contiguous block, the blocks of shards 0..N-1 in order cover
// the range exactly once (shard i takes frames first + floor(i n / N) .. first + floor((i+1) n / N)
// - 1 of n frames; a shard may get none when N > n).
std::vector<int> shard_frames(const FrameRange& range, const Shard& s);

// An output name with one printf-style frame conversion: %d, %Nd or %0Nd (N in 1..9); %% is a
// literal %. Any other use of % is an error naming `flag`. has_pattern is false when the name has
// no conversion.
Status check_frame_pattern(const std::string& name, const std::string& flag, bool& has_pattern);
// The name for `frame` (the name must have passed check_frame_pattern).
std::string format_frame_name(const std::string& name, int frame);

// `--spp N`: a square number of samples per pixel in 1..256 (k x k, k = 1..16), on the regular
// grid: the frame is rendered at k times the width and height and each k x k block is averaged.
Result<int> parse_spp(const std::string& text);
// `--exposure EV`: a finite number in [-24, 24]; linear radiance is scaled by 2^EV.
Result<float> parse_exposure(const std::string& text);

// Box filter: each output pixel is the sum of its k x k block, in row-major order, times 1 / k^2.
Image box_downsample(const Image& image, int k);
// Point sample: each output pixel is the block's sample (k / 2, k / 2) (the centre for odd k), so a
// non-colour AOV (depth, uv, steps, normal) keeps one surface's value per pixel.
Image point_downsample(const Image& image, int k);
Plane point_downsample(const Plane& plane, int k);
// RGB *= scale (alpha kept).
void apply_exposure(Image& image, float scale);

}  // namespace relief::cli
