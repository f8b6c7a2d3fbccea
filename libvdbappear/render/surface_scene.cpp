#include "libvdbappear/render/surface_scene.h"

#include <embree3/rtcore.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace vdbappear {

namespace {

struct GeometryInfo {
  Rgb albedo = Rgb::Zero();
  int light = -1;
  int translucent = -1;
  int brdf = -1;
  int prefiltered = -1;
  std::shared_ptr<const std::vector<Vec3>> normals;  // per triangle; shared by the copies of a mesh
  Mat3 rotation = Mat3::Identity();  // of a copy of a mesh: its mesh's normals turned by it
};

void throwOnEmbreeError(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + what + " failed (error " + std::to_string(int(error)) + ")");
}

}  // namespace

// One Embree scene per level of detail; a geometry is attached, under the same id, to the scene of
// every level it belongs to (Embree shares it, each scene builds its own BVH over it). A mesh with
// copies is a scene of its own, and each copy an instance of it: a geometry of the level scenes.
struct SurfaceScene::Impl {
  RTCDevice device = nullptr;
  std::vector<RTCScene> scenes;            // by level, made at commit
  std::vector<RTCScene> instanced;         // the meshes with copies, one scene each
  std::vector<RTCGeometry> pending;        // added, attached at commit
  std::vector<DetailLevels> levels;        // of each geometry
  std::vector<GeometryInfo> geometries;    // indexed by geometry id
  bool committed = false;

  RTCScene sceneOf(int level) const {
    if (!committed) throw std::logic_error("SurfaceScene: queried before commit");
    return scenes[std::size_t(std::clamp(level, 0, int(scenes.size()) - 1))];
  }

  void add(const std::vector<Triangle>& triangles, GeometryInfo info, DetailLevels detail = {},
           const std::vector<RigidMotion>& copies = {}) {
    if (committed) throw std::logic_error("SurfaceScene: a surface added after commit");
    if (!(detail.first >= 0 && detail.first <= detail.last)) throw std::invalid_argument("SurfaceScene: bad detail levels");
    if (triangles.empty()) return;
    auto normals = std::make_shared<std::vector<Vec3>>();
    RTCGeometry mesh = newMesh(triangles, normals.get());
    info.normals = std::move(normals);
    if (copies.empty()) return attach(mesh, detail, std::move(info));
    RTCScene scene = rtcNewScene(device);
    instanced.push_back(scene);  // released with the SurfaceScene, also when a step below throws
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcAttachGeometry(scene, mesh);
    rtcReleaseGeometry(mesh);
    rtcCommitScene(scene);
    throwOnEmbreeError(device, "building an instanced mesh");
    for (const RigidMotion& copy : copies) {
      RTCGeometry instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
      if (!instance) throw std::runtime_error("Embree: cannot make a copy of a mesh");
      GeometryInfo placed = info;
      placed.rotation = copy.rotation;
      attach(instance, detail, std::move(placed));  // released with the SurfaceScene from here on
      rtcSetGeometryInstancedScene(instance, scene);
      float transform[12];  // column major: the rotation's columns, then the offset
      for (int column = 0; column < 3; ++column)
        for (int row = 0; row < 3; ++row) transform[3 * column + row] = float(copy.rotation(row, column));
      for (int row = 0; row < 3; ++row) transform[9 + row] = float(copy.offset[row]);
      rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, transform);
      rtcCommitGeometry(instance);
      throwOnEmbreeError(device, "placing a copy of a mesh");
    }
  }

  void attach(RTCGeometry geometry, DetailLevels detail, GeometryInfo info) {
    pending.push_back(geometry);
    levels.push_back(detail);
    geometries.push_back(std::move(info));
  }

  // A committed triangle mesh and its unit normals.
  RTCGeometry newMesh(const std::vector<Triangle>& triangles, std::vector<Vec3>* normals) const {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                  3 * sizeof(float), 3 * triangles.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                    3 * sizeof(unsigned), triangles.size()));
    throwOnEmbreeError(device, "allocating a mesh");
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        for (int axis = 0; axis < 3; ++axis) vertices[9 * i + 3 * k + axis] = float(triangles[i][k][axis]);
        indices[3 * i + k] = unsigned(3 * i + k);
      }
      normals->push_back((triangles[i][1] - triangles[i][0]).cross(triangles[i][2] - triangles[i][0]).normalized());
    }
    rtcCommitGeometry(geometry);
    return geometry;
  }

  void commit() {
    if (committed) throw std::logic_error("SurfaceScene: committed twice");
    int count = 1;
    for (const DetailLevels& l : levels) count = std::max(count, l.first + 1);
    for (int level = 0; level < count; ++level) {
      RTCScene scene = rtcNewScene(device);
      rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
      for (std::size_t id = 0; id < pending.size(); ++id)
        if (levels[id].first <= level && level <= levels[id].last) rtcAttachGeometryByID(scene, pending[id], unsigned(id));
      rtcCommitScene(scene);
      scenes.push_back(scene);
      throwOnEmbreeError(device, "building the scene");
    }
    for (RTCGeometry geometry : pending) rtcReleaseGeometry(geometry);  // the scenes hold them
    pending.clear();
    committed = true;
  }
};

SurfaceScene::SurfaceScene() : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice("verbose=0");
  if (!impl_->device) throw std::runtime_error("Embree: cannot create a device");
}

SurfaceScene::~SurfaceScene() {
  for (RTCScene scene : impl_->scenes) rtcReleaseScene(scene);
  for (RTCScene scene : impl_->instanced) rtcReleaseScene(scene);
  for (RTCGeometry geometry : impl_->pending) rtcReleaseGeometry(geometry);
  rtcReleaseDevice(impl_->device);
}

void SurfaceScene::addDiffuse(const std::vector<Triangle>& triangles, const Rgb& albedo,
                              const std::vector<RigidMotion>& copies) {
  impl_->add(triangles, GeometryInfo{albedo, -1, -1, -1, -1, {}}, {}, copies);
}

void SurfaceScene::addGlossy(const std::vector<Triangle>& triangles, int brdf_index, DetailLevels levels,
                             const std::vector<RigidMotion>& copies) {
  impl_->add(triangles, GeometryInfo{Rgb::Zero(), -1, -1, brdf_index, -1, {}}, levels, copies);
}

void SurfaceScene::addPrefiltered(const std::vector<Triangle>& triangles, int surface_index, DetailLevels levels,
                                  const std::vector<RigidMotion>& copies) {
  impl_->add(triangles, GeometryInfo{Rgb::Zero(), -1, -1, -1, surface_index, {}}, levels, copies);
}

void SurfaceScene::addLight(const std::vector<Triangle>& triangles, int light_index) {
  impl_->add(triangles, GeometryInfo{Rgb::Zero(), light_index, -1, -1, -1, {}});
}

void SurfaceScene::addTranslucent(const std::vector<Triangle>& triangles, int object_index) {
  impl_->add(triangles, GeometryInfo{Rgb::Zero(), -1, object_index, -1, -1, {}});
}

void SurfaceScene::commit() { impl_->commit(); }

bool SurfaceScene::empty() const { return impl_->geometries.empty(); }

int SurfaceScene::levelCount() const { return std::max(1, int(impl_->scenes.size())); }

namespace {

RTCRay makeRay(const Vec3& o, const Vec3& d, double t_min, double t_max) {
  RTCRay ray{};
  ray.org_x = float(o.x());
  ray.org_y = float(o.y());
  ray.org_z = float(o.z());
  ray.dir_x = float(d.x());
  ray.dir_y = float(d.y());
  ray.dir_z = float(d.z());
  ray.tnear = float(t_min);
  ray.tfar = std::isinf(t_max) ? std::numeric_limits<float>::infinity() : float(t_max);
  ray.mask = ~0u;
  return ray;
}

}  // namespace

std::optional<SurfaceHit> SurfaceScene::intersect(const Vec3& o, const Vec3& d, double t_min, double t_max,
                                                  int level) const {
  if (empty()) return std::nullopt;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit hit{};
  hit.ray = makeRay(o, d, t_min, t_max);
  hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  hit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->sceneOf(level), &context, &hit);
  if (hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  // A copy's id is its instance's; its mesh is geometry 0 of the instanced scene, whose normals turn
  // with the copy.
  const unsigned id = hit.hit.instID[0] != RTC_INVALID_GEOMETRY_ID ? hit.hit.instID[0] : hit.hit.geomID;
  const GeometryInfo& info = impl_->geometries[id];
  const Vec3& normal = (*info.normals)[hit.hit.primID];
  return SurfaceHit{double(hit.ray.tfar), Vec3(info.rotation * normal), info.albedo,
                    info.light, info.translucent, info.brdf, info.prefiltered, hit.hit.primID,
                    Point2(hit.hit.u, hit.hit.v)};
}

bool SurfaceScene::occluded(const Vec3& o, const Vec3& d, double t_min, double t_max, int level) const {
  if (empty()) return false;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = makeRay(o, d, t_min, t_max);
  rtcOccluded1(impl_->sceneOf(level), &context, &ray);
  return ray.tfar < 0;
}

}  // namespace vdbappear
