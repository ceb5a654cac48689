// `sarmap plan` on a run of a small simulated room with a doorway: a path on
// each graph, no path as an answer with a reason, bad options as errors, and
// graph.json as networkx reads it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/cli/cli_runner.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::run_cli;

class PlanCommand : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(dir());
    fs::create_directories(dir());
    const fs::path arena = fs::path(SARMAP_SOURCE_DIR) / "tests" / "cli" / "data" / "room_with_door.json";
    const auto sim = run_cli("simulate " + quoted(arena.string()) + " --out " + quoted((dir() / "seq").string()) +
                                 " --quiet",
                             dir());
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const auto r = run_cli("run " + quoted((dir() / "seq").string()) + " --out " + quoted(run().string()) +
                               " --classifier labels --quiet",
                           dir());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { fs::remove_all(dir()); }
  static fs::path dir() { return fs::temp_directory_path() / ("sarmap_plan_cli_" + std::to_string(::getpid())); }
  static fs::path run() { return dir() / "run"; }
  static test::CliResult plan(const std::string& args) {
    return run_cli("plan " + quoted(run().string()) + " " + args, dir());
  }
  static nlohmann::json json_of(const fs::path& file) { return nlohmann::json::parse(test::read_all(file)); }
};

TEST_F(PlanCommand, FindsAPathThroughTheDoorwayOnEveryGraph) {
  for (const char* graph : {"tree", "roadmap", "grid"}) {
    const fs::path out = dir() / (std::string(graph) + ".json");
    const auto r = plan(std::string("--from 0.6,0.6,0 --to 3.4,2.4,0 --graph ") + graph + " --out " + quoted(out.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(std::string("path on the ") + graph), std::string::npos) << r.out;
    const auto path = json_of(out);
    EXPECT_TRUE(path.at("found").get<bool>());
    EXPECT_EQ(path.at("graph"), graph);
    EXPECT_GE(path.at("length").get<double>(), std::hypot(2.8, 1.8));
    bool crossed_in_door = false;
    const auto& points = path.at("points");
    for (std::size_t i = 1; i < points.size(); ++i) {
      const double x0 = points[i - 1][0], x1 = points[i][0];
      if ((x0 < 2) == (x1 < 2)) continue;
      const double t = (2 - x0) / (x1 - x0);
      const double y = points[i - 1][1].get<double>() + t * (points[i][1].get<double>() - points[i - 1][1].get<double>());
      crossed_in_door = crossed_in_door || (y > 1.1 && y < 1.9);
      EXPECT_GT(y, 1.1);
      EXPECT_LT(y, 1.9);
    }
    EXPECT_TRUE(crossed_in_door) << graph;
    if (std::string(graph) != "grid") {
      EXPECT_GE(path.at("nodes").size(), 2u);
    }
  }
  const auto a = plan("--from 0.6,0.6,0 --to 3.4,2.4,0 --graph roadmap --algorithm astar --out " +
                      quoted((dir() / "astar.json").string()));
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_NEAR(json_of(dir() / "astar.json").at("length").get<double>(),
              json_of(dir() / "roadmap.json").at("length").get<double>(), 1e-9);
}

TEST_F(PlanCommand, NoPathIsAnAnswerWithAReason) {
  const fs::path out = dir() / "blocked.json";
  const auto r = plan("--from 0.6,0.6,0 --to 2.0,2.5,0 --out " + quoted(out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("no path on the tree: goal_blocked"), std::string::npos) << r.out;
  const auto path = json_of(out);
  EXPECT_FALSE(path.at("found").get<bool>());
  EXPECT_EQ(path.at("reason"), "goal_blocked");
  const auto outside = plan("--from 9,9,0 --to 0.6,0.6,0 --graph grid");
  ASSERT_EQ(outside.exit_code, 0) << outside.err;
  EXPECT_NE(outside.out.find("unknown_space"), std::string::npos) << outside.out;
}

TEST_F(PlanCommand, BadOptionsAreErrors) {
  auto bad = plan("--from 1,2 --to 3.4,2.4,0");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("--from must be x,y,z"), std::string::npos) << bad.err;
  bad = plan("--from 1,2,nan --to 3.4,2.4,0");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("finite"), std::string::npos) << bad.err;
  bad = plan("--from 1,2,0 --to 3.4,2.4,0 --graph maze");
  EXPECT_NE(bad.err.find("--graph must be tree, roadmap or grid"), std::string::npos) << bad.err;
  bad = run_cli("plan " + quoted((dir() / "nowhere").string()) + " --from 0,0,0 --to 1,1,0", dir());
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("nowhere: no manifest.json"), std::string::npos) << bad.err;
}

TEST_F(PlanCommand, GraphJsonLoadsInNetworkx) {
  // networkx 3.4 and later name the link list with edges=; Debian 12's 2.8 reads "links" by default.
  const std::string script = "import json, sys, networkx as nx\n"
                             "data = json.load(open(sys.argv[1]))\n"
                             "try:\n"
                             "    g = nx.node_link_graph(data, edges='links')\n"
                             "except TypeError:\n"
                             "    g = nx.node_link_graph(data)\n"
                             "t = [e for e in g.edges(data=True) if e[2]['in_tree']]\n"
                             "print(g.number_of_nodes(), g.number_of_edges(), len(t), nx.number_connected_components(g))\n";
  std::ofstream(dir() / "load.py") << script;
  const std::string command = "python3 " + quoted((dir() / "load.py").string()) + " " +
                              quoted((run() / "graph.json").string()) + " > " + quoted((dir() / "nx.txt").string()) +
                              " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << test::read_all(dir() / "nx.txt");
  const auto graph = json_of(run() / "graph.json");
  std::size_t tree = 0;
  for (const auto& link : graph.at("links")) tree += link.at("in_tree").get<bool>();
  std::istringstream nx(test::read_all(dir() / "nx.txt"));
  std::size_t nodes = 0, edges = 0, tree_edges = 0, components = 0;
  nx >> nodes >> edges >> tree_edges >> components;
  EXPECT_EQ(nodes, graph.at("nodes").size());
  EXPECT_EQ(edges, graph.at("links").size());
  EXPECT_EQ(tree_edges, tree);
  EXPECT_EQ(components, nodes - tree);  // the tree spans each component of the roadmap
}

}  // namespace
}  // namespace sarmap
