// `sarmap view RUNDIR [--out FILE] [--path path.json] [--max-points N]`:
// writes RUNDIR/view.html, one page that opens from disk with no network: the
// viewer's script (web/viewer/, three.js bundled in by the build) and the
// run's layers (view_data.hpp) inlined. Written atomically.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/run_folder.hpp"
#include "tools/sarmap/commands.hpp"
#include "tools/sarmap/number_checks.hpp"
#include "tools/sarmap/shipped_data.hpp"
#include "tools/sarmap/view_data.hpp"

namespace sarmap::cli {
namespace {

namespace fs = std::filesystem;

struct ViewArgs {
  std::string run;
  std::string out;
  std::string path;
  std::size_t max_points = ViewDataOptions{}.max_items;
  bool quiet = false;
};

// Text inside a <script> element ends at the first "</script", whatever
// JavaScript or JSON string it stands in. In JSON a '<' can only stand in a
// string, where \u003c means the same; in the script "<\/script" does, in
// its strings and regular expressions alike.
std::string json_script_safe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (const char c : json) {
    if (c == '<') {
      out += "\\u003c";
    } else {
      out += c;
    }
  }
  return out;
}

std::string script_safe(std::string script) {
  const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; };
  for (std::size_t at = script.find("</"); at != std::string::npos; at = script.find("</", at + 1)) {
    std::string word;
    for (std::size_t i = at + 2; i < script.size() && i < at + 8; ++i) word += lower(script[i]);
    if (word == "script") script.insert(at + 1, "\\");
  }
  return script;
}

std::string html_escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string layer_counts(const nlohmann::ordered_json& layers) {
  std::string text;
  for (const auto& [name, layer] : layers.items()) {
    text += (text.empty() ? "" : ", ") + name + " " + std::to_string(layer["count"].get<std::size_t>());
    if (layer.contains("total") && layer["total"] != layer["count"]) {
      text += " of " + std::to_string(layer["total"].get<std::size_t>());
    }
  }
  return text;
}

void run_view(const ViewArgs& a) {
  const fs::path run = a.run;
  std::error_code ec;
  if (!fs::exists(run, ec)) throw Error(ErrorCode::Io, "view: " + run.string() + " not found");
  if (!fs::is_directory(run, ec)) {
    throw Error(ErrorCode::InvalidArgument,
                "view: " + run.string() + " is not a folder written by sarmap run");
  }
  verify_run_folder(run);  // a half-written or mixed folder is refused
  const fs::path bundle = shipped_viewer_bundle();

  ViewDataOptions options;
  options.max_items = a.max_points;
  if (!a.path.empty()) {
    if (!fs::is_regular_file(a.path, ec)) throw Error(ErrorCode::Io, "view: --path " + a.path + " not found");
    options.path_file = a.path;
  } else if (fs::is_regular_file(run / "path.json", ec)) {
    options.path_file = run / "path.json";
  }
  const ViewData data = read_view_data(run, options);
  const FileBytes script = read_file_bytes(bundle);

  const fs::path out = a.out.empty() ? run / "view.html" : fs::path(a.out);
  AtomicFileWriter page(out);
  page.write("<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>sarmap view: " +
             html_escaped(data.json["run"].get<std::string>()) +
             "</title>\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n</head>\n"
             "<body>\n<script id=\"sarmap-data\" type=\"application/json\">");
  page.write(json_script_safe(data.json.dump()));
  page.write("</script>\n<script>\n");
  page.write(script_safe(std::string(script.view())));
  page.write("\n</script>\n</body>\n</html>\n");
  page.commit();

  if (a.quiet) return;
  for (const std::string& note : data.notes) std::printf("note: %s\n", note.c_str());
  std::printf("wrote %s (%s)\n", out.string().c_str(), layer_counts(data.json["layers"]).c_str());
}

}  // namespace

void add_view_command(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  CLI::App* cmd = app.add_subcommand(
      "view", "Write RUNDIR/view.html, a 3-D view of a run that opens offline in a browser");
  cmd->add_option("RUNDIR", args->run, "Folder written by `sarmap run`")->required();
  cmd->add_option("--out", args->out, "Write the page here instead of RUNDIR/view.html");
  cmd->add_option("--path", args->path,
                  "A route from `sarmap plan --out` to draw (default: RUNDIR/path.json if there)");
  cmd->add_option("--max-points", args->max_points,
                  "Most points, voxels or free voxels drawn per layer; more are thinned evenly")
      ->check(finite_positive())
      ->capture_default_str();
  cmd->add_flag("--quiet", args->quiet, "Print nothing");
  cmd->callback([args] { run_view(*args); });
}

}  // namespace sarmap::cli
