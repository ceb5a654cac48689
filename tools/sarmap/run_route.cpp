#include "tools/sarmap/run_route.hpp"

#include <string>
#include <utility>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/segments/segment_files.hpp"
#include "engine/topo/graph_files.hpp"

namespace sarmap::cli {

namespace fs = std::filesystem;

topo::Route plan_on_run(const fs::path& run, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                        topo::RouteGraph graph, topo::RouteSearch search) {
  verify_run_folder(run);  // a half-written or mixed folder is refused
  for (const char* name : {"graph.json", "segments.json", "map.sarmap"}) {
    if (!fs::is_regular_file(run / name)) {
      throw Error(ErrorCode::Io,
                  (run / name).string() + " not found (plan needs a folder written by sarmap run)");
    }
  }
  topo::GraphFile graph_file = topo::read_graph_json(run / "graph.json");
  const segments::SegmentsFile segments_file = segments::read_segments_json(run / "segments.json");
  std::vector<const segments::Segment*> segments;
  for (const segments::Segment& s : segments_file.segments) segments.push_back(&s);
  const metric::MetricMap map = metric::load_map(run / "map.sarmap");
  const topo::TopoMap topo = topo::TopoMap::restore(graph_file.settings, std::move(graph_file.nodes),
                                                    std::move(graph_file.edges), segments, map);
  return topo::plan_route(topo, from, to, graph, search);
}

}  // namespace sarmap::cli
