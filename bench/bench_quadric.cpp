// Cost of relief mapping with correct silhouettes (Oliveira and Policarpo 2005): relief_quadric
// with the accurate (equation 6) and approximate (equation 7) distances against plain relief on
// the `torus` scene at 1024 x 768, 2 threads, the same 32 + 8 search, and relief_quadric with
// search=relaxed_cone (15 cone steps + 8 halvings); and the per-vertex quadric
// fit (scene/mesh_prep.h) of a 100k-vertex torus.
#include "bench/bench_util.h"
#include "builtin/builtin_curved.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

const std::map<std::string, std::string> kSearch = {
    {"steps", "32"}, {"min_steps", "32"}, {"binary_steps", "8"}};
std::map<std::string, std::string> with(std::map<std::string, std::string> p, const char* k,
                                        const char* v) {
  p[k] = v;
  return p;
}

const TechniqueCase kCases[] = {
    {"Relief_32_8", "relief", kSearch},
    {"Quadric_Approximate_32_8", "relief_quadric", with(kSearch, "distance", "approximate")},
    {"Quadric_Accurate_32_8", "relief_quadric", with(kSearch, "distance", "accurate")},
    {"Quadric_RelaxedCone_15_8",
     "relief_quadric",
     {{"search", "relaxed_cone"}, {"cone_steps", "15"}, {"binary_steps", "8"}}},
};

void run_case(benchmark::State& state, const TechniqueCase& c) {
  const WorkCounters work = time_technique(state, "torus", c);
  const double f = static_cast<double>(work.fragments);
  if (f == 0.0) return;
  state.counters["discarded_per_fragment"] = static_cast<double>(work.discarded) / f;
}

// 316 x 316 cells: 317^2 = 100489 vertices.
void BM_QuadricFit_100k(benchmark::State& state) {
  const Mesh base = parametric_mesh("torus", torus_surface(1.0f, 0.4f), 316, 316, {8, 2});
  for (auto _ : state) {
    Mesh m = base;
    compute_quadrics(m);
    benchmark::DoNotOptimize(m.quadric.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(base.positions.size()));
}
BENCHMARK(BM_QuadricFit_100k)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace relief

int main(int argc, char** argv) {
  return relief::run_technique_cases(argc, argv, "BM_Torus_", relief::kCases, relief::run_case);
}
