// `sarmap simulate`: renders an arena (a JSON description, or a random one
// from a seed) into a sarmap sequence folder of world-frame, labelled frames.
// A random arena's sensor is chosen here (--sensor and its options); an arena
// file's sensor is the file's.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/random_arena.hpp"
#include "engine/sim/simulator.hpp"
#include "tools/sarmap/number_checks.hpp"
#include "tools/sarmap/commands.hpp"
#include "tools/sarmap/progress.hpp"

namespace sarmap::cli {
namespace {

struct SimulateArgs {
  std::string arena;
  std::string out;
  std::uint64_t seed = 0;
  std::size_t frames = 0;
  bool quiet = false;
  std::optional<std::uint64_t> random;
  std::string write_arena;
  // The random arena's sensor; unset options keep RandomSensor's defaults.
  std::string sensor = "depth";
  std::optional<double> sensor_height, pitch, min_range, max_range;
  std::optional<int> width, height, rings, samples;
  std::vector<double> vertical_fov;
};

std::string show(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// The sensor options as a RandomSensor; a combination no sensor can have is a
// usage error (exit 2), naming the options.
sim::RandomSensor random_sensor(const SimulateArgs& a, const CLI::App& cmd) {
  const auto usage = [](const std::string& what) { throw CLI::ValidationError("simulate", what); };
  const bool lidar = a.sensor == "lidar";
  std::vector<std::string> given;
  for (const char* name : {"--sensor", "--sensor-height", "--pitch", "--min-range", "--max-range", "--width",
                           "--height", "--rings", "--samples", "--vertical-fov"}) {
    if (cmd.count(name) > 0) given.emplace_back(name);
  }
  if (!given.empty() && !a.random) {
    usage(given.front() +
          " chooses a random arena's sensor and needs --random SEED (an arena file's sensor is its "
          "\"sensor\" and \"trajectory\" objects)");
  }
  for (const char* name : lidar ? std::array{"--width", "--height"} : std::array{"--rings", "--samples"}) {
    if (cmd.count(name) > 0) usage(std::string(name) + " is not an option of --sensor " + a.sensor);
  }
  if (!lidar && cmd.count("--vertical-fov") > 0) usage("--vertical-fov is an option of --sensor lidar");
  sim::RandomSensor s;
  s.type = lidar ? SensorType::Lidar : SensorType::DepthCamera;
  s.height = a.sensor_height;
  s.pitch_deg = a.pitch;
  s.min_range = a.min_range;
  s.max_range = a.max_range;
  if (a.width) s.width = *a.width;
  if (a.height) s.image_height = *a.height;
  if (a.rings) s.rings = *a.rings;
  if (a.samples) s.samples = *a.samples;
  if (!a.vertical_fov.empty()) {
    if (!(a.vertical_fov[0] < a.vertical_fov[1])) {
      usage("--vertical-fov MIN,MAX needs MIN < MAX, got " + show(a.vertical_fov[0]) + "," +
            show(a.vertical_fov[1]));
    }
    s.vertical_fov_min_deg = a.vertical_fov[0];
    s.vertical_fov_max_deg = a.vertical_fov[1];
  }
  const double min_range = s.min_range.value_or(lidar ? 0.4 : 0.3);
  const double max_range = s.max_range.value_or(lidar ? 12.0 : 5.0);
  if (!(max_range > min_range)) {
    usage("--max-range (" + show(max_range) + ") must be greater than --min-range (" + show(min_range) + ")");
  }
  return s;
}

void run_simulate(const SimulateArgs& a, const CLI::App& cmd) {
  const sim::RandomSensor sensor = random_sensor(a, cmd);
  if (a.random && !a.arena.empty()) {
    throw Error(ErrorCode::InvalidArgument, "simulate: give either ARENA.json or --random SEED, not both");
  }
  if (!a.random && a.arena.empty()) throw Error(ErrorCode::InvalidArgument, "simulate: give ARENA.json or --random SEED");
  if (!a.write_arena.empty() && !a.random) {
    throw Error(ErrorCode::InvalidArgument, "simulate: --write-arena saves a generated arena; it needs --random");
  }
  if (a.out.empty() && a.write_arena.empty()) throw Error(ErrorCode::InvalidArgument, "simulate: --out DIR is required");
  sim::Arena arena;
  if (a.random) {
    const std::string text = sim::random_arena_json(*a.random, sensor);
    if (!a.write_arena.empty()) {
      AtomicFileWriter writer(a.write_arena);
      writer.write(text);
      writer.commit();
      if (!a.quiet) std::printf("wrote arena %s\n", a.write_arena.c_str());
    }
    arena = sim::parse_arena(text, "random-" + std::to_string(*a.random), ".");
  } else {
    arena = sim::load_arena(a.arena);
  }
  if (a.out.empty()) return;
  sim::SimulationOptions options;
  options.seed = a.seed;
  const sim::Simulator simulator(arena, options);
  const std::size_t frames = a.frames == 0 ? simulator.frame_count() : std::min(a.frames, simulator.frame_count());
  std::size_t total = 0;
  // Only a terminal gets a line per frame, redrawn in place; a log gets the summary.
  ProgressLine progress("simulate", frames, !a.quiet);
  sim::write_simulated_sequence(simulator, a.out, frames, [&](std::size_t frame, std::size_t points) {
    total += points;
    progress.update(frame + 1);
  });
  progress.finish();
  if (!a.quiet) std::printf("%s: %zu frames, %zu points written to %s\n", arena.name.c_str(), frames, total, a.out.c_str());
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate a sensor in an arena and write a sequence folder");
  cmd->add_option("arena", args->arena, "Arena description (datasets/arenas/*.json)");
  cmd->add_option("--out", args->out,
                  "Output sequence folder (an earlier sequence.json and frame_NNNNNN.ply files there are "
                  "removed first; other files stay)");
  cmd->add_option("--seed", args->seed, "Seed of the sensor noise (default 0)")->check(finite_non_negative());
  cmd->add_option("--frames", args->frames, "Simulate only the first N frames")->check(CLI::PositiveNumber);
  cmd->add_flag("--quiet", args->quiet, "No progress line or summary");
  cmd->add_option("--random", args->random, "Generate a random NIST-like arena from this seed")
      ->check(finite_non_negative());
  cmd->add_option("--write-arena", args->write_arena, "Save the generated arena's JSON (with --random)");
  // The random arena's sensor (--random only: docs/training.md).
  const std::string sensor_group = "Sensor of a random arena (with --random)";
  cmd->add_option("--sensor", args->sensor,
                  "depth (a 320 x 240 depth camera, the default) or lidar (a spinning LiDAR)")
      ->check(CLI::IsMember({"depth", "lidar"}))
      ->group(sensor_group);
  cmd->add_option("--sensor-height", args->sensor_height, "Height above the ground (m, default 0.5)")
      ->check(finite_positive() & CLI::Range(0.0, 2.0))
      ->group(sensor_group);
  cmd->add_option(
         "--pitch", args->pitch,
         "Pitch in degrees, nose up positive (default: the camera's drawn from the seed in [-25, -10], "
         "the LiDAR's 0)")
      ->check(CLI::Range(-89.0, 89.0))
      ->group(sensor_group);
  cmd->add_option("--min-range", args->min_range, "Nearest return (m; default 0.3 camera, 0.4 LiDAR)")
      ->check(finite_non_negative())
      ->group(sensor_group);
  cmd->add_option("--max-range", args->max_range, "Farthest return (m; default 5 camera, 12 LiDAR)")
      ->check(finite_positive() & CLI::Range(0.0, 100.0))
      ->group(sensor_group);
  cmd->add_option("--width", args->width,
                  "Depth camera: image width (default 320; the field of view stays 60 degrees)")
      ->check(CLI::Range(16, 4096))
      ->group(sensor_group);
  cmd->add_option("--height", args->height, "Depth camera: image height (default 240)")
      ->check(CLI::Range(16, 4096))
      ->group(sensor_group);
  cmd->add_option("--rings", args->rings, "LiDAR: rings (default 16)")
      ->check(CLI::Range(1, 128))
      ->group(sensor_group);
  cmd->add_option("--samples", args->samples, "LiDAR: samples per ring over 360 degrees (default 1800)")
      ->check(CLI::Range(16, 16384))
      ->group(sensor_group);
  cmd->add_option("--vertical-fov", args->vertical_fov,
                  "LiDAR: lowest and highest ring's elevation in degrees, MIN,MAX (default -15,15)")
      ->expected(2)
      ->delimiter(',')
      ->check(CLI::Range(-90.0, 90.0))
      ->group(sensor_group);
  cmd->callback([args, cmd] { run_simulate(*args, *cmd); });
}

}  // namespace sarmap::cli
