// A front end outside sarmap's tree, linked against the installed package:
// maps the sequence named on the command line, prints the stage profile, the
// voxel counts, the segments and the topological map's size, and writes the
// run's output folder (as `sarmap run` would) when given one.
#include <cstdio>
#include <exception>

#include "engine/core/error.hpp"
#include "engine/core/version.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/io/scan_source.hpp"
#include "engine/pipeline/mapper.hpp"
#include "engine/pipeline/run_outputs.hpp"
#include "engine/topo/route_planner.hpp"

int main(int argc, char** argv) {
  if (argc != 2 && argc != 3) {
    std::fprintf(stderr, "usage: %s SEQUENCE [OUT]\n", argv[0]);
    return 2;
  }
  try {
    auto source = sarmap::open_scan_sequence(argv[1]);
    // The geometric baseline needs no model file; for the network set
    // config.classifier.kind = ClassifierKind::Dgcnn and config.classifier.model to a
    // .safetensors file (sarmap ships datasets/models/ramps-dgcnn.safetensors).
    sarmap::pipeline::MapperConfig config;
    config.classifier.kind = sarmap::pipeline::ClassifierKind::Geometric;
    sarmap::pipeline::Mapper mapper(config, source->sensor());
    sarmap::Scan scan;
    while (source->next(scan)) mapper.integrate(scan);
    // The network classifies the accumulated map, so some classes come after
    // their scan: finish() labels what still waits before the maps are read.
    mapper.finish();
    const auto counts = mapper.metric_map().counts();
    std::printf("sarmap %s: %zu scans, %zu occupied and %zu free voxels, %zu segments, %zu topological nodes\n",
                sarmap::kVersion, mapper.profile().scan_count(), counts.occupied, counts.free,
                mapper.segment_map().size(), mapper.topo_map().nodes().size());
    const auto route = sarmap::topo::plan_route(mapper.topo_map(), {0, 0, 0}, {1, 0, 0},
                                                sarmap::topo::RouteGraph::Grid);
    std::printf("grid route: %s\n", route.found ? "found" : route.reason.c_str());
    std::puts(mapper.profile().table().c_str());
    if (argc == 3) {
      sarmap::pipeline::RunRecord record{sarmap::pipeline::input_record(argv[1]), source->layout()};
      record.scans = mapper.profile().scan_count();
      sarmap::RunFolderWriter folder(argv[2]);
      sarmap::pipeline::write_run(mapper, folder, record);
      std::printf("wrote %s\n", argv[2]);
    }
    return counts.occupied > 0 ? 0 : 1;
  } catch (const sarmap::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
