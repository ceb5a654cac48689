// One rule of the chain that corrects the network's labels (rule_chain.hpp):
// a name (what `--disable-rule` and the profile's counters call it) and a
// pass over labelled points that returns how many it changed.
#pragma once

#include <cstddef>
#include <string_view>

#include "engine/core/point_buffer.hpp"
#include "engine/core/state_stream.hpp"

namespace sarmap {

class LabelRule {
 public:
  virtual ~LabelRule() = default;
  virtual std::string_view name() const = 0;
  // Relabels `points` (a new scan, or a cloud on its own), remembering what
  // later calls need (the ramp decks seen so far). Returns the points changed.
  virtual std::size_t apply(PointBuffer& points) = 0;
  // The same on points whose scans were already applied (the kept points,
  // relabelled from the accumulated map): remembers nothing new.
  virtual std::size_t reapply(PointBuffer& points) const = 0;
  // What it remembers, for a checkpoint; nothing for a rule that remembers nothing.
  virtual void save_state(StateWriter& out) const { (void)out; }
  virtual void load_state(StateReader& in) { (void)in; }
};

}  // namespace sarmap
