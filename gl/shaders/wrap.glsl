// Twin of rasterizer/texture.h wrap_texel: a texel index wrapped into [0, size) by the sampler's
// wrap mode (kWrapRepeat, kWrapClamp, kWrapMirror: the generated prelude), for the reads that
// re-do the CPU's filtering on texelFetch (cone.glsl). Needs only the prelude's constants.
//
// No integer division and no branches: llvmpipe executes both sides of a branch, and a GPU's
// integer division is a long instruction sequence. The branchy, %-based twin this replaced was
// about two thirds of the cone twins' time on llvmpipe (docs/gl-backend.md, "One frame").

// i mod p in [0, p) for |i| <= 2^26 + 1 (scaled_coord's clamp, plus one) and 1 <= p <= 2^20,
// exact whatever the rounding of GLSL's division (required within 2.5 ULP):
// - float(i) is within 2 of i and the first quotient within about 22 / p of i / p, so its floor is
//   off by at most 22 / p + 1 and the first remainder lies within 2 p + 22 of zero;
// - that remainder converts exactly; its quotient by p is off by less than 1 / p, so its floor is
//   exact but where r / p is an integer and the division rounded below it;
// - the last select puts that one case (a remainder of p) back in range.
int floor_mod(int i, int p) {
  int r = i - p * int(floor(float(i) / float(p)));
  r -= p * int(floor(float(r) / float(p)));
  return r >= p ? r - p : (r < 0 ? r + p : r);
}

// wrap_texel of the texels i and i + 1 (a bilinear footprint's two columns or rows): one
// floor_mod of the period (mirror: 2 size, whose second half runs back).
ivec2 wrap_pair(int i, int size, int w) {
  int p = w == kWrapMirror ? 2 * size : size;
  int m0 = floor_mod(i, p);
  ivec2 m = ivec2(m0, m0 + 1 == p ? 0 : m0 + 1);
  ivec2 mirrored = mix(m, ivec2(p - 1) - m, greaterThanEqual(m, ivec2(size)));
  ivec2 clamped = clamp(ivec2(i, i + 1), 0, size - 1);
  return w == kWrapClamp ? clamped : (w == kWrapMirror ? mirrored : m);
}

int wrap_texel(int i, int size, int w) { return wrap_pair(i, size, w).x; }
