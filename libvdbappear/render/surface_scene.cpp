#include "libvdbappear/render/surface_scene.h"

#include <embree3/rtcore.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
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
  std::vector<Vec3> normals;  // per triangle
};

void throwOnEmbreeError(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + what + " failed (error " + std::to_string(int(error)) + ")");
}

}  // namespace

struct SurfaceScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<GeometryInfo> geometries;  // indexed by Embree geometry id
  bool committed = false;

  void add(const std::vector<Triangle>& triangles, GeometryInfo info) {
    if (triangles.empty()) return;
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
      info.normals.push_back((triangles[i][1] - triangles[i][0]).cross(triangles[i][2] - triangles[i][0]).normalized());
    }
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    if (geometries.size() <= id) geometries.resize(id + 1);
    geometries[id] = std::move(info);
  }
};

SurfaceScene::SurfaceScene() : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice("verbose=0");
  if (!impl_->device) throw std::runtime_error("Embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
}

SurfaceScene::~SurfaceScene() {
  rtcReleaseScene(impl_->scene);
  rtcReleaseDevice(impl_->device);
}

void SurfaceScene::addDiffuse(const std::vector<Triangle>& triangles, const Rgb& albedo) {
  impl_->add(triangles, GeometryInfo{albedo, -1, -1, -1, -1, {}});
}

void SurfaceScene::addGlossy(const std::vector<Triangle>& triangles, int brdf_index) {
  impl_->add(triangles, GeometryInfo{Rgb::Zero(), -1, -1, brdf_index, -1, {}});
}

void SurfaceScene::addPrefiltered(const std::vector<Triangle>& triangles, int surface_index) {
  impl_->add(triangles, GeometryInfo{Rgb::Zero(), -1, -1, -1, surface_index, {}});
}

void SurfaceScene::addLight(const std::vector<Triangle>& triangles, int light_index) {
  impl_->add(triangles, GeometryInfo{Rgb::Zero(), light_index, -1, -1, -1, {}});
}

void SurfaceScene::addTranslucent(const std::vector<Triangle>& triangles, int object_index) {
  impl_->add(triangles, GeometryInfo{Rgb::Zero(), -1, object_index, -1, -1, {}});
}

void SurfaceScene::commit() {
  rtcCommitScene(impl_->scene);
  throwOnEmbreeError(impl_->device, "building the scene");
  impl_->committed = true;
}

bool SurfaceScene::empty() const { return impl_->geometries.empty(); }

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

std::optional<SurfaceHit> SurfaceScene::intersect(const Vec3& o, const Vec3& d, double t_min, double t_max) const {
  if (empty()) return std::nullopt;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit hit{};
  hit.ray = makeRay(o, d, t_min, t_max);
  hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  hit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &hit);
  if (hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  const GeometryInfo& info = impl_->geometries[hit.hit.geomID];
  return SurfaceHit{double(hit.ray.tfar), info.normals[hit.hit.primID], info.albedo, info.light, info.translucent, info.brdf, info.prefiltered};
}

bool SurfaceScene::occluded(const Vec3& o, const Vec3& d, double t_min, double t_max) const {
  if (empty()) return false;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = makeRay(o, d, t_min, t_max);
  rtcOccluded1(impl_->scene, &context, &ray);
  return ray.tfar < 0;
}

}  // namespace vdbappear
