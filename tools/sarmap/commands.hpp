// Each subcommand of the sarmap CLI registers itself on the app; main() only
// lists them. A command signals failure by throwing sarmap::Error.
#pragma once

#include <CLI/CLI.hpp>

namespace sarmap::cli {

// Options every command shares.
struct GlobalOptions {
  bool quiet = false;
};

}  // namespace sarmap::cli
