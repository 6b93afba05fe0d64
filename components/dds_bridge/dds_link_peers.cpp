// DdsLink::Impl's record of the peers: the robot id each participant announced and holds,
// with DDS-Security only once authenticated, and which robots are alive, joined or lost.

#include <algorithm>

#include "components/dds_bridge/dds_link_impl.hpp"
#include "components/dds_bridge/team_keys.hpp"

namespace scancrew::dds_bridge {

uint32_t DdsLink::Impl::sender(const rtps::GuidPrefix_t& participant) const {
  std::lock_guard lock(peers_mutex);
  return sender_locked(participant);
}

uint32_t DdsLink::Impl::claimed(const rtps::GuidPrefix_t& participant) const {
  std::lock_guard lock(peers_mutex);
  const auto it = claimed_by.find(participant);
  return it == claimed_by.end() ? kUnknownSender : it->second;
}

uint32_t DdsLink::Impl::sender_locked(const rtps::GuidPrefix_t& participant) const {
  const auto it = claimed_by.find(participant);
  if (it == claimed_by.end()) return kUnknownSender;
  const auto holders = claimants.find(it->second);
  return holders != claimants.end() && !holders->second.empty() &&
                 holders->second.front() == participant
             ? it->second
             : kUnknownSender;
}

void DdsLink::Impl::participant_discovered(const rtps::GuidPrefix_t& participant,
                                           const std::vector<uint8_t>& user_data) {
  if (secure()) {
    std::lock_guard lock(peers_mutex);
    if (!authorized.contains(participant)) {
      unauthenticated_claims[participant] = user_data;
      return;
    }
  }
  claim(participant, user_data);
}

void DdsLink::Impl::participant_authenticated(const rtps::GuidPrefix_t& participant, bool ok) {
  if (!ok) return;
  std::optional<std::vector<uint8_t>> pending;
  {
    std::lock_guard lock(peers_mutex);
    authorized.insert(participant);
    const auto it = unauthenticated_claims.find(participant);
    if (it != unauthenticated_claims.end()) {
      pending = std::move(it->second);
      unauthenticated_claims.erase(it);
    }
  }
  if (pending) claim(participant, *pending);
}

void DdsLink::Impl::claim(const rtps::GuidPrefix_t& participant,
                          const std::vector<uint8_t>& user_data) {
  // a bridge of this team (same partitions); another application or team is no claimant
  const auto robot_id = robot_of_user_data(user_data, config.partitions);
  if (!robot_id) return;
  if (secure()) {
    // with security, an announced id counts only from a participant authenticated with
    // that place's certificate: its GUID prefix is derived from the certificate's subject
    const auto expected =
        place_guid_prefix(config.security_team, place_name(*robot_id, config.simulator_id));
    if (!std::equal(expected.begin(), expected.end(), participant.value)) {
      if (callbacks.on_warning)
        callbacks.on_warning("a DDS participant announces robot " + std::to_string(*robot_id) +
                             " but authenticated with another place's certificate: its "
                             "samples are refused");
      return;
    }
  }
  std::string warning;
  {
    std::lock_guard lock(peers_mutex);
    // it left (participant_left) between its authentication and this claim
    if (secure() && !authorized.contains(participant)) return;
    if (const auto it = claimed_by.find(participant); it != claimed_by.end()) {
      if (it->second == *robot_id) return;  // the same claim again
      forget_claim(participant);            // it announces another id now
    }
    claimed_by[participant] = *robot_id;
    auto& queue = claimants[*robot_id];
    queue.push_back(participant);
    if (queue.front() != participant)
      warning = "a second DDS participant announces robot " + std::to_string(*robot_id) +
                " while the first is in the domain: its samples are refused until the first "
                "leaves (silent for liveliness_lease_s, or gone)";
    // a participant that announces an id another announced before is a new process of that
    // robot (restarted): the bridge starts its per-sender state again, before its samples
    const auto last = last_claimant.find(*robot_id);
    const bool new_process = last != last_claimant.end() && !(last->second == participant);
    last_claimant[*robot_id] = participant;
    if (new_process && callbacks.on_new_process) callbacks.on_new_process(*robot_id);
  }
  if (!warning.empty() && callbacks.on_warning) callbacks.on_warning(warning);
}

std::optional<std::pair<rtps::GuidPrefix_t, fdds::InstanceHandle_t>>
DdsLink::Impl::holder_presence_locked(uint32_t robot_id) {
  const auto holders = claimants.find(robot_id);
  if (holders == claimants.end() || holders->second.empty()) return std::nullopt;
  const rtps::GuidPrefix_t holder = holders->second.front();
  const auto presence = pending_presence.find(holder);
  if (presence == pending_presence.end()) return std::nullopt;
  const fdds::InstanceHandle_t writer = presence->second;
  pending_presence.erase(presence);
  return std::make_pair(holder, writer);
}

void DdsLink::Impl::participant_left(const rtps::GuidPrefix_t& participant) {
  std::optional<std::pair<rtps::GuidPrefix_t, fdds::InstanceHandle_t>> promoted;
  uint32_t robot_id = 0;
  {
    std::lock_guard lock(peers_mutex);
    authorized.erase(participant);
    unauthenticated_claims.erase(participant);
    const auto it = claimed_by.find(participant);
    if (it == claimed_by.end()) return;
    robot_id = it->second;
    forget_claim(participant);
    // the next participant that announced the id (a restarted robot) now holds it; its
    // presence, refused while it did not, counts now
    promoted = holder_presence_locked(robot_id);
  }
  if (promoted) peer_seen(promoted->first, promoted->second, robot_id);
}

void DdsLink::Impl::forget_claim(const rtps::GuidPrefix_t& participant) {
  const auto it = claimed_by.find(participant);
  if (it == claimed_by.end()) return;
  auto& queue = claimants[it->second];
  queue.erase(std::remove(queue.begin(), queue.end(), participant), queue.end());
  if (queue.empty()) claimants.erase(it->second);
  pending_presence.erase(participant);
  claimed_by.erase(it);
}

void DdsLink::Impl::presence(const rtps::GuidPrefix_t& participant,
                             const fdds::InstanceHandle_t& writer, uint32_t robot_id) {
  {
    std::lock_guard lock(peers_mutex);
    if (sender_locked(participant) != robot_id) {
      const auto it = claimed_by.find(participant);
      if (it != claimed_by.end() && it->second == robot_id) pending_presence[participant] = writer;
      return;
    }
  }
  peer_seen(participant, writer, robot_id);
}

void DdsLink::Impl::peer_seen(const rtps::GuidPrefix_t& participant,
                              const fdds::InstanceHandle_t& writer, uint32_t robot_id) {
  if (robot_id == config.robot_id) return;  // our own presence
  bool joined = false, back = false, restarted = false;
  {
    std::lock_guard lock(peers_mutex);
    // a new holder's presence replaces the old one's: the old writer's late events (its
    // liveliness, its leaving) no longer speak for the robot
    std::erase_if(robot_of_writer,
                  [&](const auto& kv) { return kv.second == robot_id && !(kv.first == writer); });
    robot_of_writer[writer] = robot_id;
    const auto seen = seen_holder.find(robot_id);
    restarted = seen != seen_holder.end() && !(seen->second == participant);
    seen_holder[robot_id] = participant;
    joined = alive.insert(robot_id).second;
    back = lost.erase(robot_id) > 0;
    if (joined && callbacks.on_peer)
      callbacks.on_peer(robot_id, true,
                        restarted ? "back (a new process: it restarted)"
                        : back    ? "back"
                                  : "joined");
  }
}

void DdsLink::Impl::peer_gone(const fdds::InstanceHandle_t& writer, std::string_view why) {
  std::lock_guard lock(peers_mutex);
  auto it = robot_of_writer.find(writer);
  if (it == robot_of_writer.end()) return;  // never announced itself (or our own)
  const uint32_t robot_id = it->second;
  if (alive.erase(robot_id) == 0) return;  // already reported
  lost.insert(robot_id);
  if (callbacks.on_peer) callbacks.on_peer(robot_id, false, why);
}

void DdsLink::Impl::peer_alive_again(const fdds::InstanceHandle_t& writer) {
  std::lock_guard lock(peers_mutex);
  auto it = robot_of_writer.find(writer);
  if (it == robot_of_writer.end()) return;
  const uint32_t robot_id = it->second;
  if (!alive.insert(robot_id).second) return;
  lost.erase(robot_id);
  if (callbacks.on_peer) callbacks.on_peer(robot_id, true, "back");
}

}  // namespace scancrew::dds_bridge
