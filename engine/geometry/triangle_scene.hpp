// Classed triangle meshes in one Embree scene, one geometry per mesh: first
// hits of rays (the simulated sensors, ground heights, rendered pictures) and
// batched occlusion of line segments (the topological map's edges against its
// walls). All scenes share one Embree device, created on first use.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/geometry/classed_mesh.hpp"
#include "engine/geometry/segment.hpp"

namespace sarmap::geometry {

// How a batch of rays is handed to Embree; both give the same answers
// (tested), the benchmarks say which is faster for which batch.
enum class RayBatchMode { Single, Packet16 };

// Embree's BVH build quality. High suits a scene built once and traced
// millions of times (the simulator's). Low (a Morton build) suits a scene
// rebuilt for each batch of queries, as the topological map's wall scene: it
// builds several times faster than Medium or High and answers as fast
// (PERF.md, bench/geometry).
enum class BuildQuality { Low, Medium, High };

// Bytes Embree holds now for every scene of the process (their indices and
// geometry buffers), as Embree reports them to the shared device's memory
// monitor; 0 before the first scene.
std::size_t embree_bytes();

// Every query is const and thread-safe: many threads may trace one scene.
class TriangleScene {
 public:
  // Builds the scene; empty meshes are skipped. Throws sarmap::Error
  // (InvalidData, naming the mesh) for a bad mesh (see validate_mesh), or if
  // Embree fails. Robust mode always: rays never slip through the shared edge
  // of two triangles (a floor's diagonal, a box's corner).
  explicit TriangleScene(std::span<const ClassedMesh> meshes, BuildQuality quality = BuildQuality::High);

  // Replaces the meshes with these: the scene then answers as one built from
  // them would (a hit's `mesh` is its index here), on the Embree scene,
  // geometries and buffers of the last build where they hold the new meshes
  // (buffers grow with half again as much room). A mesh equal to the one
  // at its index in the last build is not built again: in a Low-quality scene
  // (Embree's two-level index) the build then costs what changed. An empty
  // or missing mesh gives back its geometry and buffers. For a scene
  // rebuilt at every update (the topological map's walls, a mesh per tile):
  // buffers made anew each time leave the allocator holes that long runs pay
  // for in memory. Throws as the constructor does; a bad mesh is found
  // before anything changes, but after an Embree failure the scene must not
  // be traced. Not beside any query.
  void rebuild(std::span<const ClassedMesh> meshes);
  ~TriangleScene();
  TriangleScene(const TriangleScene&) = delete;
  TriangleScene& operator=(const TriangleScene&) = delete;

  struct Hit {
    float t = 0;  // in units of the direction's length
    ClassId label = ClassId::Unknown;
    bool hit = false;
  };

  // First surface along origin + t * direction with t in [t_near, t_far].
  // Throws sarmap::Error for an origin that is not finite or lies beyond
  // kMaxSceneCoordinate (OutOfRange), a non-finite direction or an interval
  // that is not 0 <= t_near <= t_far (InvalidArgument); intersect_batch checks
  // its origin and interval the same way.
  Hit intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
                float t_far) const;

  struct SurfaceHit {
    bool hit = false;
    float t = 0;                 // in units of the direction's length
    std::uint32_t mesh = 0;      // index of the hit mesh in the constructor's span
    std::uint32_t triangle = 0;  // index of the hit triangle within that mesh
    // Unit normal of the hit triangle's plane, turned to face the ray's
    // origin (so a renderer need not know the mesh's winding).
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  };

  // As intersect, but says which triangle of which mesh was hit and its
  // normal: what a renderer needs to colour and shade the pixel. Checks and
  // throws as intersect does.
  SurfaceHit closest_hit(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
                         float t_far) const;

  // A batch of rays from one origin: t_out[i] is the hit distance (infinity on
  // a miss), label_out[i] its class. Allocates nothing.
  void intersect_batch(const Eigen::Vector3f& origin, std::span<const Eigen::Vector3f> directions,
                       float t_near, float t_far, std::span<float> t_out, std::span<std::uint8_t> label_out,
                       RayBatchMode mode = RayBatchMode::Single) const;

  // blocked[i] = 1 when segments[i] meets a triangle, else 0; TBB-parallel
  // over the batch, nothing allocated per segment. A surface test: a segment lying wholly
  // inside a closed mesh, and a zero-length segment, are not blocked. Agrees
  // with the exact reference except near a surface (kSurfaceTolerance). The
  // answers do not depend on the thread count. Throws sarmap::Error
  // (InvalidArgument) when the spans differ in size, and, naming the lowest
  // such index, for an endpoint that is not finite (InvalidArgument) or
  // beyond kMaxSceneCoordinate (OutOfRange); `blocked` is then unspecified.
  // Packets of 16 are the default: on random edges they were never slower
  // than single rays at any size measured (bench/geometry).
  void segments_blocked(std::span<const Segment> segments, std::span<std::uint8_t> blocked,
                        RayBatchMode mode = RayBatchMode::Packet16) const;

  ClassId geometry_label(std::uint32_t geometry) const { return labels_[geometry]; }
  std::size_t geometry_count() const { return labels_.size(); }

  // Bytes this scene holds outside Embree (its tables of geometries), by
  // capacity. Embree's own part (the index, the geometry buffers) is in
  // embree_bytes().
  std::size_t memory_bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<ClassId> labels_;        // by Embree geometry id
  std::vector<std::uint32_t> meshes_;  // by Embree geometry id: the index in the last build's span
};

}  // namespace sarmap::geometry
