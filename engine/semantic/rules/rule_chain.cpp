#include "engine/semantic/rules/rule_chain.hpp"

#include <algorithm>
#include <numeric>

#include "engine/core/error.hpp"

namespace sarmap {

namespace {

class SteepSurfaceVeto final : public LabelRule {
 public:
  explicit SteepSurfaceVeto(const SteepSurfaceVetoSettings& settings) : settings_(settings) { validate(settings); }
  std::string_view name() const override { return kRuleNames[0]; }
  std::size_t apply(PointBuffer& points) override { return reapply(points); }
  std::size_t reapply(PointBuffer& points) const override { return veto_steep_inclined_ramps(points, settings_); }

 private:
  SteepSurfaceVetoSettings settings_;
};

class WallBands final : public LabelRule {
 public:
  explicit WallBands(const WallBandSettings& settings) : settings_(settings) { validate(settings); }
  std::string_view name() const override { return kRuleNames[1]; }
  std::size_t apply(PointBuffer& points) override { return reapply(points); }
  std::size_t reapply(PointBuffer& points) const override { return label_wall_bands(points, settings_); }

 private:
  WallBandSettings settings_;
};

class RampSides final : public LabelRule {
 public:
  explicit RampSides(const RampSideSettings& settings) : decks_(settings) {}
  std::string_view name() const override { return kRuleNames[2]; }
  std::size_t apply(PointBuffer& points) override { return decks_.label_side_faces(points); }
  std::size_t reapply(PointBuffer& points) const override { return decks_.label_under_known_decks(points); }
  void save_state(StateWriter& out) const override { decks_.save_state(out); }
  void load_state(StateReader& in) override { decks_.load_state(in); }

 private:
  RampDeckMemory decks_;  // the ramp decks of every scan so far
};

class WallFeet final : public LabelRule {
 public:
  explicit WallFeet(const WallFootSettings& settings) : settings_(settings) { validate(settings); }
  std::string_view name() const override { return kRuleNames[3]; }
  std::size_t apply(PointBuffer& points) override { return reapply(points); }
  std::size_t reapply(PointBuffer& points) const override { return label_wall_feet(points, settings_); }

 private:
  WallFootSettings settings_;
};

std::size_t rule_index(std::string_view name) {
  const auto it = std::find(kRuleNames.begin(), kRuleNames.end(), name);
  if (it == kRuleNames.end()) {
    throw Error(ErrorCode::InvalidArgument,
                "unknown rule \"" + std::string(name) + "\": the rules are " + rule_name_list());
  }
  return static_cast<std::size_t>(it - kRuleNames.begin());
}

}  // namespace

bool& rule_enabled(RuleChainSettings& settings, std::string_view name) {
  bool* flags[kRuleCount] = {&settings.ramp_veto.enabled, &settings.wall_bands.enabled,
                             &settings.ramp_sides.enabled, &settings.wall_feet.enabled};
  return *flags[rule_index(name)];
}

bool rule_enabled(const RuleChainSettings& settings, std::string_view name) {
  return rule_enabled(const_cast<RuleChainSettings&>(settings), name);
}

std::string rule_name_list() {
  std::string list;
  for (std::string_view name : kRuleNames) list += (list.empty() ? "" : ", ") + std::string(name);
  return list;
}

std::size_t RuleChanges::of(std::string_view name) const { return changed[rule_index(name)]; }

std::size_t RuleChanges::total() const { return std::accumulate(changed.begin(), changed.end(), std::size_t{0}); }

RuleChanges& RuleChanges::operator+=(const RuleChanges& other) {
  for (std::size_t r = 0; r < kRuleCount; ++r) changed[r] += other.changed[r];
  return *this;
}

RuleChain::RuleChain(const RuleChainSettings& settings) : settings_(settings) {
  rules_.push_back(std::make_unique<SteepSurfaceVeto>(settings.ramp_veto));
  rules_.push_back(std::make_unique<WallBands>(settings.wall_bands));
  rules_.push_back(std::make_unique<RampSides>(settings.ramp_sides));
  rules_.push_back(std::make_unique<WallFeet>(settings.wall_feet));
}

RuleChain::RuleChain(RuleChain&&) noexcept = default;
RuleChain& RuleChain::operator=(RuleChain&&) noexcept = default;
RuleChain::~RuleChain() = default;

RuleChanges RuleChain::apply(PointBuffer& points) {
  RuleChanges changes;
  for (std::size_t r = 0; r < kRuleCount; ++r) changes.changed[r] = rules_[r]->apply(points);
  return changes;
}

RuleChanges RuleChain::reapply(PointBuffer& points) const {
  RuleChanges changes;
  for (std::size_t r = 0; r < kRuleCount; ++r) changes.changed[r] = rules_[r]->reapply(points);
  return changes;
}

void RuleChain::save_state(StateWriter& out) const {
  for (const auto& rule : rules_) rule->save_state(out);
}

void RuleChain::load_state(StateReader& in) {
  for (const auto& rule : rules_) rule->load_state(in);
}

}  // namespace sarmap
