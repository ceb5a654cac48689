#include "engine/sim/arena_scene.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::sim {

struct ArenaScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

void check_device(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) {
    throw Error(ErrorCode::InvalidData, std::string("Embree failed while ") + what + " (error " +
                                            std::to_string(static_cast<int>(e)) + ")");
  }
}

void init_ray(RTCRayHit& rh, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_near, float t_far) {
  rh.ray.org_x = o.x();
  rh.ray.org_y = o.y();
  rh.ray.org_z = o.z();
  rh.ray.dir_x = d.x();
  rh.ray.dir_y = d.y();
  rh.ray.dir_z = d.z();
  rh.ray.tnear = t_near;
  rh.ray.tfar = t_far;
  rh.ray.time = 0;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace

ArenaScene::ArenaScene(const std::vector<ClassedMesh>& meshes) : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (impl_->device == nullptr) throw Error(ErrorCode::InvalidData, "Embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  // Robust mode keeps rays from slipping through the shared edges of
  // neighbouring triangles (the floor's diagonal, a box's corners).
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  for (const ClassedMesh& m : meshes) {
    if (m.indices.empty()) continue;
    if (m.indices.size() % 3 != 0) throw Error(ErrorCode::InvalidData, m.name + ": index count is not a multiple of 3");
    for (std::uint32_t i : m.indices) {
      if (i >= m.vertices.size()) throw Error(ErrorCode::InvalidData, m.name + ": triangle index out of range");
    }
    RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), m.vertices.size()));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), m.triangle_count()));
    check_device(impl_->device, "allocating geometry buffers");
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {
      v[3 * i] = m.vertices[i].x();
      v[3 * i + 1] = m.vertices[i].y();
      v[3 * i + 2] = m.vertices[i].z();
    }
    std::copy(m.indices.begin(), m.indices.end(), idx);
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(impl_->scene, g);
    rtcReleaseGeometry(g);
    if (id >= labels_.size()) labels_.resize(id + 1, ClassId::Unknown);
    labels_[id] = m.label;
  }
  rtcCommitScene(impl_->scene);
  check_device(impl_->device, "building the scene");
}

ArenaScene::~ArenaScene() = default;

ArenaScene::Hit ArenaScene::intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
                                      float t_far) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  init_ray(rh, origin, direction, t_near, t_far);
  rtcIntersect1(impl_->scene, &context, &rh);
  Hit hit;
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
    hit.hit = true;
    hit.t = rh.ray.tfar;
    hit.label = labels_[rh.hit.geomID];
  }
  return hit;
}

void ArenaScene::intersect_batch(const Eigen::Vector3f& origin, std::span<const Eigen::Vector3f> directions,
                                 float t_near, float t_far, std::span<float> t_out,
                                 std::span<std::uint8_t> label_out, RayBatchMode mode) const {
  constexpr float kMiss = std::numeric_limits<float>::infinity();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  const std::size_t n = directions.size();
  if (mode == RayBatchMode::Single) {
    RTCRayHit rh;
    for (std::size_t i = 0; i < n; ++i) {
      init_ray(rh, origin, directions[i], t_near, t_far);
      rtcIntersect1(impl_->scene, &context, &rh);
      const bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
      t_out[i] = hit ? rh.ray.tfar : kMiss;
      label_out[i] = hit ? static_cast<std::uint8_t>(labels_[rh.hit.geomID]) : 0;
    }
    return;
  }
  // Packets of 16 coherent rays (neighbouring pixels share BVH nodes).
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RTCRayHit16 packet;
  alignas(64) int valid[16];
  for (std::size_t base = 0; base < n; base += 16) {
    const std::size_t count = std::min<std::size_t>(16, n - base);
    for (std::size_t k = 0; k < 16; ++k) {
      const bool on = k < count;
      valid[k] = on ? -1 : 0;
      const Eigen::Vector3f& d = directions[on ? base + k : base];
      packet.ray.org_x[k] = origin.x();
      packet.ray.org_y[k] = origin.y();
      packet.ray.org_z[k] = origin.z();
      packet.ray.dir_x[k] = d.x();
      packet.ray.dir_y[k] = d.y();
      packet.ray.dir_z[k] = d.z();
      packet.ray.tnear[k] = t_near;
      packet.ray.tfar[k] = t_far;
      packet.ray.time[k] = 0;
      packet.ray.mask[k] = 0xFFFFFFFFu;
      packet.ray.id[k] = static_cast<unsigned>(k);
      packet.ray.flags[k] = 0;
      packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, impl_->scene, &context, &packet);
    for (std::size_t k = 0; k < count; ++k) {
      const unsigned g = packet.hit.geomID[k];
      const bool hit = g != RTC_INVALID_GEOMETRY_ID;
      t_out[base + k] = hit ? packet.ray.tfar[k] : kMiss;
      label_out[base + k] = hit ? static_cast<std::uint8_t>(labels_[g]) : 0;
    }
  }
}

double ArenaScene::ground_height(double x, double y, double z_top) const {
  const Eigen::Vector3f origin(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z_top));
  const Eigen::Vector3f down(0, 0, -1);
  float t_near = 0;
  // Steps past walls and obstacles until it meets terrain or a ramp.
  for (int step = 0; step < 64; ++step) {
    const Hit h = intersect(origin, down, t_near, std::numeric_limits<float>::infinity());
    if (!h.hit) return 0;
    if (h.label == ClassId::Terrain || h.label == ClassId::InclinedRamp || h.label == ClassId::FlatRamp) {
      return z_top - h.t;
    }
    t_near = h.t + 1e-4f;
  }
  return 0;
}

}  // namespace sarmap::sim
