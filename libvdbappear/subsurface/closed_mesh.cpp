#include "libvdbappear/subsurface/closed_mesh.h"

#include <fmt/format.h>

#include <Eigen/Geometry>

#include <map>
#include <stdexcept>
#include <tuple>

namespace vdbappear {

namespace {

using VertexKey = std::tuple<double, double, double>;
VertexKey keyOf(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

std::vector<Triangle> outwardClosedMesh(std::vector<Triangle> triangles, const std::string& where) {
  const auto fail = [&](const std::string& what) { throw std::invalid_argument(fmt::format("{}: {}", where, what)); };
  if (triangles.empty()) fail("the mesh has no triangle");
  // Directed edges by vertex position (mesh files repeat shared vertices exactly).
  std::map<std::pair<VertexKey, VertexKey>, int> directed;
  double volume6 = 0;  // six times the signed volume enclosed
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const Triangle& t = triangles[i];
    if ((t[1] - t[0]).cross(t[2] - t[0]).squaredNorm() <= 0) fail(fmt::format("triangle {} is degenerate", i));
    for (int k = 0; k < 3; ++k) ++directed[{keyOf(t[k]), keyOf(t[(k + 1) % 3])}];
    volume6 += t[0].dot(t[1].cross(t[2]));
  }
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    const int opposite = reverse == directed.end() ? 0 : reverse->second;
    const Vec3 a(std::get<0>(edge.first), std::get<1>(edge.first), std::get<2>(edge.first));
    if (count > 1) fail(fmt::format("the mesh is not consistently oriented or not manifold (an edge at {:.6g},{:.6g},{:.6g} "
                                    "is run the same way by {} triangles)", a.x(), a.y(), a.z(), count));
    if (opposite != 1) fail(fmt::format("the mesh is not closed (an edge at {:.6g},{:.6g},{:.6g} has no neighbour): a "
                                        "translucent object needs an inside", a.x(), a.y(), a.z()));
  }
  if (volume6 < 0)
    for (Triangle& t : triangles) std::swap(t[1], t[2]);
  return triangles;
}

}  // namespace vdbappear
