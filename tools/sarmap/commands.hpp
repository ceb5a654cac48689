// Each subcommand of the sarmap CLI lives in its own file and registers itself
// on the app through one function declared here; main() only calls them. A
// command's callback signals failure by throwing sarmap::Error.
#pragma once

#include <CLI/CLI.hpp>

namespace sarmap::cli {

// (declarations: void add_<name>_command(CLI::App& app);)
void add_info_command(CLI::App& app);
void add_convert_command(CLI::App& app);
void add_simulate_command(CLI::App& app);
void add_eval_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_demo_command(CLI::App& app);
void add_classify_command(CLI::App& app);
void add_plan_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_view_command(CLI::App& app);
void add_merge_command(CLI::App& app);

}  // namespace sarmap::cli
