// `sarmap simulate`: renders an arena (a JSON description, or a random one
// from a seed) into a sarmap sequence folder of world-frame, labelled frames.
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

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
};

void run_simulate(const SimulateArgs& a) {
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
    const std::string text = sim::random_arena_json(*a.random);
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
  cmd->callback([args] { run_simulate(*args); });
}

}  // namespace sarmap::cli
