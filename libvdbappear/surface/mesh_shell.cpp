#include "libvdbappear/surface/mesh_shell.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vdbappear {
namespace {

bool finite(const UvTriangle& t) {
  for (int c = 0; c < 3; ++c)
    if (!t.position[c].allFinite() || !t.normal[c].allFinite() || !t.uv[c].allFinite()) return false;
  return true;
}

// The map's height at tile coordinates on its triangles as the renderer and the prefilter mesh it
// (cellTriangles: {p00, p10, p11} where x >= y within a cell, {p00, p11, p01} where x < y), the map
// repeating every tile.
double heightAt(const HeightField& field, const Point2& tile) {
  const double x = (tile.x() - std::floor(tile.x())) * field.cellsX(), y = (tile.y() - std::floor(tile.y())) * field.cellsY();
  const int i = std::clamp(int(x), 0, field.cellsX() - 1), j = std::clamp(int(y), 0, field.cellsY() - 1);
  const double fx = x - i, fy = y - j;
  const double h00 = field.at(i, j), h11 = field.at(i + 1, j + 1);
  if (fx >= fy) return h00 + fx * (field.at(i + 1, j) - h00) + fy * (h11 - field.at(i + 1, j));
  return h00 + fy * (field.at(i, j + 1) - h00) + fx * (h11 - field.at(i, j + 1));
}

// The first sub-triangle of row j of a triangle split k times: rows hold 2 (k - j) - 1 each.
std::uint32_t rowStart(int k, int j) { return std::uint32_t(j) * std::uint32_t(2 * k - j); }

}  // namespace

MeshShell::MeshShell(std::vector<UvTriangle> base, int tiles_x, int tiles_y)
    : base_(std::move(base)), tiles_x_(tiles_x), tiles_y_(tiles_y) {
  if (base_.empty()) throw std::invalid_argument("the mesh has no triangles");
  if (tiles_x < 1 || tiles_y < 1) throw std::invalid_argument("tiles must be at least 1 x 1");
  for (std::size_t i = 0; i < base_.size(); ++i)
    if (!finite(base_[i])) throw std::invalid_argument("triangle " + std::to_string(i) + " has a corner that is not finite");
}

Point2 MeshShell::tileAt(const UvTriangle& t, const Barycentric& b) const {
  const Point2 uv = (1 - b.b1 - b.b2) * t.uv[0] + b.b1 * t.uv[1] + b.b2 * t.uv[2];
  return {tiles_x_ * uv.x(), tiles_y_ * uv.y()};
}

Vec3 MeshShell::normalAt(const UvTriangle& t, const Barycentric& b) const {
  const Vec3 n = (1 - b.b1 - b.b2) * t.normal[0] + b.b1 * t.normal[1] + b.b2 * t.normal[2];
  if (n.squaredNorm() > 1e-24) return n.normalized();
  return (t.position[1] - t.position[0]).cross(t.position[2] - t.position[0]).normalized();
}

std::array<MeshShell::Barycentric, 3> MeshShell::subTriangle(std::uint32_t s) const {
  const int k = k_;
  int j = std::clamp(int(std::floor(k - std::sqrt(double(k) * k - double(s)))), 0, k - 1);
  while (j > 0 && rowStart(k, j) > s) --j;
  while (j + 1 < k && rowStart(k, j + 1) <= s) ++j;
  const std::uint32_t r = s - rowStart(k, j);
  const int i = int(r / 2);
  const auto at = [k](int a, int b) { return Barycentric{double(a) / k, double(b) / k}; };
  if (r % 2 == 0) return {at(i, j), at(i + 1, j), at(i, j + 1)};  // pointing up, as the base triangle
  return {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
}

std::vector<Triangle> MeshShell::displace(const HeightField& field, double height_scale, double vertices_per_cell,
                                          std::size_t max_triangles) {
  if (!(vertices_per_cell > 0)) throw std::invalid_argument("vertices per cell must be positive");
  double longest = 0;  // in map cells
  for (const UvTriangle& t : base_)
    for (int c = 0; c < 3; ++c) {
      const Point2 d = t.uv[(c + 1) % 3] - t.uv[c];
      longest = std::max(longest, std::hypot(d.x() * tiles_x_ * field.cellsX(), d.y() * tiles_y_ * field.cellsY()));
    }
  const double k = std::max(1.0, std::ceil(longest * vertices_per_cell));
  const double count = double(base_.size()) * k * k;
  if (count > double(max_triangles))
    throw std::length_error("the map over the mesh would be " + std::to_string(std::llround(count)) +
                            " triangles (each of the mesh's " + std::to_string(base_.size()) + " split " +
                            std::to_string(std::llround(k * k)) + " times), more than " + std::to_string(max_triangles) +
                            ": use fewer tiles or a mesh whose UVs span fewer map cells per triangle");
  k_ = int(k);
  std::vector<Triangle> triangles;
  triangles.reserve(std::size_t(count));
  std::vector<Vec3> vertices;  // of one base triangle, row after row: vertex (i, j) at j (2k + 3 - j) / 2 + i
  const auto vertex = [this](int i, int j) { return std::size_t(j) * (2 * k_ + 3 - j) / 2 + std::size_t(i); };
  for (const UvTriangle& t : base_) {
    vertices.clear();
    for (int j = 0; j <= k_; ++j)
      for (int i = 0; i + j <= k_; ++i) {
        const Barycentric b{double(i) / k_, double(j) / k_};
        const Vec3 p = (1 - b.b1 - b.b2) * t.position[0] + b.b1 * t.position[1] + b.b2 * t.position[2];
        vertices.push_back(p + height_scale * heightAt(field, tileAt(t, b)) * normalAt(t, b));
      }
    for (int j = 0; j < k_; ++j)
      for (int i = 0; i + j < k_; ++i) {
        triangles.push_back({vertices[vertex(i, j)], vertices[vertex(i + 1, j)], vertices[vertex(i, j + 1)]});
        if (i + j + 1 < k_)
          triangles.push_back({vertices[vertex(i + 1, j)], vertices[vertex(i + 1, j + 1)], vertices[vertex(i, j + 1)]});
      }
  }
  return triangles;
}

MeshShell::MapPoint MeshShell::mapPoint(std::uint32_t primitive, const Point2& barycentric) const {
  const std::uint32_t per_base = std::uint32_t(k_) * std::uint32_t(k_);
  const UvTriangle& t = base_.at(primitive / per_base);
  const std::array<Barycentric, 3> c = subTriangle(primitive % per_base);
  const double w0 = 1 - barycentric.x() - barycentric.y();
  const Barycentric b{w0 * c[0].b1 + barycentric.x() * c[1].b1 + barycentric.y() * c[2].b1,
                      w0 * c[0].b2 + barycentric.x() * c[1].b2 + barycentric.y() * c[2].b2};
  const Vec3 n = normalAt(t, b);
  // dP/du and dP/dv of the base triangle: [e1 e2] = [dP/du dP/dv] [duv1 duv2].
  const Vec3 e1 = t.position[1] - t.position[0], e2 = t.position[2] - t.position[0];
  const Point2 d1 = t.uv[1] - t.uv[0], d2 = t.uv[2] - t.uv[0];
  const double det = d1.x() * d2.y() - d2.x() * d1.y();
  const Vec3 dp_du = (d2.y() * e1 - d1.y() * e2) / det, dp_dv = (d1.x() * e2 - d2.x() * e1) / det;
  const Vec3 s = dp_du - n * n.dot(dp_du);
  if (!(std::abs(det) > 0) || !s.allFinite() || !(s.squaredNorm() > 1e-24 * dp_du.squaredNorm()))
    return {tileAt(t, b), Frame::fromNormal(n)};  // no UV gradient here: any frame about n
  const Vec3 s_unit = s.normalized();
  // Mirrored UVs turn the map over: its y then runs along -(n x s), and the frame is left-handed.
  const double handedness = dp_du.cross(dp_dv).dot(n) < 0 ? -1 : 1;
  const Frame frame{s_unit, handedness * n.cross(s_unit), n};
  const Vec3 dp_dx = dp_du / tiles_x_, dp_dy = dp_dv / tiles_y_;  // per unit of tile coordinates
  Eigen::Matrix2d tile_to_frame;
  tile_to_frame << frame.s.dot(dp_dx), frame.s.dot(dp_dy), frame.t.dot(dp_dx), frame.t.dot(dp_dy);
  return {tileAt(t, b), frame, tile_to_frame};
}

double MeshShell::meanTileWidth() const {
  double world = 0, uv = 0;
  for (const UvTriangle& t : base_) {
    world += 0.5 * (t.position[1] - t.position[0]).cross(t.position[2] - t.position[0]).norm();
    const Point2 d1 = t.uv[1] - t.uv[0], d2 = t.uv[2] - t.uv[0];
    uv += 0.5 * std::abs(d1.x() * d2.y() - d2.x() * d1.y());
  }
  return uv > 0 ? std::sqrt(world / (uv * tiles_x_ * tiles_y_)) : 0.0;
}

}  // namespace vdbappear
