#pragma once
// Meshes with UVs for the tests of displacement over meshes (surface/mesh_shell.h): a UV sphere
// parameterised as SphereShell is, and OBJ files of such meshes.

#include "libvdbappear/math/constants.h"
#include "libvdbappear/surface/mesh_shell.h"

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

namespace vdbappear::test {

// n_u x n_v quads over the sphere, vertex (a, b) at u = a / n_u, v = b / n_v: longitude 2 pi u,
// latitude from the south pole (v = 0) to the north pole (v = 1), as SphereShell's tile coordinates
// divided by the tile counts; exact normals; counter-clockwise seen from outside. The quads at the
// poles keep their degenerate half (two corners at the pole).
inline std::vector<UvTriangle> uvSphere(const Vec3& centre, double radius, int n_u, int n_v) {
  const auto corner = [&](int a, int b) {
    const double u = double(a) / n_u, v = double(b) / n_v, theta = kPi * (1 - v), phi = 2 * kPi * u;
    const Vec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    return std::make_tuple(Vec3(centre + radius * n), n, Point2(u, v));
  };
  std::vector<UvTriangle> triangles;
  for (int b = 0; b < n_v; ++b)
    for (int a = 0; a < n_u; ++a) {
      const auto c00 = corner(a, b), c10 = corner(a + 1, b), c11 = corner(a + 1, b + 1), c01 = corner(a, b + 1);
      for (const auto& [p, q, r] : {std::make_tuple(c00, c10, c11), std::make_tuple(c00, c11, c01)}) {
        UvTriangle t;
        int k = 0;
        for (const auto& c : {p, q, r}) {
          t.position[k] = std::get<0>(c);
          t.normal[k] = std::get<1>(c);
          t.uv[k++] = std::get<2>(c);
        }
        triangles.push_back(t);
      }
    }
  return triangles;
}

// An OBJ file of the triangles, with their UVs and normals unless left out.
inline void writeObj(const std::string& path, const std::vector<UvTriangle>& triangles, bool uvs = true,
                     bool normals = true) {
  std::ofstream out(path);
  out.precision(17);
  for (const UvTriangle& t : triangles)
    for (int k = 0; k < 3; ++k) {
      out << "v " << t.position[k].x() << ' ' << t.position[k].y() << ' ' << t.position[k].z() << '\n';
      if (uvs) out << "vt " << t.uv[k].x() << ' ' << t.uv[k].y() << '\n';
      if (normals) out << "vn " << t.normal[k].x() << ' ' << t.normal[k].y() << ' ' << t.normal[k].z() << '\n';
    }
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    out << 'f';
    for (std::size_t k = 1; k <= 3; ++k) {
      const std::size_t v = 3 * i + k;
      out << ' ' << v;
      if (uvs || normals) out << '/' << (uvs ? std::to_string(v) : "") << (normals ? "/" + std::to_string(v) : "");
    }
    out << '\n';
  }
}

}  // namespace vdbappear::test
