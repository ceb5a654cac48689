#include "engine/geometry/triangle_scene.hpp"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/error.hpp"
#include "engine/geometry/float_limits.hpp"

namespace sarmap::geometry {

struct TriangleScene::Impl {
  // One mesh's Embree geometry and the buffers behind it, kept between
  // rebuilds while the mesh holds triangles; the buffers hold some room
  // beyond their items.
  struct MeshGeometry {
    RTCGeometry geometry = nullptr;
    unsigned id = 0;
    RTCBuffer vertices = nullptr, indices = nullptr;
    std::size_t vertex_capacity = 0, triangle_capacity = 0;
    std::size_t vertex_count = 0, triangle_count = 0;  // of the mesh in the buffers
  };

  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  RTCBuildQuality quality = RTC_BUILD_QUALITY_HIGH;
  std::vector<MeshGeometry> meshes;  // by mesh index

  // Detaches a mesh's geometry from the scene (Embree gives its id to the
  // next geometry attached) and lets go of it and its buffers.
  void release(MeshGeometry& m) {
    if (m.geometry) {
      rtcDetachGeometry(scene, m.id);
      rtcReleaseGeometry(m.geometry);
    }
    if (m.vertices) rtcReleaseBuffer(m.vertices);
    if (m.indices) rtcReleaseBuffer(m.indices);
    m = MeshGeometry{};
  }
  ~Impl() {
    for (MeshGeometry& m : meshes) release(m);
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

// Embree asserts (and aborts the process) on a ray it deems invalid: refuse
// such a ray with an error first.
void check_ray(const Eigen::Vector3f& origin, const Eigen::Vector3f* direction, float t_near, float t_far) {
  const bool origin_ok = origin.allFinite() && origin.cwiseAbs().maxCoeff() <= kMaxSceneCoordinate;
  if (!origin_ok) {
    throw Error(ErrorCode::OutOfRange, "ray origin (" + std::to_string(origin.x()) + ", " + std::to_string(origin.y()) +
                                           ", " + std::to_string(origin.z()) + ") is not finite or lies beyond " +
                                           std::to_string(kMaxSceneCoordinate) + " m");
  }
  if (direction != nullptr && !direction->allFinite()) throw Error(ErrorCode::InvalidArgument, "ray direction is not finite");
  if (!(t_near >= 0) || !(t_far >= t_near)) {
    throw Error(ErrorCode::InvalidArgument, "ray interval must satisfy 0 <= t_near <= t_far");
  }
}

void check_device(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) {
    throw Error(ErrorCode::InvalidData, std::string("Embree failed while ") + what + " (error " +
                                            std::to_string(static_cast<int>(e)) + ")");
  }
}

RTCBuildQuality embree_quality(BuildQuality q) {
  switch (q) {
    case BuildQuality::Low:
      return RTC_BUILD_QUALITY_LOW;
    case BuildQuality::Medium:
      return RTC_BUILD_QUALITY_MEDIUM;
    case BuildQuality::High:
      break;
  }
  return RTC_BUILD_QUALITY_HIGH;
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

// One checked ray's first hit in `scene` (geomID invalid on a miss).
RTCRayHit cast_one(RTCScene scene, const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                   float t_near, float t_far) {
  check_ray(origin, &direction, t_near, t_far);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  init_ray(rh, origin, direction, t_near, t_far);
  rtcIntersect1(scene, &context, &rh);
  return rh;
}

// A segment as Embree's ray: origin p, direction q - p, t in [0, 1]. False
// for a segment whose float direction is zero: it crosses no surface.
bool segment_ray(const Segment& s, Eigen::Vector3f& origin, Eigen::Vector3f& direction) {
  origin = s.p.cast<float>();
  direction = (s.q - s.p).cast<float>();
  return direction.x() != 0 || direction.y() != 0 || direction.z() != 0;
}

bool segment_in_range(const Segment& s) {
  // Written so that NaN fails every comparison and lands out of range.
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(s.p[i]) <= kMaxSceneCoordinate) || !(std::abs(s.q[i]) <= kMaxSceneCoordinate))
      return false;
  }
  return true;
}

void record_lowest(std::atomic<std::size_t>& lowest, std::size_t i) {
  std::size_t seen = lowest.load(std::memory_order_relaxed);
  while (i < seen && !lowest.compare_exchange_weak(seen, i, std::memory_order_relaxed)) {
  }
}

// Embree's live bytes on the shared device: every allocation and release
// it reports, from any thread.
std::atomic<std::int64_t> device_bytes{0};

bool count_device_bytes(void* /*user*/, ssize_t bytes, bool /*post*/) {
  device_bytes.fetch_add(static_cast<std::int64_t>(bytes), std::memory_order_relaxed);
  return true;  // never refuse an allocation
}

// The process's one Embree device, retained for the caller. Scenes share it
// because the topological map builds a wall scene at every update, and a
// device of its own cost each of them more than the scene's build (PERF.md).
// Embree allows scenes of one device to be built and traced from any number
// of threads. Created on first use; a failed creation is tried again next
// time.
RTCDevice shared_device() {
  static std::mutex creating;
  static RTCDevice device = nullptr;
  const std::lock_guard<std::mutex> lock(creating);
  if (device == nullptr) {
    device = rtcNewDevice(nullptr);
    if (device != nullptr) rtcSetDeviceMemoryMonitorFunction(device, count_device_bytes, nullptr);
  }
  if (device == nullptr) throw Error(ErrorCode::InvalidData, "Embree: cannot create a device");
  rtcRetainDevice(device);
  return device;
}

// Each task takes this many segments: enough to amortise the task, few
// enough that 1k edges still spread over both cores. A multiple of 16.
constexpr std::size_t kSegmentsPerTask = 256;

// The data of `buffer`, made (or made anew, with half again as much room)
// when it holds fewer than `items` of `item_bytes`. Embree reads a buffer's
// last item with a 16-byte load, hence the padding.
void* buffer_for(RTCDevice device, RTCBuffer& buffer, std::size_t& capacity, std::size_t items,
                 std::size_t item_bytes) {
  if (capacity < items) {
    if (buffer) rtcReleaseBuffer(buffer);
    capacity = items + items / 2;
    buffer = rtcNewBuffer(device, capacity * item_bytes + 16);
    if (buffer == nullptr) {
      capacity = 0;
      check_device(device, "allocating geometry buffers");
      throw Error(ErrorCode::InvalidData, "Embree failed while allocating geometry buffers");
    }
  }
  return rtcGetBufferData(buffer);
}

}  // namespace

std::size_t embree_bytes() {
  return static_cast<std::size_t>(std::max<std::int64_t>(0, device_bytes.load(std::memory_order_relaxed)));
}

std::size_t TriangleScene::memory_bytes() const {
  return sizeof(Impl) + capacity_bytes(impl_->meshes) + capacity_bytes(labels_) + capacity_bytes(meshes_);
}

TriangleScene::TriangleScene(std::span<const ClassedMesh> meshes, BuildQuality quality)
    : impl_(std::make_unique<Impl>()) {
  impl_->device = shared_device();
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  impl_->quality = embree_quality(quality);
  rtcSetSceneBuildQuality(impl_->scene, impl_->quality);
  rebuild(meshes);
}

void TriangleScene::rebuild(std::span<const ClassedMesh> meshes) {
  for (const ClassedMesh& m : meshes) {
    if (!m.indices.empty()) validate_mesh(m);
  }
  // Embree keeps one pending error per thread and device: one this thread
  // left from an earlier call must not be taken for this scene's.
  rtcGetDeviceError(impl_->device);
  if (impl_->meshes.size() < meshes.size()) impl_->meshes.resize(meshes.size());
  for (std::size_t mesh_index = 0; mesh_index < impl_->meshes.size(); ++mesh_index) {
    Impl::MeshGeometry& slot = impl_->meshes[mesh_index];
    if (mesh_index >= meshes.size() || meshes[mesh_index].indices.empty()) {
      // Its geometry and buffers are let go, so that the scene's memory
      // follows the meshes it holds (a wall scene's tiles whose walls a
      // bounded map forgot), at the price of new ones if it fills again.
      impl_->release(slot);
      continue;
    }
    const ClassedMesh& m = meshes[mesh_index];
    if (slot.geometry == nullptr) {
      slot.geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
      if (slot.geometry == nullptr) {
        check_device(impl_->device, "making a geometry");
        throw Error(ErrorCode::InvalidData, "Embree failed while making a geometry");
      }
      // Embree builds with the geometry's quality too (Medium unless told), so
      // a Low scene would otherwise still pay for a Medium build.
      rtcSetGeometryBuildQuality(slot.geometry, impl_->quality);
      slot.id = rtcAttachGeometry(impl_->scene, slot.geometry);
      if (slot.id >= labels_.size()) {
        labels_.resize(slot.id + 1, ClassId::Unknown);
        meshes_.resize(slot.id + 1, 0);
      }
    }
    const std::size_t vertex_count = m.vertices.size(), triangle_count = m.triangle_count();
    labels_[slot.id] = m.label;
    meshes_[slot.id] = static_cast<std::uint32_t>(mesh_index);
    static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "vertices compared as packed floats");
    // An unchanged mesh keeps its BVH: in a Low-quality scene (two levels)
    // only the geometries committed since the last build are built again.
    if (slot.vertex_count == vertex_count && slot.triangle_count == triangle_count &&
        std::memcmp(rtcGetBufferData(slot.vertices), m.vertices.data(), vertex_count * 3 * sizeof(float)) == 0 &&
        std::memcmp(rtcGetBufferData(slot.indices), m.indices.data(), triangle_count * 3 * sizeof(unsigned)) == 0) {
      continue;
    }
    auto* v = static_cast<float*>(
        buffer_for(impl_->device, slot.vertices, slot.vertex_capacity, vertex_count, 3 * sizeof(float)));
    auto* idx = static_cast<unsigned*>(
        buffer_for(impl_->device, slot.indices, slot.triangle_capacity, triangle_count, 3 * sizeof(unsigned)));
    for (std::size_t i = 0; i < vertex_count; ++i) {
      v[3 * i] = m.vertices[i].x();
      v[3 * i + 1] = m.vertices[i].y();
      v[3 * i + 2] = m.vertices[i].z();
    }
    std::copy(m.indices.begin(), m.indices.end(), idx);
    rtcSetGeometryBuffer(slot.geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, slot.vertices, 0,
                         3 * sizeof(float), vertex_count);
    rtcSetGeometryBuffer(slot.geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, slot.indices, 0,
                         3 * sizeof(unsigned), triangle_count);
    slot.vertex_count = vertex_count;
    slot.triangle_count = triangle_count;
    rtcCommitGeometry(slot.geometry);
  }
  rtcCommitScene(impl_->scene);
  check_device(impl_->device, "building the scene");
}

TriangleScene::~TriangleScene() = default;

TriangleScene::Hit TriangleScene::intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                                            float t_near, float t_far) const {
  const RTCRayHit rh = cast_one(impl_->scene, origin, direction, t_near, t_far);
  Hit hit;
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
    hit.hit = true;
    hit.t = rh.ray.tfar;
    hit.label = labels_[rh.hit.geomID];
  }
  return hit;
}

TriangleScene::SurfaceHit TriangleScene::closest_hit(const Eigen::Vector3f& origin,
                                                     const Eigen::Vector3f& direction, float t_near,
                                                     float t_far) const {
  const RTCRayHit rh = cast_one(impl_->scene, origin, direction, t_near, t_far);
  SurfaceHit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.hit = true;
  hit.t = rh.ray.tfar;
  hit.mesh = meshes_[rh.hit.geomID];
  hit.triangle = rh.hit.primID;
  Eigen::Vector3f n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  n.normalize();
  hit.normal = n.dot(direction) > 0 ? -n : n;
  return hit;
}

void TriangleScene::intersect_batch(const Eigen::Vector3f& origin,
                                    std::span<const Eigen::Vector3f> directions, float t_near, float t_far,
                                    std::span<float> t_out, std::span<std::uint8_t> label_out,
                                    RayBatchMode mode) const {
  constexpr float kMiss = std::numeric_limits<float>::infinity();
  // Directions are the caller's precomputed unit rays; the origin and
  // interval are checked once for the batch.
  check_ray(origin, nullptr, t_near, t_far);
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

void TriangleScene::segments_blocked(std::span<const Segment> segments, std::span<std::uint8_t> blocked,
                                     RayBatchMode mode) const {
  const std::size_t n = segments.size();
  if (blocked.size() != n) {
    throw Error(ErrorCode::InvalidArgument, "TriangleScene::segments_blocked: " + std::to_string(n) +
                                                " segments but " + std::to_string(blocked.size()) + " flags");
  }
  std::atomic<std::size_t> lowest_bad{n};
  RTCScene scene = impl_->scene;
  const auto single = [&](std::size_t begin, std::size_t end) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray;
    Eigen::Vector3f o, d;
    for (std::size_t i = begin; i < end; ++i) {
      blocked[i] = 0;
      if (!segment_in_range(segments[i])) {
        record_lowest(lowest_bad, i);
        continue;
      }
      if (!segment_ray(segments[i], o, d)) continue;
      ray.org_x = o.x();
      ray.org_y = o.y();
      ray.org_z = o.z();
      ray.dir_x = d.x();
      ray.dir_y = d.y();
      ray.dir_z = d.z();
      ray.tnear = 0;
      ray.tfar = 1;
      ray.time = 0;
      ray.mask = 0xFFFFFFFFu;
      ray.id = 0;
      ray.flags = 0;
      rtcOccluded1(scene, &context, &ray);
      // Embree marks an occluded ray by setting tfar to -infinity.
      blocked[i] = ray.tfar < 0 ? 1 : 0;
    }
  };
  const auto packets = [&](std::size_t begin, std::size_t end) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    alignas(64) RTCRay16 packet;
    alignas(64) int valid[16];
    Eigen::Vector3f o, d;
    for (std::size_t base = begin; base < end; base += 16) {
      const std::size_t count = std::min<std::size_t>(16, end - base);
      for (std::size_t k = 0; k < 16; ++k) {
        bool on = false;
        if (k < count) {
          const std::size_t i = base + k;
          blocked[i] = 0;
          if (!segment_in_range(segments[i])) {
            record_lowest(lowest_bad, i);
          } else {
            on = segment_ray(segments[i], o, d);
          }
        }
        if (!on) o = d = Eigen::Vector3f::Zero();
        valid[k] = on ? -1 : 0;
        packet.org_x[k] = o.x();
        packet.org_y[k] = o.y();
        packet.org_z[k] = o.z();
        packet.dir_x[k] = d.x();
        packet.dir_y[k] = d.y();
        packet.dir_z[k] = d.z();
        packet.tnear[k] = 0;
        packet.tfar[k] = 1;
        packet.time[k] = 0;
        packet.mask[k] = 0xFFFFFFFFu;
        packet.id[k] = static_cast<unsigned>(k);
        packet.flags[k] = 0;
      }
      rtcOccluded16(valid, scene, &context, &packet);
      for (std::size_t k = 0; k < count; ++k) {
        if (valid[k] != 0 && packet.tfar[k] < 0) blocked[base + k] = 1;
      }
    }
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kSegmentsPerTask),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      if (mode == RayBatchMode::Single) {
                        single(r.begin(), r.end());
                      } else {
                        packets(r.begin(), r.end());
                      }
                    });
  const std::size_t bad = lowest_bad.load();
  if (bad < n) {
    const Segment& s = segments[bad];
    const bool finite = s.p.allFinite() && s.q.allFinite();
    throw Error(finite ? ErrorCode::OutOfRange : ErrorCode::InvalidArgument,
                "TriangleScene::segments_blocked: segment " + std::to_string(bad) +
                    (finite ? " has a coordinate beyond " +
                                  std::to_string(static_cast<int>(kMaxSceneCoordinate)) + " m"
                            : " has a non-finite endpoint"));
  }
}

}  // namespace sarmap::geometry
