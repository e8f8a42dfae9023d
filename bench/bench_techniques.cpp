// Technique cost on the built-in `plane` scene at 1024x768 with 2 threads (issue 3): for each
// technique of the relief family at the step counts of the papers (Policarpo, Oliveira and Comba
// 2005: relief 10 + 5 and 32 + 8; McGuire 2005: steep parallax 32; Tatarchuk 2006: POM 32;
// Kaneko 2001 / Welsh 2004: parallax; the exact max-mip reference of Tevs et al. 2008; the cone
// family of Policarpo and Oliveira 2007 at the chapter's 15 steps), the frame
// time and, as user counters, ns per fragment and texture fetches, search steps and shadow steps
// per fragment. The scene's self-shadow and depth correction stay on. Linear step counts are
// fixed (min_steps = steps), as in the papers. One line of kCases adds a technique. Relief 10 + 5
// runs twice, with Blinn-Phong and with the metallic-roughness BRDF; interleave them to compare:
//   build/bench/bench_techniques --benchmark_filter='Relief_10_5' --benchmark_repetitions=9
//     --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
//
//   build/bench/bench_techniques --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "bench/bench_util.h"

namespace relief {
namespace {

const TechniqueCase kCases[] = {
    {"Normal", "normal", {}},  // baseline: no search
    {"Parallax", "parallax", {}},
    {"SteepParallax_32", "steep_parallax", {{"steps", "32"}}},
    {"Pom_32", "pom", {{"steps", "32"}, {"min_steps", "32"}}},
    {"Relief_10_5", "relief", {{"steps", "10"}, {"min_steps", "10"}, {"binary_steps", "5"}}},
    // the same with the glTF metallic-roughness BRDF in place of Blinn-Phong (issue 24's cost)
    {"Relief_10_5_MetallicRoughness",
     "relief",
     {{"steps", "10"}, {"min_steps", "10"}, {"binary_steps", "5"}},
     true},
    // the same with height-field ambient occlusion, 8 rays x 4 steps (issue 24's cost)
    {"Relief_10_5_HeightAo8",
     "relief",
     {{"steps", "10"}, {"min_steps", "10"}, {"binary_steps", "5"}},
     false,
     8},
    // issue 24's goal at 1920x1080: Blinn-Phong, metallic-roughness, metallic-roughness with the
    // studio environment's image-based light (all with the scene's lights and shadows)
    {"Relief_10_5_1080p_BlinnPhong",
     "relief",
     {{"steps", "10"}, {"min_steps", "10"}, {"binary_steps", "5"}},
     false,
     0,
     false,
     1920,
     1080},
    {"Relief_10_5_1080p_MetallicRoughness",
     "relief",
     {{"steps", "10"}, {"min_steps", "10"}, {"binary_steps", "5"}},
     true,
     0,
     false,
     1920,
     1080},
    {"Relief_10_5_1080p_MetallicRoughnessEnv",
     "relief",
     {{"steps", "10"}, {"min_steps", "10"}, {"binary_steps", "5"}},
     true,
     0,
     true,
     1920,
     1080},
    {"Relief_32_8", "relief", {{"steps", "32"}, {"min_steps", "32"}, {"binary_steps", "8"}}},
    {"Exact", "exact", {}},
    {"Cone_15", "cone", {{"steps", "15"}}},  // GPU Gems 3 ch. 18, figure 18-1 settings
    {"ConeQuad_15", "cone_quad", {{"steps", "15"}}},
    {"RelaxedCone_15_6", "relaxed_cone", {{"steps", "15"}, {"binary_steps", "6"}}},
};

void run_technique(benchmark::State& state, const TechniqueCase& c) {
  const WorkCounters work = time_technique(state, "plane", c);
  const double f = static_cast<double>(work.fragments);
  if (f == 0.0) return;
  state.counters["fetches_per_fragment"] = static_cast<double>(work.texture_fetches) / f;
  state.counters["shadow_steps_per_fragment"] = static_cast<double>(work.shadow_steps) / f;
}

}  // namespace
}  // namespace relief

int main(int argc, char** argv) {
  return relief::run_technique_cases(argc, argv, "BM_Technique_", relief::kCases,
                                     relief::run_technique);
}
