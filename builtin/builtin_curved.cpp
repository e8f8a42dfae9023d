// Curved built-in scenes and their parametric meshes: Oliveira and Policarpo, "An Efficient
// Representation for Surface Details", UFRGS RP-351, 2005 (figure 9: a cylinder and a teapot with
// relief on their silhouettes; figure 14: the saddle region of a torus). The Utah teapot is
// Newell's 1975 data set: 32 bicubic Bezier patches over 306 control points (z up in the data).
#include "builtin/builtin_curved.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>

#include <glm/geometric.hpp>

#include "builtin/builtin_parts.h"
#include "builtin/builtin_room.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

constexpr float kPi = 3.14159265358979f;

// 2 pi s with s = 1 mapped to 0, so the seam's two copies of a point are bit-identical (and
// welded by the quadric fit).
float turn(float s) {
  return s >= 1.0f ? 0.0f : 2.0f * kPi * s;
}

// clang-format off
const uint16_t kTeapotPatches[32][16] = {
    {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15},
    {3, 16, 17, 18, 7, 19, 20, 21, 11, 22, 23, 24, 15, 25, 26, 27},
    {18, 28, 29, 30, 21, 31, 32, 33, 24, 34, 35, 36, 27, 37, 38, 39},
    {30, 40, 41, 0, 33, 42, 43, 4, 36, 44, 45, 8, 39, 46, 47, 12},
    {12, 13, 14, 15, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59},
    {15, 25, 26, 27, 51, 60, 61, 62, 55, 63, 64, 65, 59, 66, 67, 68},
    {27, 37, 38, 39, 62, 69, 70, 71, 65, 72, 73, 74, 68, 75, 76, 77},
    {39, 46, 47, 12, 71, 78, 79, 48, 74, 80, 81, 52, 77, 82, 83, 56},
    {56, 57, 58, 59, 84, 85, 86, 87, 88, 89, 90, 91, 92, 93, 94, 95},
    {59, 66, 67, 68, 87, 96, 97, 98, 91, 99, 100, 101, 95, 102, 103, 104},
    {68, 75, 76, 77, 98, 105, 106, 107, 101, 108, 109, 110, 104, 111, 112, 113},
    {77, 82, 83, 56, 107, 114, 115, 84, 110, 116, 117, 88, 113, 118, 119, 92},
    {120, 121, 122, 123, 124, 125, 126, 127, 128, 129, 130, 131, 132, 133, 134, 135},
    {123, 136, 137, 120, 127, 138, 139, 124, 131, 140, 141, 128, 135, 142, 143, 132},
    {132, 133, 134, 135, 144, 145, 146, 147, 148, 149, 150, 151, 68, 152, 153, 154},
    {135, 142, 143, 132, 147, 155, 156, 144, 151, 157, 158, 148, 154, 159, 160, 68},
    {161, 162, 163, 164, 165, 166, 167, 168, 169, 170, 171, 172, 173, 174, 175, 176},
    {164, 177, 178, 161, 168, 179, 180, 165, 172, 181, 182, 169, 176, 183, 184, 173},
    {173, 174, 175, 176, 185, 186, 187, 188, 189, 190, 191, 192, 193, 194, 195, 196},
    {176, 183, 184, 173, 188, 197, 198, 185, 192, 199, 200, 189, 196, 201, 202, 193},
    {203, 203, 203, 203, 206, 207, 208, 209, 210, 210, 210, 210, 211, 212, 213, 214},
    {203, 203, 203, 203, 209, 216, 217, 218, 210, 210, 210, 210, 214, 219, 220, 221},
    {203, 203, 203, 203, 218, 223, 224, 225, 210, 210, 210, 210, 221, 226, 227, 228},
    {203, 203, 203, 203, 225, 229, 230, 206, 210, 210, 210, 210, 228, 231, 232, 211},
    {211, 212, 213, 214, 233, 234, 235, 236, 237, 238, 239, 240, 241, 242, 243, 244},
    {214, 219, 220, 221, 236, 245, 246, 247, 240, 248, 249, 250, 244, 251, 252, 253},
    {221, 226, 227, 228, 247, 254, 255, 256, 250, 257, 258, 259, 253, 260, 261, 262},
    {228, 231, 232, 211, 256, 263, 264, 233, 259, 265, 266, 237, 262, 267, 268, 241},
    {269, 269, 269, 269, 278, 279, 280, 281, 274, 275, 276, 277, 270, 271, 272, 273},
    {269, 269, 269, 269, 281, 288, 289, 290, 277, 285, 286, 287, 273, 282, 283, 284},
    {269, 269, 269, 269, 290, 297, 298, 299, 287, 294, 295, 296, 284, 291, 292, 293},
    {269, 269, 269, 269, 299, 304, 305, 278, 296, 302, 303, 274, 293, 300, 301, 270},
};
const float kTeapotPoints[306][3] = {
    {1.4f, 0.0f, 2.4f}, {1.4f, -0.784f, 2.4f}, {0.784f, -1.4f, 2.4f},
    {0.0f, -1.4f, 2.4f}, {1.3375f, 0.0f, 2.53125f}, {1.3375f, -0.749f, 2.53125f},
    {0.749f, -1.3375f, 2.53125f}, {0.0f, -1.3375f, 2.53125f}, {1.4375f, 0.0f, 2.53125f},
    {1.4375f, -0.805f, 2.53125f}, {0.805f, -1.4375f, 2.53125f}, {0.0f, -1.4375f, 2.53125f},
    {1.5f, 0.0f, 2.4f}, {1.5f, -0.84f, 2.4f}, {0.84f, -1.5f, 2.4f},
    {0.0f, -1.5f, 2.4f}, {-0.784f, -1.4f, 2.4f}, {-1.4f, -0.784f, 2.4f},
    {-1.4f, 0.0f, 2.4f}, {-0.749f, -1.3375f, 2.53125f}, {-1.3375f, -0.749f, 2.53125f},
    {-1.3375f, 0.0f, 2.53125f}, {-0.805f, -1.4375f, 2.53125f}, {-1.4375f, -0.805f, 2.53125f},
    {-1.4375f, 0.0f, 2.53125f}, {-0.84f, -1.5f, 2.4f}, {-1.5f, -0.84f, 2.4f},
    {-1.5f, 0.0f, 2.4f}, {-1.4f, 0.784f, 2.4f}, {-0.784f, 1.4f, 2.4f},
    {0.0f, 1.4f, 2.4f}, {-1.3375f, 0.749f, 2.53125f}, {-0.749f, 1.3375f, 2.53125f},
    {0.0f, 1.3375f, 2.53125f}, {-1.4375f, 0.805f, 2.53125f}, {-0.805f, 1.4375f, 2.53125f},
    {0.0f, 1.4375f, 2.53125f}, {-1.5f, 0.84f, 2.4f}, {-0.84f, 1.5f, 2.4f},
    {0.0f, 1.5f, 2.4f}, {0.784f, 1.4f, 2.4f}, {1.4f, 0.784f, 2.4f},
    {0.749f, 1.3375f, 2.53125f}, {1.3375f, 0.749f, 2.53125f}, {0.805f, 1.4375f, 2.53125f},
    {1.4375f, 0.805f, 2.53125f}, {0.84f, 1.5f, 2.4f}, {1.5f, 0.84f, 2.4f},
    {1.75f, 0.0f, 1.875f}, {1.75f, -0.98f, 1.875f}, {0.98f, -1.75f, 1.875f},
    {0.0f, -1.75f, 1.875f}, {2.0f, 0.0f, 1.35f}, {2.0f, -1.12f, 1.35f},
    {1.12f, -2.0f, 1.35f}, {0.0f, -2.0f, 1.35f}, {2.0f, 0.0f, 0.9f},
    {2.0f, -1.12f, 0.9f}, {1.12f, -2.0f, 0.9f}, {0.0f, -2.0f, 0.9f},
    {-0.98f, -1.75f, 1.875f}, {-1.75f, -0.98f, 1.875f}, {-1.75f, 0.0f, 1.875f},
    {-1.12f, -2.0f, 1.35f}, {-2.0f, -1.12f, 1.35f}, {-2.0f, 0.0f, 1.35f},
    {-1.12f, -2.0f, 0.9f}, {-2.0f, -1.12f, 0.9f}, {-2.0f, 0.0f, 0.9f},
    {-1.75f, 0.98f, 1.875f}, {-0.98f, 1.75f, 1.875f}, {0.0f, 1.75f, 1.875f},
    {-2.0f, 1.12f, 1.35f}, {-1.12f, 2.0f, 1.35f}, {0.0f, 2.0f, 1.35f},
    {-2.0f, 1.12f, 0.9f}, {-1.12f, 2.0f, 0.9f}, {0.0f, 2.0f, 0.9f},
    {0.98f, 1.75f, 1.875f}, {1.75f, 0.98f, 1.875f}, {1.12f, 2.0f, 1.35f},
    {2.0f, 1.12f, 1.35f}, {1.12f, 2.0f, 0.9f}, {2.0f, 1.12f, 0.9f},
    {2.0f, 0.0f, 0.45f}, {2.0f, -1.12f, 0.45f}, {1.12f, -2.0f, 0.45f},
    {0.0f, -2.0f, 0.45f}, {1.5f, 0.0f, 0.225f}, {1.5f, -0.84f, 0.225f},
    {0.84f, -1.5f, 0.225f}, {0.0f, -1.5f, 0.225f}, {1.5f, 0.0f, 0.15f},
    {1.5f, -0.84f, 0.15f}, {0.84f, -1.5f, 0.15f}, {0.0f, -1.5f, 0.15f},
    {-1.12f, -2.0f, 0.45f}, {-2.0f, -1.12f, 0.45f}, {-2.0f, 0.0f, 0.45f},
    {-0.84f, -1.5f, 0.225f}, {-1.5f, -0.84f, 0.225f}, {-1.5f, 0.0f, 0.225f},
    {-0.84f, -1.5f, 0.15f}, {-1.5f, -0.84f, 0.15f}, {-1.5f, 0.0f, 0.15f},
    {-2.0f, 1.12f, 0.45f}, {-1.12f, 2.0f, 0.45f}, {0.0f, 2.0f, 0.45f},
    {-1.5f, 0.84f, 0.225f}, {-0.84f, 1.5f, 0.225f}, {0.0f, 1.5f, 0.225f},
    {-1.5f, 0.84f, 0.15f}, {-0.84f, 1.5f, 0.15f}, {0.0f, 1.5f, 0.15f},
    {1.12f, 2.0f, 0.45f}, {2.0f, 1.12f, 0.45f}, {0.84f, 1.5f, 0.225f},
    {1.5f, 0.84f, 0.225f}, {0.84f, 1.5f, 0.15f}, {1.5f, 0.84f, 0.15f},
    {-1.6f, 0.0f, 2.025f}, {-1.6f, -0.3f, 2.025f}, {-1.5f, -0.3f, 2.25f},
    {-1.5f, 0.0f, 2.25f}, {-2.3f, 0.0f, 2.025f}, {-2.3f, -0.3f, 2.025f},
    {-2.5f, -0.3f, 2.25f}, {-2.5f, 0.0f, 2.25f}, {-2.7f, 0.0f, 2.025f},
    {-2.7f, -0.3f, 2.025f}, {-3.0f, -0.3f, 2.25f}, {-3.0f, 0.0f, 2.25f},
    {-2.7f, 0.0f, 1.8f}, {-2.7f, -0.3f, 1.8f}, {-3.0f, -0.3f, 1.8f},
    {-3.0f, 0.0f, 1.8f}, {-1.5f, 0.3f, 2.25f}, {-1.6f, 0.3f, 2.025f},
    {-2.5f, 0.3f, 2.25f}, {-2.3f, 0.3f, 2.025f}, {-3.0f, 0.3f, 2.25f},
    {-2.7f, 0.3f, 2.025f}, {-3.0f, 0.3f, 1.8f}, {-2.7f, 0.3f, 1.8f},
    {-2.7f, 0.0f, 1.575f}, {-2.7f, -0.3f, 1.575f}, {-3.0f, -0.3f, 1.35f},
    {-3.0f, 0.0f, 1.35f}, {-2.5f, 0.0f, 1.125f}, {-2.5f, -0.3f, 1.125f},
    {-2.65f, -0.3f, 0.9375f}, {-2.65f, 0.0f, 0.9375f}, {-2.0f, -0.3f, 0.9f},
    {-1.9f, -0.3f, 0.6f}, {-1.9f, 0.0f, 0.6f}, {-3.0f, 0.3f, 1.35f},
    {-2.7f, 0.3f, 1.575f}, {-2.65f, 0.3f, 0.9375f}, {-2.5f, 0.3f, 1.125f},
    {-1.9f, 0.3f, 0.6f}, {-2.0f, 0.3f, 0.9f}, {1.7f, 0.0f, 1.425f},
    {1.7f, -0.66f, 1.425f}, {1.7f, -0.66f, 0.6f}, {1.7f, 0.0f, 0.6f},
    {2.6f, 0.0f, 1.425f}, {2.6f, -0.66f, 1.425f}, {3.1f, -0.66f, 0.825f},
    {3.1f, 0.0f, 0.825f}, {2.3f, 0.0f, 2.1f}, {2.3f, -0.25f, 2.1f},
    {2.4f, -0.25f, 2.025f}, {2.4f, 0.0f, 2.025f}, {2.7f, 0.0f, 2.4f},
    {2.7f, -0.25f, 2.4f}, {3.3f, -0.25f, 2.4f}, {3.3f, 0.0f, 2.4f},
    {1.7f, 0.66f, 0.6f}, {1.7f, 0.66f, 1.425f}, {3.1f, 0.66f, 0.825f},
    {2.6f, 0.66f, 1.425f}, {2.4f, 0.25f, 2.025f}, {2.3f, 0.25f, 2.1f},
    {3.3f, 0.25f, 2.4f}, {2.7f, 0.25f, 2.4f}, {2.8f, 0.0f, 2.475f},
    {2.8f, -0.25f, 2.475f}, {3.525f, -0.25f, 2.49375f}, {3.525f, 0.0f, 2.49375f},
    {2.9f, 0.0f, 2.475f}, {2.9f, -0.15f, 2.475f}, {3.45f, -0.15f, 2.5125f},
    {3.45f, 0.0f, 2.5125f}, {2.8f, 0.0f, 2.4f}, {2.8f, -0.15f, 2.4f},
    {3.2f, -0.15f, 2.4f}, {3.2f, 0.0f, 2.4f}, {3.525f, 0.25f, 2.49375f},
    {2.8f, 0.25f, 2.475f}, {3.45f, 0.15f, 2.5125f}, {2.9f, 0.15f, 2.475f},
    {3.2f, 0.15f, 2.4f}, {2.8f, 0.15f, 2.4f}, {0.0f, 0.0f, 3.15f},
    {0.0f, -0.002f, 3.15f}, {0.002f, 0.0f, 3.15f}, {0.8f, 0.0f, 3.15f},
    {0.8f, -0.45f, 3.15f}, {0.45f, -0.8f, 3.15f}, {0.0f, -0.8f, 3.15f},
    {0.0f, 0.0f, 2.85f}, {0.2f, 0.0f, 2.7f}, {0.2f, -0.112f, 2.7f},
    {0.112f, -0.2f, 2.7f}, {0.0f, -0.2f, 2.7f}, {-0.002f, 0.0f, 3.15f},
    {-0.45f, -0.8f, 3.15f}, {-0.8f, -0.45f, 3.15f}, {-0.8f, 0.0f, 3.15f},
    {-0.112f, -0.2f, 2.7f}, {-0.2f, -0.112f, 2.7f}, {-0.2f, 0.0f, 2.7f},
    {0.0f, 0.002f, 3.15f}, {-0.8f, 0.45f, 3.15f}, {-0.45f, 0.8f, 3.15f},
    {0.0f, 0.8f, 3.15f}, {-0.2f, 0.112f, 2.7f}, {-0.112f, 0.2f, 2.7f},
    {0.0f, 0.2f, 2.7f}, {0.45f, 0.8f, 3.15f}, {0.8f, 0.45f, 3.15f},
    {0.112f, 0.2f, 2.7f}, {0.2f, 0.112f, 2.7f}, {0.4f, 0.0f, 2.55f},
    {0.4f, -0.224f, 2.55f}, {0.224f, -0.4f, 2.55f}, {0.0f, -0.4f, 2.55f},
    {1.3f, 0.0f, 2.55f}, {1.3f, -0.728f, 2.55f}, {0.728f, -1.3f, 2.55f},
    {0.0f, -1.3f, 2.55f}, {1.3f, 0.0f, 2.4f}, {1.3f, -0.728f, 2.4f},
    {0.728f, -1.3f, 2.4f}, {0.0f, -1.3f, 2.4f}, {-0.224f, -0.4f, 2.55f},
    {-0.4f, -0.224f, 2.55f}, {-0.4f, 0.0f, 2.55f}, {-0.728f, -1.3f, 2.55f},
    {-1.3f, -0.728f, 2.55f}, {-1.3f, 0.0f, 2.55f}, {-0.728f, -1.3f, 2.4f},
    {-1.3f, -0.728f, 2.4f}, {-1.3f, 0.0f, 2.4f}, {-0.4f, 0.224f, 2.55f},
    {-0.224f, 0.4f, 2.55f}, {0.0f, 0.4f, 2.55f}, {-1.3f, 0.728f, 2.55f},
    {-0.728f, 1.3f, 2.55f}, {0.0f, 1.3f, 2.55f}, {-1.3f, 0.728f, 2.4f},
    {-0.728f, 1.3f, 2.4f}, {0.0f, 1.3f, 2.4f}, {0.224f, 0.4f, 2.55f},
    {0.4f, 0.224f, 2.55f}, {0.728f, 1.3f, 2.55f}, {1.3f, 0.728f, 2.55f},
    {0.728f, 1.3f, 2.4f}, {1.3f, 0.728f, 2.4f}, {0.0f, 0.0f, 0.0f},
    {1.5f, 0.0f, 0.15f}, {1.5f, 0.84f, 0.15f}, {0.84f, 1.5f, 0.15f},
    {0.0f, 1.5f, 0.15f}, {1.5f, 0.0f, 0.075f}, {1.5f, 0.84f, 0.075f},
    {0.84f, 1.5f, 0.075f}, {0.0f, 1.5f, 0.075f}, {1.425f, 0.0f, 0.0f},
    {1.425f, 0.798f, 0.0f}, {0.798f, 1.425f, 0.0f}, {0.0f, 1.425f, 0.0f},
    {-0.84f, 1.5f, 0.15f}, {-1.5f, 0.84f, 0.15f}, {-1.5f, 0.0f, 0.15f},
    {-0.84f, 1.5f, 0.075f}, {-1.5f, 0.84f, 0.075f}, {-1.5f, 0.0f, 0.075f},
    {-0.798f, 1.425f, 0.0f}, {-1.425f, 0.798f, 0.0f}, {-1.425f, 0.0f, 0.0f},
    {-1.5f, -0.84f, 0.15f}, {-0.84f, -1.5f, 0.15f}, {0.0f, -1.5f, 0.15f},
    {-1.5f, -0.84f, 0.075f}, {-0.84f, -1.5f, 0.075f}, {0.0f, -1.5f, 0.075f},
    {-1.425f, -0.798f, 0.0f}, {-0.798f, -1.425f, 0.0f}, {0.0f, -1.425f, 0.0f},
    {0.84f, -1.5f, 0.15f}, {1.5f, -0.84f, 0.15f}, {0.84f, -1.5f, 0.075f},
    {1.5f, -0.84f, 0.075f}, {0.798f, -1.425f, 0.0f}, {1.425f, -0.798f, 0.0f},
};
// clang-format on

float bernstein(int i, float t) {
  const float s = 1.0f - t;
  const float b[4] = {s * s * s, 3.0f * t * s * s, 3.0f * t * t * s, t * t * t};
  return b[i];
}
float bernstein_d(int i, float t) {
  const float s = 1.0f - t;
  const float b[4] = {-3.0f * s * s, 3.0f * s * s - 6.0f * t * s, 6.0f * t * s - 3.0f * t * t,
                      3.0f * t * t};
  return b[i];
}

// Point and derivatives of teapot patch k at (u, v): u along the patch's rows (control index
// 4 i + j, i the row), v along its columns. The data's surface normal cross(dP/du, dP/dv)
// points into the pot on every patch.
void teapot_patch(int k, float u, float v, glm::vec3& p, glm::vec3& pu, glm::vec3& pv) {
  p = pu = pv = glm::vec3(0.0f);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const float* c = kTeapotPoints[kTeapotPatches[k][i * 4 + j]];
      const glm::vec3 cp(c[0], c[2], -c[1]);  // z up -> y up
      p += cp * (bernstein(i, u) * bernstein(j, v));
      pu += cp * (bernstein_d(i, u) * bernstein(j, v));
      pv += cp * (bernstein(i, u) * bernstein_d(j, v));
    }
}

// The tangent of a surface point: dP/ds made perpendicular to the normal, w = +1 where
// cross(N, T) runs along dP/dt (from p_lo to p_hi, points a little before and after in t) and
// the uv tiling keeps the direction of v, -1 otherwise.
glm::vec4 surface_tangent(const SurfacePoint& sp, glm::vec3 p_lo, glm::vec3 p_hi,
                          glm::vec2 uv_tiles) {
  glm::vec3 t = sp.ds - sp.n * glm::dot(sp.n, sp.ds);
  t = glm::length(t) > 1e-12f ? glm::normalize(t) : glm::vec3(0.0f);
  const float along = glm::dot(glm::cross(sp.n, t), p_hi - p_lo) * uv_tiles.y;
  return glm::vec4(t * (uv_tiles.x < 0.0f ? -1.0f : 1.0f), along < 0.0f ? -1.0f : 1.0f);
}

// A point with no usable dP/ds (a surface that gives ds = 0): all tangents from prepare_mesh.
void drop_unusable_tangents(Mesh& m) {
  for (const glm::vec4& tg : m.tangents)
    if (!(glm::dot(glm::vec3(tg), glm::vec3(tg)) > 0.5f)) {
      m.tangents.clear();
      return;
    }
}

}  // namespace

Mesh parametric_mesh(const std::string& name, const Surface& surface, int ns, int nt,
                     glm::vec2 uv_tiles) {
  Mesh m;
  m.name = name;
  for (int j = 0; j <= nt; ++j)
    for (int i = 0; i <= ns; ++i) {
      const float s = static_cast<float>(i) / ns, t = static_cast<float>(j) / nt;
      const SurfacePoint sp = surface(s, t);
      m.positions.push_back(sp.p);
      m.normals.push_back(sp.n);
      m.uvs.push_back(glm::vec2(s, t) * uv_tiles);
      m.tangents.push_back(surface_tangent(sp, surface(s, std::max(t - 1e-3f, 0.0f)).p,
                                           surface(s, std::min(t + 1e-3f, 1.0f)).p, uv_tiles));
    }
  drop_unusable_tangents(m);
  const uint32_t row = static_cast<uint32_t>(ns + 1);
  for (uint32_t j = 0; j < static_cast<uint32_t>(nt); ++j)
    for (uint32_t i = 0; i < static_cast<uint32_t>(ns); ++i) {
      const uint32_t a = j * row + i, b = a + 1, c = b + row, d = a + row;
      m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
    }
  prepare_mesh(m);
  return m;
}

Surface sphere_surface(float r) {
  return [r](float s, float t) {
    const float phi = turn(s), theta = kPi * (1.0f - t);
    // exact poles: every copy of a pole is the same point
    const float st = (t <= 0.0f || t >= 1.0f) ? 0.0f : std::sin(theta);
    const float ct = t <= 0.0f ? -1.0f : (t >= 1.0f ? 1.0f : std::cos(theta));
    const glm::vec3 n(st * std::cos(phi), ct, -st * std::sin(phi));
    return SurfacePoint{n * r, n, glm::vec3(-std::sin(phi), 0.0f, -std::cos(phi))};
  };
}

Surface torus_surface(float R, float r) {
  return [R, r](float s, float t) {
    const float a = turn(s), b = turn(t);
    const glm::vec3 n(std::cos(b) * std::cos(a), std::sin(b), -std::cos(b) * std::sin(a));
    const glm::vec3 c(R * std::cos(a), 0.0f, -R * std::sin(a));
    return SurfacePoint{c + n * r, n, glm::vec3(-std::sin(a), 0.0f, -std::cos(a))};
  };
}

Surface cylinder_surface(float r, float h) {
  return [r, h](float s, float t) {
    const float a = turn(s);
    const glm::vec3 n(std::cos(a), 0.0f, -std::sin(a));
    return SurfacePoint{n * r + glm::vec3(0.0f, h * (t - 0.5f), 0.0f), n,
                        glm::vec3(-std::sin(a), 0.0f, -std::cos(a))};
  };
}

Mesh make_teapot(int n, float height, glm::vec2 uv_tiles) {
  Mesh m;
  m.name = "teapot";
  const float scale = height / 3.15f;
  for (int k = 0; k < 32; ++k) {
    const uint32_t base = static_cast<uint32_t>(m.positions.size());
    for (int j = 0; j <= n; ++j)      // t: the patch's u (rows)
      for (int i = 0; i <= n; ++i) {  // s: the patch's v (columns)
        const float s = static_cast<float>(i) / n, t = static_cast<float>(j) / n;
        glm::vec3 p, pu, pv;
        teapot_patch(k, t, s, p, pu, pv);
        glm::vec3 nrm = glm::cross(pv, pu);  // outward
        glm::vec3 ds = pv, dt = pu;          // dP/ds, dP/dt
        if (!(glm::length(nrm) > 1e-6f)) {
          // a collapsed patch edge (lid knob, bottom centre): the frame a little inside
          glm::vec3 q, qu, qv;
          teapot_patch(k, std::clamp(t, 1e-3f, 1.0f - 1e-3f), std::clamp(s, 1e-3f, 1.0f - 1e-3f), q,
                       qu, qv);
          nrm = glm::cross(qv, qu);
          ds = qv;
          dt = qu;
        }
        const float len = glm::length(nrm);
        const glm::vec3 n = len > 0.0f ? nrm / len : glm::vec3(0, 1, 0);
        m.positions.push_back(p * scale);
        m.normals.push_back(n);
        m.uvs.push_back(glm::vec2(s, t) * uv_tiles);
        m.tangents.push_back(surface_tangent({p, n, ds}, p - dt, p + dt, uv_tiles));
      }
    const uint32_t row = static_cast<uint32_t>(n + 1);
    for (uint32_t j = 0; j < static_cast<uint32_t>(n); ++j)
      for (uint32_t i = 0; i < static_cast<uint32_t>(n); ++i) {
        const uint32_t a = base + j * row + i, b = a + 1, c = b + row, d = a + row;
        m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
      }
  }
  drop_unusable_tangents(m);
  prepare_mesh(m);
  return m;
}

namespace {

// Rounded bumps, 4 x 4 per tile over a floor at depth 0.7: a relief that shows on a silhouette.
ReliefTexel bumps(float u, float v) {
  const float fu = u * 4.0f - std::floor(u * 4.0f) - 0.5f,
              fv = v * 4.0f - std::floor(v * 4.0f) - 0.5f;
  const float r2 = (fu * fu + fv * fv) / 0.16f;
  const float d = r2 < 1.0f ? 0.7f - 0.7f * std::sqrt(1.0f - r2)
                            : 0.7f + 0.3f * std::min(1.0f, (r2 - 1.0f) * 4.0f);
  // alternate bumps (a checkerboard) are a shade darker; the floor between them is one colour, so
  // no tone step lies on the cell borders, which are mesh edges on the built-in meshes (a step
  // there read as a shading seam along the edges: issue 23)
  const int cell = static_cast<int>(std::floor(u * 4.0f)) + static_cast<int>(std::floor(v * 4.0f));
  const float tone = (cell & 1) && r2 < 1.0f ? 0.85f : 1.0f;
  return {std::clamp(d, 0.0f, 1.0f), glm::vec3(0.75f, 0.45f, 0.25f) * tone * (1.0f - 0.4f * d)};
}

Scene curved_scene(const std::string& name, Mesh mesh, float depth_scale, glm::vec3 eye,
                   glm::vec3 target) {
  Scene s;
  s.name = name;
  Material mat = procedural_relief_material(name + "_bumps", bumps, 256, depth_scale);
  mat.technique = "relief_quadric";
  mat.self_shadow = false;
  mat.silhouette = true;
  s.materials.push_back(mat);
  s.meshes.push_back(std::move(mesh));
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  s.lights.push_back(directional_light("sun", {-0.5f, -0.7f, -0.5f}, glm::vec3(1.4f)));
  s.cameras.push_back(look_at("view", eye, target, 40.0f, 30.0f));
  s.ambient = glm::vec3(0.08f);
  s.background = glm::vec4(0.05f, 0.06f, 0.08f, 1.0f);
  return s;
}

}  // namespace

Result<Scene> make_curved_scene(const std::string& name) {
  if (name == "sphere")
    return curved_scene(name, parametric_mesh("sphere", sphere_surface(1.0f), 64, 32, {4, 2}),
                        0.04f, {0.0f, 0.6f, 3.4f}, {0, 0, 0});
  if (name == "cylinder")
    return curved_scene(name,
                        parametric_mesh("cylinder", cylinder_surface(0.7f, 2.0f), 64, 8, {3, 2}),
                        0.05f, {0.0f, 1.2f, 4.0f}, {0, 0, 0});
  if (name == "torus")  // from above at an angle: the inner (saddle) half faces the camera
    return curved_scene(name, parametric_mesh("torus", torus_surface(1.0f, 0.4f), 96, 48, {8, 2}),
                        0.04f, {0.0f, 2.6f, 2.4f}, {0, -0.1f, 0});
  if (name == "teapot")
    return curved_scene(name, make_teapot(12, 1.6f, {2, 2}), 0.04f, {0.0f, 1.9f, 4.0f},
                        {0, 0.75f, 0});
  return Status::error("unknown curved scene '" + name + "'");
}

}  // namespace relief
