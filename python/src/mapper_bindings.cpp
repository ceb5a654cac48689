// Mapper: the pipeline's Mapper (engine/pipeline/mapper.hpp) for Python. Scans
// go in as numpy arrays through Mapper::integrate, the maps' queries come out
// vectorised, and write() is the CLI's write_run: the run API, not a second
// pipeline. Every native call runs without the GIL, one at a time per Mapper.
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>
#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/core/state_stream.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/io/scan_source.hpp"
#include "engine/metric/voxel_cloud.hpp"
#include "engine/pipeline/mapper.hpp"
#include "engine/pipeline/mapper_config_json.hpp"
#include "engine/pipeline/mapper_file.hpp"
#include "engine/pipeline/run_outputs.hpp"
#include "engine/segments/segment_files.hpp"
#include "engine/topo/graph_files.hpp"
#include "engine/topo/route_planner.hpp"
#include "python/src/array_arguments.hpp"
#include "python/src/bindings.hpp"
#include "python/src/config_arguments.hpp"
#include "python/src/errors.hpp"
#include "python/src/sequence.hpp"

namespace sarmap::python {

namespace {

// What a pickled Mapper holds: (version, config JSON, sensor dict, Mapper
// state bytes as a checkpoint holds them, scans offered, points dropped). The
// state is in the machine's byte order, as checkpoints are.
constexpr int kPickleVersion = 2;

struct PyMapper {
  PyMapper(const pipeline::MapperConfig& config, const SensorInfo& sensor) : mapper(config, sensor) {}

  pipeline::Mapper mapper;
  // Native calls run without the GIL, so two Python threads could otherwise
  // reach the same Mapper at once.
  std::mutex mutex;
  std::chrono::steady_clock::time_point created = std::chrono::steady_clock::now();
  std::size_t offered = 0;             // integrate() calls: the scan index in messages
  std::size_t dropped_non_finite = 0;  // points integrate() dropped for a NaN or infinite coordinate
};

// Runs fn(self) without the GIL, holding the Mapper's lock.
template <class Fn>
auto locked(PyMapper& self, Fn&& fn) {
  py::gil_scoped_release release;
  std::lock_guard lock(self.mutex);
  return fn(self);
}

// A vectorised point query: fn(map, point) per row, into a new array of the
// input's shape without its last axis.
template <class T, class Fn>
py::array_t<T> query(PyMapper& self, const py::object& points, Fn&& fn) {
  const QueryPoints q(points, "points");
  py::array_t<T> out(q.result_shape());
  T* values = out.mutable_data();
  locked(self, [&](PyMapper& m) {
    const metric::MetricMap& map = m.mapper.metric_map();
    for (std::size_t i = 0; i < q.size(); ++i) values[i] = fn(map, q[i]);
  });
  return out;
}

py::object parse_json(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

// manifest.json's input, layout and arena for write(input=...).
pipeline::RunRecord run_record(const py::object& input) {
  pipeline::RunRecord record;
  if (input.is_none()) {
    // Scans from arrays: no file defines the input.
    record.input = {{"path", nullptr}, {"sha256", nullptr}};
    record.layout = "arrays";
  } else if (py::isinstance<Sequence>(input)) {
    const Sequence& s = input.cast<const Sequence&>();
    record.input = pipeline::input_record(s.path());
    record.layout = s.source().layout();
    record.arena_sha256 = s.source().arena_sha256();
  } else {
    const std::string path = path_argument(input, "input");
    const std::unique_ptr<ScanSource> source = open_scan_sequence(path);
    record.input = pipeline::input_record(path);
    record.layout = source->layout();
    record.arena_sha256 = source->arena_sha256();
  }
  return record;
}

py::dict route_dict(const topo::Route& route) {
  py::dict d;
  d["found"] = route.found;
  d["reason"] = route.reason;
  d["graph"] = std::string(topo::to_string(route.graph));
  d["algorithm"] = route.graph == topo::RouteGraph::Grid ? std::string("wavefront")
                                                         : std::string(topo::to_string(route.search));
  d["length"] = route.length;
  py::array_t<double> points({static_cast<py::ssize_t>(route.points.size()), py::ssize_t{3}});
  auto rows = points.mutable_unchecked<2>();
  for (std::size_t i = 0; i < route.points.size(); ++i) {
    for (int c = 0; c < 3; ++c) rows(static_cast<py::ssize_t>(i), c) = route.points[i][c];
  }
  d["points"] = points;
  d["nodes"] = py::cast(route.nodes);
  return d;
}

}  // namespace

void bind_mapper(py::module_& m) {
  py::class_<PyMapper>(m, "Mapper", R"doc(
The pipeline's Mapper: builds the semantic, metric and topological maps scan by
scan. config: None (every default: the shipped DGCNN), a dict in the config
schema of docs/formats.md (only the keys it changes), or the path of a config
file or a run's manifest.json; an unknown key or a value of the wrong type is a
ValueError naming the dotted key. sensor: None or a dict ("type": "lidar" or
"depth_camera", "max_range", "min_range", "intrinsics"), e.g. a Sequence's
sensor: max_range 0 in the config takes the sensor's, and a LiDAR's segments
use segment_max_range_lidar.)doc")
      .def(py::init([](const py::object& config, const py::object& sensor) {
             const pipeline::MapperConfig c = config_argument(config, "config");
             const SensorInfo s = sensor_argument(sensor, "sensor");
             py::gil_scoped_release release;  // loading the model takes a while
             return std::make_unique<PyMapper>(c, s);
           }),
           py::arg("config") = py::none(), py::arg("sensor") = py::none())
      .def(
          "integrate",
          [](PyMapper& self, const py::object& points, const py::object& pose, const py::object& labels,
             const py::object& frame, const py::object& origin) {
            if (!py::isinstance<py::str>(frame)) {
              type_error("frame", "expected \"sensor\" or \"world\", got a " + describe(frame));
            }
            const std::string where = frame.cast<std::string>();
            if (where != "sensor" && where != "world") {
              value_error("frame", "expected \"sensor\" or \"world\", got \"" + where + "\"");
            }
            Scan scan;
            scan.points = point_buffer_argument(points, labels, "points");
            scan.pose = pose_argument(pose, "pose");
            scan.origin = origin.is_none() ? scan.pose.translation() : point_argument(origin, "origin");
            scan.source = "Mapper.integrate";
            locked(self, [&](PyMapper& m) {
              // As a sequence's reader does (engine/io/sarmap_sequence.cpp):
              // sensor-frame points are moved by the pose, and points with a
              // NaN or infinite coordinate (a depth camera's missing pixels)
              // are dropped.
              if (where == "sensor") scan.pose.apply(scan.points);
              m.dropped_non_finite += scan.points.remove_non_finite();
              scan.index = m.offered++;
              try {
                m.mapper.integrate(scan);
              } catch (const Error& e) {
                // As `sarmap run` skips a refused scan: listed in the profile,
                // its row dropped, the maps as they were.
                m.mapper.profile().skip_scan(scan.index, scan.source, e.what(), /*row_open=*/true);
                throw;
              }
            });
          },
          py::arg("points"), py::arg("pose"), py::arg("labels") = py::none(), py::arg("frame") = "sensor",
          py::arg("origin") = py::none(), R"doc(
Maps one scan. points: an (N, 3) float32 array (copied) or a PointCloud (copied,
with its labels and other fields); pose: the (4, 4) sensor-to-world transform
(rigid); labels: None or (N,) uint8 class ids (the labels classifier's input,
and ground truth beside any other classifier's). frame="sensor": points are in
the sensor frame and moved by the pose, as a sequence with points_frame sensor;
frame="world": points are in the world frame. Rays start at origin, the pose's
translation by default. Points with a NaN or infinite coordinate are dropped
(counted in dropped_non_finite). A scan the Mapper refuses raises ValueError and
leaves the maps as they were.)doc")
      .def(
          "integrate_sequence",
          [](PyMapper& self, Sequence& sequence, bool overlap, std::size_t start, const py::object& stop_arg) {
            std::size_t stop = sequence.source().size();
            if (!stop_arg.is_none()) {
              if (!py::isinstance<py::int_>(stop_arg) || stop_arg.cast<long long>() < 0) {
                type_error("stop", "expected None or a frame number >= 0, got " + describe(stop_arg));
              }
              stop = std::min(stop, stop_arg.cast<std::size_t>());
            }
            struct Skipped {
              std::size_t frame;
              std::string source, error;
            };
            std::vector<Skipped> skipped;
            std::size_t mapped = 0;
            locked(self, [&](PyMapper& m) {
              // As `sarmap run` maps a sequence: its stages overlapped unless
              // asked not to, a frame that cannot be read or a scan refused
              // costing only itself (listed in the profile, the maps as they were).
              sequence.rewind();
              sequence.skip_to(start);
              const auto read = [&](std::size_t frame, Scan& scan) { return frame < stop && sequence.next(scan); };
              const auto done = [&](pipeline::StreamedScan& item) {
                m.dropped_non_finite += item.scan.dropped_non_finite;
                ++m.offered;
                if (item.mapped) {
                  ++mapped;
                  return;
                }
                const std::string source =
                    item.read_failed ? "frame " + std::to_string(item.frame) : item.scan.source;
                m.mapper.profile().skip_scan(item.frame, source, item.error->what(), /*row_open=*/false);
                skipped.push_back({item.frame, source, item.error->what()});
              };
              m.mapper.integrate_stream(start, read, done,
                                        overlap ? pipeline::StageOverlap::On : pipeline::StageOverlap::Off);
            });
            py::dict result;
            result["scans"] = mapped;
            py::list listed;
            for (const Skipped& s : skipped) {
              py::dict d;
              d["frame"] = s.frame;
              d["source"] = s.source;
              d["error"] = s.error;
              listed.append(d);
            }
            result["skipped"] = listed;
            return result;
          },
          py::arg("sequence"), py::kw_only(), py::arg("overlap") = true, py::arg("start") = 0,
          py::arg("stop") = py::none(), R"doc(
Maps the frames [start, stop) of a Sequence (open_sequence; every frame by
default), as `sarmap run` does: with overlap=True the next scan is classified while the maps take this
one (two scans in flight, the same maps as one at a time; overlap=False runs
the stages in order). A frame that cannot be read, or a scan the Mapper
refuses, costs only itself: it is listed in the profile and in the result, and
the maps stay as they were. Returns {"scans": mapped, "skipped": [{"frame",
"source", "error"}, ...]}. Runs without the GIL.)doc")
      .def(
          "finish", [](PyMapper& self) { locked(self, [](PyMapper& m) { m.mapper.finish(); }); },
          "The scans have ended: the classifier of the accumulated map labels the blocks still waiting. Call "
          "it "
          "before reading the final maps; scans may still follow.")
      .def(
          "merge",
          [](PyMapper& self, PyMapper& other, const py::object& transform) {
            if (&self == &other) throw py::value_error("other: a Mapper cannot be merged into itself");
            const Pose other_to_this = transform.is_none() ? Pose() : pose_argument(transform, "transform");
            std::size_t graph_nodes = 0;
            const pipeline::MapperMergeCounts c = [&] {
              py::gil_scoped_release release;
              std::scoped_lock lock(self.mutex, other.mutex);
              const pipeline::MapperMergeCounts counts = self.mapper.merge(other.mapper, other_to_this);
              self.dropped_non_finite += other.dropped_non_finite;
              graph_nodes = self.mapper.topo_map().nodes().size();
              return counts;
            }();
            py::dict out;
            out["blocks_added"] = c.metric.blocks_added;
            out["blocks_merged"] = c.metric.blocks_merged;
            out["voxels_in_both"] = c.metric.voxels_in_both;
            out["semantic_points_added"] = c.semantic_points_added;
            out["segments_created"] = c.segments.created;
            out["segments_merged"] = c.segments.merged;
            out["graph_nodes"] = graph_nodes;
            return out;
          },
          py::arg("other"), py::arg("transform") = py::none(),
          "Merges another Mapper's maps (another robot or another part of the sequence) into this one: both "
          "are finished, the metric map merges voxel by voxel (log-odds and class evidence added and "
          "clamped), kept points by voxel, the labelled point map by cell, segments by the scan-by-scan "
          "merge rule, and the graph is rebuilt. transform: None (same map frame) or the (4, 4) rigid "
          "transform from other's map frame into this one's (points and segments move exactly; voxels are "
          "resampled, exactly for whole-voxel shifts and quarter turns). `other` keeps its maps. This Mapper "
          "then takes no more scans, but may take further merges. ValueError naming both values when the "
          "resolutions, voxels or classifiers differ. Returns the merge's counts as a dict.")
      .def(py::pickle(
          [](PyMapper& self) {
            std::string config, state;
            SensorInfo sensor;
            std::size_t offered = 0, dropped = 0;
            locked(self, [&](PyMapper& m) {
              config = pipeline::config_to_json(m.mapper.config()).dump();
              sensor = m.mapper.sensor();
              StateWriter out;
              m.mapper.save_state(out);
              state = out.bytes();
              offered = m.offered;
              dropped = m.dropped_non_finite;
            });
            return py::make_tuple(kPickleVersion, config, sensor_dict(sensor), py::bytes(state), offered, dropped);
          },
          [](const py::tuple& t) {
            if (t.size() != 6 || !py::isinstance<py::int_>(t[0]) || t[0].cast<int>() != kPickleVersion) {
              value_error("state", "not a pickled sarmap.Mapper of this version");
            }
            pipeline::MapperConfig config;
            try {
              config = pipeline::config_from_json(nlohmann::ordered_json::parse(t[1].cast<std::string>()));
            } catch (const nlohmann::json::exception& e) {
              value_error("state", std::string("the pickled config is not JSON: ") + e.what());
            }
            const SensorInfo sensor = sensor_argument(t[2], "sensor");
            const std::string state = t[3].cast<std::string>();
            auto mapper = [&] {
              py::gil_scoped_release release;  // loading the model and the maps takes a while
              auto m = std::make_unique<PyMapper>(config, sensor);
              StateReader in(state, "pickled Mapper");
              m->mapper.load_state(in);
              return m;
            }();
            mapper->offered = t[4].cast<std::size_t>();
            mapper->dropped_non_finite = t[5].cast<std::size_t>();
            return mapper;
          }))
      .def_property_readonly(
          "merged",
          [](PyMapper& self) { return locked(self, [](PyMapper& m) { return m.mapper.merged(); }); },
          "Whether merge() made this Mapper (it then takes no more scans).")
      .def(
          "write",
          [](PyMapper& self, const py::object& folder, const py::object& input, bool keep_state) {
            const std::string out = path_argument(folder, "folder");
            pipeline::RunRecord record = run_record(input);
            record.mapper_state = keep_state;
            locked(self, [&](PyMapper& m) {
              m.mapper.profile().set_wall_seconds(
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - m.created).count());
              record.scans = m.mapper.profile().scan_count();
              record.scans_skipped = m.mapper.profile().skipped_scans();
              RunFolderWriter writer(out);
              pipeline::write_run(m.mapper, writer, record);
            });
          },
          py::arg("folder"), py::arg("input") = py::none(), py::arg("keep_state") = false,
          "Writes the run's output folder as `sarmap run` does (write_run: map.sarmap, voxels.ply, segments, "
          "graph, grid, profile, summary, then manifest.json). input: the Sequence or path the scans came "
          "from, recorded in the manifest (None: scans from arrays). keep_state: also write mapper.state, "
          "which Mapper.load and `sarmap merge` read. The profile's wall time is the time since the Mapper "
          "was made.")
      .def_static(
          "load",
          [](const py::object& path) {
            const std::string file = path_argument(path, "path");
            std::unique_ptr<PyMapper> made;
            {
              py::gil_scoped_release release;  // loading the model and the maps takes a while
              pipeline::load_mapper_file(
                  file, [&](const pipeline::MapperConfig& config, const SensorInfo& sensor) -> pipeline::Mapper& {
                    made = std::make_unique<PyMapper>(config, sensor);
                    return made->mapper;
                  });
            }
            return made;
          },
          py::arg("path"),
          "A Mapper from a mapper.state file (`sarmap run --keep-state`, Mapper.write(keep_state=True)), "
          "with the config, sensor and maps it was saved with. RuntimeError naming the file when it is "
          "damaged, truncated or of another version.")
      .def(
          "state_at",
          [](PyMapper& self, const py::object& points) {
            return query<std::uint8_t>(self, points,
                                       [](const metric::MetricMap& map, const Eigen::Vector3d& p) {
                                         return static_cast<std::uint8_t>(map.state_at(p));
                                       });
          },
          py::arg("points"),
          "Voxel state per point of an (..., 3) float32/float64 array: UNKNOWN (0), FREE (1) or OCCUPIED "
          "(2), as "
          "uint8 of shape (...); unknown for NaN and beyond the map's limits.")
      .def(
          "class_at",
          [](PyMapper& self, const py::object& points) {
            return query<std::uint8_t>(self, points,
                                       [](const metric::MetricMap& map, const Eigen::Vector3d& p) {
                                         return static_cast<std::uint8_t>(map.class_at(p));
                                       });
          },
          py::arg("points"), "Class id (uint8) of the occupied voxel at each point; 0 (unknown) elsewhere.")
      .def(
          "probability_at",
          [](PyMapper& self, const py::object& points) {
            return query<double>(self, points, [](const metric::MetricMap& map, const Eigen::Vector3d& p) {
              return map.probability_at(p);
            });
          },
          py::arg("points"), "Occupancy probability (float64) at each point; 0.5 where unknown.")
      .def(
          "voxel_cloud",
          [](PyMapper& self) {
            return locked(self,
                          [](PyMapper& m) { return metric::occupied_voxel_cloud(m.mapper.metric_map()); });
          },
          "The occupied voxels as a PointCloud (voxels.ply's points): centres, labels = class, scores "
          "[\"probability\"] = occupancy probability.")
      .def(
          "occupied_voxels",
          [](PyMapper& self) {
            py::object cloud = py::cast(locked(
                self, [](PyMapper& m) { return metric::occupied_voxel_cloud(m.mapper.metric_map()); }));
            return py::make_tuple(cloud.attr("xyz"), cloud.attr("labels"));
          },
          "(centres, classes): the occupied voxels' centres as an (M, 3) float32 array (a copy) and their "
          "classes "
          "as (M,) uint8 (a view), in the order of voxels.ply.")
      .def(
          "counts",
          [](PyMapper& self) {
            const metric::MapCounts c =
                locked(self, [](PyMapper& m) { return m.mapper.metric_map().counts(); });
            py::dict d;
            d["blocks"] = c.blocks;
            d["known"] = c.known;
            d["free"] = c.free;
            d["occupied"] = c.occupied;
            return d;
          },
          "Voxels by state and the block count of the metric map.")
      .def(
          "segments",
          [](PyMapper& self) {
            return parse_json(
                locked(self, [](PyMapper& m) { return segments::segments_json(m.mapper.segment_map()); }));
          },
          "The planar segments as segments.json holds them: {\"version\", \"segments\": [{\"id\", \"class\", "
          "\"normal\", \"slope_deg\", \"area_m2\", \"rectangle\", ...}], \"merges\"}.")
      .def(
          "graph",
          [](PyMapper& self) {
            return parse_json(
                locked(self, [](PyMapper& m) { return topo::graph_json(m.mapper.topo_map()); }));
          },
          "The topological map as graph.json holds it, networkx's node-link form "
          "(networkx.node_link_graph(mapper.graph()) loads it).")
      .def(
          "plan",
          [](PyMapper& self, const py::object& start, const py::object& goal, const std::string& graph,
             const std::string& algorithm) {
            const auto g = topo::route_graph_from(graph);
            if (!g) value_error("graph", "expected \"tree\", \"roadmap\" or \"grid\", got \"" + graph + "\"");
            const auto s = topo::route_search_from(algorithm);
            if (!s) value_error("algorithm", "expected \"dijkstra\" or \"astar\", got \"" + algorithm + "\"");
            const Eigen::Vector3d from = point_argument(start, "start"), to = point_argument(goal, "goal");
            const topo::Route route = locked(
                self, [&](PyMapper& m) { return topo::plan_route(m.mapper.topo_map(), from, to, *g, *s); });
            return route_dict(route);
          },
          py::arg("start"), py::arg("goal"), py::arg("graph") = "tree", py::arg("algorithm") = "dijkstra",
          "A path between two points as `sarmap plan` finds it: on the spanning tree, the roadmap (Dijkstra "
          "or A*) "
          "or the traversability grid (wavefront). Returns {\"found\", \"reason\" (why not), \"graph\", "
          "\"algorithm\", \"length\", \"points\": (K, 3) float64, \"nodes\"}.")
      .def(
          "semantic_points",
          [](PyMapper& self) {
            return locked(self, [](PyMapper& m) {
              PointBuffer points = m.mapper.semantic_points();
              // Classes that came after their scan, or changed since, are the map's now (as write_run does).
              if (m.mapper.classifier().labels_arrive_late()) m.mapper.classifier().relabel(points);
              return points;
            });
          },
          "The kept classified points (semantic_points.ply's) as a PointCloud: a copy, labels as the map has "
          "them "
          "now.")
      .def(
          "profile",
          [](PyMapper& self) {
            return parse_json(locked(self, [](PyMapper& m) { return m.mapper.profile().json(); }));
          },
          "Time and counters per stage, as profile.json holds them.")
      .def_property_readonly(
          "config",
          [](PyMapper& self) {
            return parse_json(
                locked(self, [](PyMapper& m) { return pipeline::config_to_json(m.mapper.config()).dump(); }));
          },
          "Every setting, as a dict in the config schema.")
      .def_property_readonly(
          "scans",
          [](PyMapper& self) {
            return locked(self, [](PyMapper& m) { return m.mapper.profile().scan_count(); });
          },
          "Scans mapped so far.")
      .def_property_readonly(
          "dropped_non_finite",
          [](PyMapper& self) { return locked(self, [](PyMapper& m) { return m.dropped_non_finite; }); },
          "Points dropped for a NaN or infinite coordinate: by integrate(), and by the reader of the frames "
          "integrate_sequence() mapped.")
      .def_property_readonly(
          "resolution",
          [](PyMapper& self) {
            return locked(self, [](PyMapper& m) { return m.mapper.metric_map().resolution(); });
          },
          "The metric map's voxel edge, metres.");
}

}  // namespace sarmap::python
