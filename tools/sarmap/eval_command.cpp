// `sarmap eval`: scores the outputs of `sarmap run` against an arena's ground truth.
#include <cstdio>
#include <string>

#include "engine/eval/run_evaluation.hpp"
#include "engine/sim/arena.hpp"
#include "tools/sarmap/commands.hpp"

namespace sarmap::cli {
namespace {

struct EvalArgs {
  std::string arena;
  std::string run;
  bool json = false;
};

void run_eval(const EvalArgs& a) {
  const sim::Arena arena = sim::load_arena(a.arena);
  const eval::RunEvaluation evaluation = eval::evaluate_run(arena, a.run);
  const std::string text = a.json ? eval::format_json(evaluation) : eval::format_table(evaluation);
  std::fputs(text.c_str(), stdout);
}

}  // namespace

void add_eval_command(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* cmd = app.add_subcommand("eval", "Score a run's outputs against an arena's ground truth");
  cmd->add_option("--arena", args->arena, "Arena description the run was simulated from")->required();
  cmd->add_option("--run", args->run, "Folder written by `sarmap run`")->required();
  cmd->add_flag("--json", args->json, "Print the figures as JSON");
  // Taken like every subcommand's --quiet; eval draws no progress, and the
  // figures are its result, so nothing is left to silence.
  const std::string quiet_help = "No progress output (eval prints none; its figures still print)";
  cmd->add_flag("--quiet", quiet_help);
  cmd->callback([args] { run_eval(*args); });
}

}  // namespace sarmap::cli
