// A flag that turns a default-on rule off (--no-ramp-veto, ...). CLI11's own
// negated flag ("!--no-x" bound to the setting) shows "--no-x{false}" in
// --help; this shows the flag as it is typed.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace sarmap::cli {

inline CLI::Option* add_off_switch(CLI::App* cmd, const std::string& flag, bool& setting,
                                   const std::string& description) {
  return cmd->add_flag_callback(flag, [&setting] { setting = false; }, description);
}

}  // namespace sarmap::cli
