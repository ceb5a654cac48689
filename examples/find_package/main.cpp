// A front end outside sarmap's tree, linked against the installed package:
// maps the sequence named on the command line and prints the stage profile,
// the voxel counts, the segments and the topological map's size.
#include <cstdio>
#include <exception>

#include "engine/core/error.hpp"
#include "engine/core/version.hpp"
#include "engine/io/scan_source.hpp"
#include "engine/pipeline/mapper.hpp"
#include "engine/topo/route_planner.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s SEQUENCE\n", argv[0]);
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
    const auto counts = mapper.metric_map().counts();
    std::printf("sarmap %s: %zu scans, %zu occupied and %zu free voxels, %zu segments, %zu topological nodes\n",
                sarmap::kVersion, mapper.profile().scan_count(), counts.occupied, counts.free,
                mapper.segment_map().size(), mapper.topo_map().nodes().size());
    const auto route = sarmap::topo::plan_route(mapper.topo_map(), {0, 0, 0}, {1, 0, 0},
                                                sarmap::topo::RouteGraph::Grid);
    std::printf("grid route: %s\n", route.found ? "found" : route.reason.c_str());
    std::puts(mapper.profile().table().c_str());
    return counts.occupied > 0 ? 0 : 1;
  } catch (const sarmap::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
