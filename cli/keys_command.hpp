#pragma once

// `scancrew keys`: a team's keys for DDS-Security (docs/security.md).
//   scancrew keys init DIR [--team NAME]     the team's authority and governance
//   scancrew keys add DIR LAUNCH --robot K | --station | --sim
//                                            a place's identity and permissions: it may
//                                            publish what its bridges in LAUNCH export and
//                                            read what they import (and the presence and
//                                            lockstep topics every bridge uses)

#include <cstdint>
#include <string>

#include "components/dds_bridge/team_keys.hpp"
#include "core/result.hpp"

namespace scancrew::cli {

struct KeysOptions {
  std::string dir;
  std::string team = "team";
  std::string launch;
  int64_t robot = -1;  // --robot K
  bool station = false, sim = false;
  std::vector<std::string> overrides;  // --set name.key=value, as the launch is run with
};

int run_keys_init(const KeysOptions& options);
int run_keys_add(const KeysOptions& options);

// The grant of a place from a launch file's dds_bridge components: each bridge (per robot,
// or the station's or the simulator's) whose place is `place` adds its exports, expanded for
// its robot and prefixed as on the wire, to publish, and its imports to subscribe; with the
// launch's `--set` overrides applied first.
Result<dds_bridge::PlaceGrant, std::string> grant_from_launch(
    const std::string& launch_text, const std::string& label, const std::string& place,
    const std::vector<std::string>& overrides = {});

}  // namespace scancrew::cli
