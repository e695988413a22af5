#include "reconstruction/cube_cases.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vscan::reconstruction {
namespace {

// Corner c with bit `axis` forced to `value`.
int WithBit(int c, int axis, int value) { return (c & ~(1 << axis)) | (value << axis); }

// The two free axes' bits of edge k of axis a, spread around the fixed axis.
int EdgeStartCorner(int edge) {
  const int a = edge / 4, k = edge % 4;
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  return ((k & 1) << b) | (((k >> 1) & 1) << c);
}

int EdgeBetween(int c0, int c1) {
  const int diff = c0 ^ c1;
  const int a = diff == 1 ? 0 : diff == 2 ? 1 : 2;
  const int start = WithBit(c0, a, 0);
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  return 4 * a + (((start >> b) & 1) | (((start >> c) & 1) << 1));
}

// The four corners of face (axis a, side s) in counter-clockwise order seen from outside the cube.
std::array<int, 4> FaceCorners(int a, int s) {
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  const int base = s << a;
  // (b, c) = (0,0), (1,0), (1,1), (0,1) turns counter-clockwise about +a, since e_b x e_c = e_a.
  std::array<int, 4> q = {base, base | (1 << b), base | (1 << b) | (1 << c), base | (1 << c)};
  if (s == 0) std::swap(q[1], q[3]);
  return q;
}

// On each face, every run of inside corners (walked counter-clockwise) is cut off by a segment from
// the edge where the walk leaves the inside to the edge where it entered. Two diagonal inside
// corners are two runs, a choice made by the face alone, so neighbouring cubes agree on it and
// the surface has no cracks. Each cut edge starts one segment and ends another: the segments
// chain into closed loops, which are split into triangle fans.
std::vector<CubeTriangle> BuildCase(uint32_t mask) {
  const auto inside = [mask](int corner) { return ((mask >> corner) & 1) != 0; };
  std::array<int, 12> next;
  next.fill(-1);
  for (int a = 0; a < 3; ++a) {
    for (int s = 0; s < 2; ++s) {
      const std::array<int, 4> q = FaceCorners(a, s);
      for (int k = 0; k < 4; ++k) {
        // Corner q[k] starts a run when the corner before it is outside.
        if (!inside(q[k]) || inside(q[(k + 3) % 4])) continue;
        int end = k;
        while (inside(q[(end + 1) % 4]) && (end + 1) % 4 != k) end = (end + 1) % 4;
        const int entered = EdgeBetween(q[(k + 3) % 4], q[k]);
        const int left = EdgeBetween(q[end], q[(end + 1) % 4]);
        next[left] = entered;
      }
    }
  }
  std::vector<CubeTriangle> triangles;
  std::array<bool, 12> used{};
  for (int e = 0; e < 12; ++e) {
    if (next[e] < 0 || used[e]) continue;
    std::vector<int> loop;
    for (int cur = e; !used[cur]; cur = next[cur]) {
      used[cur] = true;
      loop.push_back(cur);
    }
    for (size_t i = 1; i + 1 < loop.size(); ++i) {
      triangles.push_back({static_cast<uint8_t>(loop[0]), static_cast<uint8_t>(loop[i]),
                           static_cast<uint8_t>(loop[i + 1])});
    }
  }
  return triangles;
}

Eigen::Vector3f EdgeMidpoint(int edge) {
  const int c = EdgeStartCorner(edge);
  Eigen::Vector3f p(c & 1, (c >> 1) & 1, (c >> 2) & 1);
  p[edge / 4] = 0.5f;
  return p;
}

std::array<std::vector<CubeTriangle>, 256> BuildTable() {
  std::array<std::vector<CubeTriangle>, 256> table;
  for (uint32_t mask = 0; mask < 256; ++mask) table[mask] = BuildCase(mask);
  // Orientation is fixed once: corner 0 alone inside must give a triangle facing away from it.
  const CubeTriangle& t = table[1].front();
  const Eigen::Vector3f n =
      (EdgeMidpoint(t[1]) - EdgeMidpoint(t[0])).cross(EdgeMidpoint(t[2]) - EdgeMidpoint(t[0]));
  if (n.sum() < 0) {
    for (auto& triangles : table) {
      for (auto& tri : triangles) std::swap(tri[1], tri[2]);
    }
  }
  return table;
}

}  // namespace

const std::vector<CubeTriangle>& CubeCase(uint32_t inside_mask) {
  static const std::array<std::vector<CubeTriangle>, 256> table = BuildTable();
  return table[inside_mask & 255];
}

int EdgeStart(int edge) { return EdgeStartCorner(edge); }

}  // namespace vscan::reconstruction
