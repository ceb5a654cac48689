// `--disable-rule NAME` (repeatable): turns a rule of the chain that
// corrects the network's labels off by name (engine/semantic/rules/
// rule_chain.hpp), for `sarmap run` and `sarmap classify` alike.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "engine/semantic/rules/rule_chain.hpp"

namespace sarmap::cli {

inline CLI::Option* add_disable_rule_option(CLI::App* cmd, std::vector<std::string>& disabled) {
  return cmd
      ->add_option("--disable-rule", disabled,
                   "Turn off a rule that corrects the network's labels (repeat for several; all are on by "
                   "default, in this order): ramp_veto (inclined-ramp labels on surfaces steeper than 60 "
                   "degrees become wall or other), wall_bands (other labels on a patch of other and wall 0.8 m "
                   "or longer, longer than a box, become wall), ramp_sides (wall or other labels with ramp deck "
                   "3-100 cm above them within 15 cm, seen in this scan or an earlier one, become inclined "
                   "ramp), wall_feet (wall labels at most 5 mm above the terrain around them become terrain)")
      ->type_name("NAME")
      ->take_all()
      ->check(CLI::IsMember(std::vector<std::string>(kRuleNames.begin(), kRuleNames.end())));
}

}  // namespace sarmap::cli
