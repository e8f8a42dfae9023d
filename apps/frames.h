// Multi-frame rendering for `relief render`: the frame range, its split into shards for a batch
// scheduler, per-frame output names, supersampling and exposure. Every parser returns a usage
// error (exit 2) naming its flag.
#pragma once

#include <string>
#include <vector>

#include "base/status.h"
#include "rasterizer/image.h"

namespace relief::cli {

// `--frames LIST`: comma-separated items, each N, A-B or A-B:S (every S-th frame from A up to
// B: 30-90:3 is 30, 33, ..., 90), 0 <= A <= B <= kMaxFrame, 1 <= S <= kMaxFrame; the frames in
// ascending order, each once (a frame named twice is an error), at most kMaxFrameCount in all.
struct FrameList {
  std::vector<int> frames;  // ascending, distinct, not empty
  int first() const { return frames.front(); }
  int last() const { return frames.back(); }
  int count() const { return static_cast<int>(frames.size()); }
};
inline constexpr int kMaxFrame = 9999999;
inline constexpr int kMaxFrameCount = 1000000;
Result<FrameList> parse_frames(const std::string& text);

// `--shard I/N`: 0 <= I < N <= 100000 (I is 0-based, as SLURM_ARRAY_TASK_ID with --array=0-(N-1)
// and JOB_COMPLETION_INDEX of a Kubernetes indexed job are).
struct Shard {
  int index = 0;
  int count = 1;
};
Result<Shard> parse_shard(const std::string& text);

// The frames shard `s` renders: a contiguous block of the list, the blocks of shards 0..N-1 in
// order cover it exactly once (shard i takes list entries floor(i n / N) .. floor((i+1) n / N) - 1
// of n frames; a shard may get none when N > n).
std::vector<int> shard_frames(const FrameList& list, const Shard& s);

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
