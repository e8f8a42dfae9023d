// Whether a linear search (shaders_cpp/search.h: samples at depths t_i = i / n) could have seen
// the first crossing of a ray with the height field, for tests that separate a search's misses
// of thin structures from its refinement error (Policarpo, Oliveira and Comba 2005, section 3:
// the linear search "may miss" features thinner than a step; relaxed cone stepping, figure
// 18-1a). The exact first hit (shaders_cpp/exact_trace.h) enters the surface at depth `enter`; the
// ray stays inside (D <= t) up to `exit`, found by marching on in depth steps of 1e-6.
#pragma once

#include <cmath>

#include "shaders_cpp/exact_trace.h"

namespace relief::testing {

struct InsideSpan {
  double enter = 0.0, exit = 0.0;
};

// The first inside span of the ray (u, v) + t (dsx, dsy) that enters at `enter` (an exact hit).
inline InsideSpan first_inside_span(const HeightField& hf, double u, double v, double dsx,
                                    double dsy, double enter) {
  constexpr double kStep = 1e-6;
  double t = enter;
  while (t < 1.0 && hf.depth_at(u + dsx * t, v + dsy * t) <= t) t += kStep;
  return {enter, std::fmin(t, 1.0)};
}

// Whether some sample t_i = i / n lies inside the span, a margin of 2e-6 in from both ends (the
// march's step and float rounding of the search's sample positions): false means a linear search
// with n steps stepped over the crossing, whatever its refinement.
// A span reaching depth 1 holds the last sample, which always counts as inside.
inline bool span_holds_a_sample(const InsideSpan& s, int n) {
  if (s.exit >= 1.0) return true;
  return std::floor((s.exit - 2e-6) * n) >= std::ceil((s.enter + 2e-6) * n);
}

}  // namespace relief::testing
