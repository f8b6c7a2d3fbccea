#include "libvdbappear/subsurface/irradiance_octree.h"

#include "libvdbappear/subsurface/dipole.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace vdbappear {

IrradianceOctree::IrradianceOctree(std::vector<IrradianceSample> samples) : samples_(std::move(samples)) {
  if (samples_.empty()) return;
  Vec3 lo = samples_[0].p, hi = samples_[0].p;
  for (const IrradianceSample& s : samples_) {
    lo = lo.cwiseMin(s.p);
    hi = hi.cwiseMax(s.p);
  }
  const double half = 0.5 * (hi - lo).maxCoeff() * (1 + 1e-9) + 1e-12;  // a cube around the samples
  const Vec3 centre = 0.5 * (lo + hi);
  build(0, samples_.size(), centre - Vec3::Constant(half), centre + Vec3::Constant(half), 0);
}

// Children first, then the node's sums from theirs (Eq. 3.11-3.13: Phi_i = sum Phi_j, A_i = sum
// A_j, M_i = sum M_j, P_i = sum A_j P_j / sum A_j), or from its samples at a leaf.
int IrradianceOctree::build(std::size_t begin, std::size_t end, const Vec3& lo, const Vec3& hi, int depth) {
  const int index = int(nodes_.size());
  nodes_.push_back(Node{lo, hi});
  Node node{lo, hi};
  node.begin = begin;
  node.end = end;
  node.leaf = end - begin <= kLeafSize || depth >= 40;
  if (node.leaf) {
    for (std::size_t k = begin; k < end; ++k) {
      const IrradianceSample& s = samples_[k];
      node.A += s.area;
      node.Phi += s.E * s.area;
      node.M += s.E * s.E * s.area;
      node.P += s.area * s.p;
    }
  } else {
    const Vec3 mid = 0.5 * (lo + hi);
    const auto octant = [&](const IrradianceSample& s) {
      return int(s.p.x() >= mid.x()) | int(s.p.y() >= mid.y()) << 1 | int(s.p.z() >= mid.z()) << 2;
    };
    std::stable_sort(samples_.begin() + std::ptrdiff_t(begin), samples_.begin() + std::ptrdiff_t(end),
                     [&](const IrradianceSample& a, const IrradianceSample& b) { return octant(a) < octant(b); });
    std::size_t first = begin;
    for (int o = 0; o < 8; ++o) {
      std::size_t last = first;
      while (last < end && octant(samples_[last]) == o) ++last;
      if (last > first) {
        Vec3 child_lo, child_hi;
        for (int axis = 0; axis < 3; ++axis) {
          const bool upper = (o >> axis) & 1;
          child_lo[axis] = upper ? mid[axis] : lo[axis];
          child_hi[axis] = upper ? hi[axis] : mid[axis];
        }
        const int child = build(first, last, child_lo, child_hi, depth + 1);
        node.child[o] = child;
        const Node& c = nodes_[child];
        node.A += c.A;
        node.Phi += c.Phi;
        node.M += c.M;
        node.P += c.A * c.P;
      }
      first = last;
    }
  }
  if (node.A > 0) node.P /= node.A;
  else node.P = 0.5 * (lo + hi);
  nodes_[index] = node;
  return index;
}

namespace {

// The running sums of one evaluation: S and grad S over every term of N, and the sums of Eq.
// (3.14) over the terms within the disk.
struct Accumulator {
  const RgbDipole& dipole;
  Vec3 p;
  double disk_radius2;
  double shortest_z_r;  // the profile's near-field scale
  SubsurfaceEstimate estimate;
  double disk_A = 0;
  Rgb disk_Phi = Rgb::Zero(), disk_M = Rgb::Zero();

  // A term of N at P with area A, flux Phi and M: S(p) += R_d(|p - P|) Phi,
  // grad S(p) += grad R_s(p - P) Phi (the convolution of Eq. 3.5 puts p - P_i in the argument).
  void add(const Vec3& P, double A, const Rgb& Phi, const Rgb& M) {
    addFlux(P, Phi);
    addToDisk(P, A, Phi, M);
    ++estimate.terms;
  }
  void addFlux(const Vec3& P, const Rgb& Phi) {
    const Vec3 x = p - P;
    const double r = x.norm();
    for (int c = 0; c < 3; ++c) {
      const DipoleProfile& profile = dipole.channel[c];
      estimate.S[c] += profile.Rd(r) * Phi[c];
      estimate.gradS[c] += profile.gradRs(x) * Phi[c];
    }
  }
  void addToDisk(const Vec3& P, double A, const Rgb& Phi, const Rgb& M) {
    if ((p - P).squaredNorm() <= disk_radius2) {
      disk_A += A;
      disk_Phi += Phi;
      disk_M += M;
    }
  }
  // A sample of N: a point term, or near p its face with E^ constant over it, integrated by
  // midpoint rule on sub-triangles no larger than 0.3 max(z_r, distance) (docs/subsurface.md §4:
  // summed as points, the nearest centroids would make S and, far more, grad S lumpy at the scale
  // of the faces).
  void add(const IrradianceSample& s) {
    const Rgb Phi = s.E * s.area, M = s.E * s.E * s.area;
    const double edge = std::max({(s.face[1] - s.face[0]).norm(), (s.face[2] - s.face[1]).norm(),
                                  (s.face[0] - s.face[2]).norm()});
    if (edge > 0 && (p - s.p).norm() < 4 * edge) integrateFace(s.face, s.E, 0);
    else addFlux(s.p, Phi);
    addToDisk(s.p, s.area, Phi, M);
    ++estimate.terms;
  }
  void integrateFace(const std::array<Vec3, 3>& t, const Rgb& E, int depth) {
    const Vec3 centre = (t[0] + t[1] + t[2]) / 3;
    const double edge = std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
    if (depth >= 6 || edge <= 0.3 * std::max(shortest_z_r, (p - centre).norm())) {
      addFlux(centre, E * (0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm()));
      return;
    }
    const Vec3 a = 0.5 * (t[0] + t[1]), b = 0.5 * (t[1] + t[2]), c = 0.5 * (t[2] + t[0]);
    integrateFace({t[0], a, c}, E, depth + 1);
    integrateFace({a, t[1], b}, E, depth + 1);
    integrateFace({c, b, t[2]}, E, depth + 1);
    integrateFace({a, b, c}, E, depth + 1);
  }
};

bool inside(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
}

}  // namespace

// Traverse_octree (§3.4): a leaf gives its samples; a node holding p, or seen under a solid angle
// A / |p - P|^2 above m, is opened; any other node is one term at its mean position P.
SubsurfaceEstimate IrradianceOctree::evaluate(const Vec3& p, const RgbDipole& dipole, const HierarchySettings& settings) const {
  double shortest_z_r = dipole.channel[0].zr();
  for (const DipoleProfile& profile : dipole.channel) shortest_z_r = std::min(shortest_z_r, profile.zr());
  Accumulator sum{dipole, p, settings.disk_radius * settings.disk_radius, shortest_z_r, {}};
  if (nodes_.empty()) return sum.estimate;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const Node& node = nodes_[std::size_t(stack.back())];
    stack.pop_back();
    if (node.leaf) {
      for (std::size_t k = node.begin; k < node.end; ++k) sum.add(samples_[k]);
    } else if (inside(p, node.lo, node.hi) || node.A > settings.max_solid_angle * (p - node.P).squaredNorm()) {
      for (int child : node.child)
        if (child >= 0) stack.push_back(child);
    } else {
      sum.add(node.P, node.A, node.Phi, node.M);
    }
  }
  if (sum.disk_A > 0) {  // Eq. (3.14): V^2 = E[I^2] - E[I]^2 over the disk
    const Rgb mean = sum.disk_Phi / sum.disk_A;
    sum.estimate.V = (sum.disk_M / sum.disk_A - mean * mean).max(0.0).sqrt();
  }
  return sum.estimate;
}

}  // namespace vdbappear
