#pragma once
// A tiled displacement map shell-mapped over a sphere (§4.7.1 "Shell mapping", reference [81] of
// the displacement chapter; the "ball" scene of Fig. 4.18): tile coordinates (u, v) in
// [0, tiles_x] x [0, tiles_y] go to longitude 2 pi u / tiles_x and to latitude from the south pole
// (v = 0) to the north pole (v = tiles_y); the map's x, y and height axes become east, north and
// the outward normal there, so a map's base frame is the sphere's tangent frame. The radius makes a
// tile `size` wide along the equator: tiles are square there when tiles_x = 2 tiles_y, and shrink
// along x toward the poles.

#include "libvdbappear/math/frame.h"
#include "libvdbappear/math/rigid_motion.h"
#include "libvdbappear/render/area_light.h"  // Triangle
#include "libvdbappear/surface/height_field.h"
#include "libvdbappear/surface/tile_stretch.h"

#include <vector>

namespace vdbappear {

struct SphereShell {
  Vec3 centre = Vec3::Zero();
  double radius = 1;
  int tiles_x = 2, tiles_y = 1;

  // The sphere on which tiles_x tiles of width `size` span the equator.
  static SphereShell ofTiles(const Vec3& centre, double size, int tiles_x, int tiles_y);

  Vec3 normal(double u, double v) const;  // outward, unit
  // s east, t north, n outward (right-handed; at the poles east is the limit along the meridian u).
  Frame frame(double u, double v) const;
  // How the tile at latitude v lies over the sphere, against a square tile as wide as the equator's
  // (ofTiles's size): diag(cos latitude, tiles_x / (2 tiles_y)) in frame(u, v) (surface/tile_stretch.h).
  // cos latitude is kept above 1e-6 at the poles.
  TileStretch stretch(double v) const;
  Vec3 point(double u, double v, double height) const { return centre + (radius + height) * normal(u, v); }
  // The tile coordinates (u, v) of the point above or below p (the inverse of point's direction).
  Point2 tileCoordinates(const Vec3& p) const;
  // The turn about the polar axis through the centre by a tiles east: it takes tile (0, b) to tile
  // (a, b), for every latitude band b.
  RigidMotion turn(int a) const;
};

// Vertex (i, j) of tile (a, b) at point(a + i / nx, b + j / ny, height_scale h(i, j)), with the cell
// split of cellTriangles; the triangles face outward.
std::vector<Triangle> shellTriangles(const HeightField& field, const SphereShell& shell, double height_scale);
// The triangles of tile (a, b) alone, as shellTriangles makes them: a band's tiles are this tile
// (a = 0) turned by shell.turn(a), so that a sphere's tiles need one tile's triangles per band.
std::vector<Triangle> shellTileTriangles(const HeightField& field, const SphereShell& shell, double height_scale,
                                         int a, int b);

}  // namespace vdbappear
