#pragma once
// Opaque surfaces, intersected through Embree 3: diffuse and glossy meshes (OBJ/PLY, height
// fields, the ground plane), the triangles of area lights and translucent objects' meshes
// (subsurface/translucent_object.h).
// Embree stays behind the implementation.

#include "libvdbappear/math/rgb.h"
#include "libvdbappear/math/rigid_motion.h"
#include "libvdbappear/render/area_light.h"  // Triangle

#include <memory>
#include <optional>
#include <vector>

namespace vdbappear {

struct SurfaceHit {
  double t = 0;
  Vec3 normal;        // unit geometric normal, counter-clockwise orientation (not flipped)
  Rgb albedo;         // diffuse reflectance (meshes)
  int light = -1;     // index of the area light hit, or -1
  int translucent = -1;  // index of the translucent object hit (RenderScene::translucent), or -1
  int brdf = -1;         // index of a glossy mesh's microfacet BRDF (RenderScene::brdfs), or -1
  int prefiltered = -1;  // index of a prefiltered displacement map (RenderScene::prefiltered), or -1
  unsigned primitive = 0;  // the triangle hit, in the order its surface was added (a copy's as its mesh's)
  Point2 barycentric = Point2::Zero();  // (b1, b2): the point (1 - b1 - b2) p0 + b1 p1 + b2 p2 of it
};

// Which levels of detail a surface belongs to (render/level_of_detail.h): a mipmap's level k is
// seen only by paths of level k; every other surface by all paths. Levels {k, kLastLevel}: k and
// every level above it (a mipmap's coarsest level, for paths of a scene whose other mipmaps have
// more levels).
struct DetailLevels {
  static constexpr int kLastLevel = 1 << 20;
  int first = 0, last = kLastLevel;
};

class SurfaceScene {
 public:
  SurfaceScene();
  ~SurfaceScene();
  SurfaceScene(const SurfaceScene&) = delete;
  SurfaceScene& operator=(const SurfaceScene&) = delete;

  // `copies`: rigid motions of the triangles, each an Embree instance of one mesh, so that a tiled
  // height field holds one tile's triangles whatever its tile count (one per latitude band over a
  // sphere); empty: the triangles as given. A hit's normal is turned with its copy.
  void addDiffuse(const std::vector<Triangle>& triangles, const Rgb& albedo, const std::vector<RigidMotion>& copies = {});
  void addGlossy(const std::vector<Triangle>& triangles, int brdf_index, DetailLevels levels = {},
                 const std::vector<RigidMotion>& copies = {});
  void addPrefiltered(const std::vector<Triangle>& triangles, int surface_index, DetailLevels levels = {},
                      const std::vector<RigidMotion>& copies = {});
  void addLight(const std::vector<Triangle>& triangles, int light_index);
  void addTranslucent(const std::vector<Triangle>& triangles, int object_index);
  void commit();  // once, after the last add and before any query (std::logic_error otherwise)
  bool empty() const;
  int levelCount() const;  // 1 + the highest first level added (1 without mipmaps); after commit

  // Closest hit with t in (t_min, t_max), among the surfaces of the given level of detail (levels
  // above levelCount() - 1 see the last).
  std::optional<SurfaceHit> intersect(const Vec3& o, const Vec3& d, double t_min, double t_max, int level = 0) const;
  bool occluded(const Vec3& o, const Vec3& d, double t_min, double t_max, int level = 0) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vdbappear
