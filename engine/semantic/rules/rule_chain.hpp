// The rules that correct the network's labels, as one ordered chain: every
// DGCNN label in sarmap (`sarmap run` per scan or on the accumulated map,
// `sarmap classify`, the library's classify stage, the kept points
// relabelled from the map) goes through this chain after the network, so a
// rule is written once and turned off by name (`--disable-rule NAME`).
//
// The order, and why (each rule's own header says what it patches):
//   ramp_veto   inclined-ramp labels on steep surfaces become wall / other;
//   wall_bands  other labels on patches longer than a box become wall —
//               before ramp_sides, so a ramp side the network called other,
//               once wall, is then found under its deck;
//   ramp_sides  wall / other labels under a ramp deck (this scan's or an
//               earlier one's) become inclined ramp;
//   wall_feet   wall labels at the floor's height become terrain — last, so
//               a ramp side's lowest points, once ramp, stay ramp.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/point_buffer.hpp"
#include "engine/core/state_stream.hpp"
#include "engine/semantic/rules/label_rule.hpp"
#include "engine/semantic/rules/ramp_side_faces.hpp"
#include "engine/semantic/rules/steep_surface_veto.hpp"
#include "engine/semantic/rules/wall_bands.hpp"
#include "engine/semantic/rules/wall_feet.hpp"

namespace sarmap {

inline constexpr std::size_t kRuleCount = 4;
// The chain's rules in their order.
inline constexpr std::array<std::string_view, kRuleCount> kRuleNames = {"ramp_veto", "wall_bands", "ramp_sides",
                                                                        "wall_feet"};

struct RuleChainSettings {
  SteepSurfaceVetoSettings ramp_veto;
  WallBandSettings wall_bands;
  RampSideSettings ramp_sides;
  WallFootSettings wall_feet;
};

// Rule `name`'s enabled flag in `settings`. Throws sarmap::Error
// (InvalidArgument) naming the rules for any other name.
bool& rule_enabled(RuleChainSettings& settings, std::string_view name);
bool rule_enabled(const RuleChainSettings& settings, std::string_view name);

// "ramp_veto, wall_bands, ramp_sides, wall_feet": for messages and --help.
std::string rule_name_list();

// Points each rule changed, in the chain's order (a disabled rule: 0).
struct RuleChanges {
  std::array<std::size_t, kRuleCount> changed{};

  // Throws sarmap::Error (InvalidArgument) for a name that is no rule's.
  std::size_t of(std::string_view name) const;
  std::size_t total() const;
  RuleChanges& operator+=(const RuleChanges& other);
};

class RuleChain {
 public:
  // Every rule's settings are checked, enabled or not (a config file is
  // wrong whichever rules run). Throws sarmap::Error (InvalidArgument)
  // naming the rule and the setting.
  explicit RuleChain(const RuleChainSettings& settings);
  RuleChain(RuleChain&&) noexcept;
  RuleChain& operator=(RuleChain&&) noexcept;
  ~RuleChain();

  // Runs the enabled rules in order on a new scan (or a cloud on its own),
  // each remembering what later scans need. Points without labels: nothing.
  // Throws sarmap::Error (InvalidArgument) for a non-finite point.
  RuleChanges apply(PointBuffer& points);
  // The same on points already applied once (LabelRule::reapply).
  RuleChanges reapply(PointBuffer& points) const;

  const RuleChainSettings& settings() const { return settings_; }

  // What the rules remember (the ramp decks), for a checkpoint.
  void save_state(StateWriter& out) const;
  // Throws sarmap::Error (Parse) naming the offset; unchanged then.
  void load_state(StateReader& in);

 private:
  RuleChainSettings settings_;
  std::vector<std::unique_ptr<LabelRule>> rules_;  // kRuleNames' order, disabled ones included
};

}  // namespace sarmap
