#pragma once
// A tiled displacement map shell-mapped over a triangle mesh by its texture coordinates (§4.7.1
// "Shell mapping" of the displacement chapter, shared/papers/002_6a636dc24396287c.txt, reference
// [81], for any mesh with UVs where surface/sphere_shell.h covers a sphere): the point of a base
// triangle at barycentric coordinates b has tile coordinates (tiles_x u(b), tiles_y v(b)), the map
// repeating tiles_x times along u and tiles_y times along v, and is displaced by the map's height
// there along the interpolated shading normal. The map's x, y and height axes become the directions
// of increasing u and v in the triangle's plane, made orthonormal about the normal, and the normal:
// the map's base frame is the mesh's tangent frame, as on the sphere.
//
// Every base triangle is split into k^2 triangles on a regular barycentric grid, one k for the whole
// mesh (the finest any triangle needs, so that neighbours share their edge vertices and no crack
// opens): k = ceil(the longest base edge in map cells * vertices_per_cell). Heights between the
// map's vertices are bilinear (surface/height_field.h).

#include "libvdbappear/math/frame.h"
#include "libvdbappear/render/area_light.h"  // Triangle
#include "libvdbappear/surface/height_field.h"

#include <array>
#include <cstdint>
#include <vector>

namespace vdbappear {

// A base triangle: corners counter-clockwise seen from the side the map rises toward.
struct UvTriangle {
  std::array<Vec3, 3> position;
  std::array<Vec3, 3> normal;  // unit shading normals at the corners
  std::array<Point2, 3> uv;
};

class MeshShell {
 public:
  // Throws std::invalid_argument when there is no triangle or a corner is not finite.
  MeshShell(std::vector<UvTriangle> base, int tiles_x, int tiles_y);

  // The displaced triangles of `field` over the mesh, base triangle after base triangle, each split
  // into subdivisions()^2; heights times height_scale. Fixes subdivisions() for mapPoint().
  // Throws std::length_error when they would be more than `max_triangles`.
  std::vector<Triangle> displace(const HeightField& field, double height_scale, double vertices_per_cell = 1,
                                 std::size_t max_triangles = std::size_t(1) << 31);

  // Where the point at barycentric coordinates (b1, b2) of displaced triangle `primitive` lies on the
  // map (Embree's u, v: the point (1 - b1 - b2) p0 + b1 p1 + b2 p2).
  struct MapPoint {
    Point2 tile;  // tile coordinates (tiles_x u, tiles_y v)
    Frame frame;  // s along increasing u, t along increasing v (made orthonormal), n the shading normal
    // World length per unit of tile coordinates, in (s, t): column 0 along the tile's x, column 1
    // along its y (the base triangle's UV gradient; the identity where it has none).
    Eigen::Matrix2d tile_to_frame = Eigen::Matrix2d::Identity();
  };
  MapPoint mapPoint(std::uint32_t primitive, const Point2& barycentric) const;

  int subdivisions() const { return k_; }
  const std::vector<UvTriangle>& base() const { return base_; }
  int tilesX() const { return tiles_x_; }
  int tilesY() const { return tiles_y_; }
  std::size_t baseTriangles() const { return base_.size(); }
  // The mean world width of a tile: sqrt(the mesh's area per tile). A prefiltered map keeps its
  // slopes only where a tile is as wide as the map was made for.
  double meanTileWidth() const;

 private:
  struct Barycentric {
    double b1, b2;  // of corners 1 and 2
  };
  // Corner c of sub-triangle s of a base triangle split k times (docs/displacement.md §8).
  std::array<Barycentric, 3> subTriangle(std::uint32_t s) const;
  Vec3 normalAt(const UvTriangle& t, const Barycentric& b) const;
  Point2 tileAt(const UvTriangle& t, const Barycentric& b) const;

  std::vector<UvTriangle> base_;
  int tiles_x_, tiles_y_;
  int k_ = 1;
};

}  // namespace vdbappear
