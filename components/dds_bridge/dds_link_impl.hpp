#pragma once

// DdsLink::Impl: the Fast DDS entities of a link and its record of the peers (which
// participant holds which robot id, who is alive). Private to the dds_bridge component:
// dds_link.cpp makes the entities, dds_link_peers.cpp keeps the record.

#include <atomic>
#include <fastdds/dds/common/InstanceHandle.hpp>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <shared_mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "components/dds_bridge/dds_link.hpp"
#include "components/dds_bridge/idl/envelopePubSubTypes.h"

namespace scancrew::dds_bridge {

namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

struct DdsLink::Impl {
  DdsLinkConfig config;
  Callbacks callbacks;
  fdds::DomainParticipant* participant = nullptr;
  fdds::Publisher* publisher = nullptr;
  fdds::Subscriber* subscriber = nullptr;
  fdds::TypeSupport type{new scancrew::dds::EnvelopePubSubType()};
  std::map<std::string, fdds::Topic*> topics;
  std::vector<fdds::DataWriter*> writers;
  std::vector<fdds::DataReader*> readers;
  std::vector<std::unique_ptr<fdds::DataReaderListener>> listeners;
  std::unique_ptr<fdds::DomainParticipantListener> participant_listener;
  fdds::DataWriter* presence_writer = nullptr;
  fdds::DataReader* presence_reader = nullptr;

  // close() waits for callbacks in flight and stops new ones
  std::shared_mutex callback_mutex;
  std::atomic<bool> closing{false};

  // presence: which robot each peer's presence writer belongs to, and who is alive; the robot
  // id each participant announced at discovery (the first participant to announce an id
  // keeps it while it is in the domain; its participant lease is liveliness_lease_s)
  mutable std::mutex peers_mutex;
  std::map<rtps::GuidPrefix_t, uint32_t> claimed_by;  // the id each participant announced
  // per id, the participants that announced it, in order: the first holds it
  std::map<uint32_t, std::vector<rtps::GuidPrefix_t>> claimants;
  std::map<rtps::GuidPrefix_t, fdds::InstanceHandle_t> pending_presence;
  std::map<fdds::InstanceHandle_t, uint32_t> robot_of_writer;
  // per id, the participant whose presence counted last (another one now: a new process)
  std::map<uint32_t, rtps::GuidPrefix_t> seen_holder;
  // per id, the participant that announced it last (another one: a new process)
  std::map<uint32_t, rtps::GuidPrefix_t> last_claimant;
  std::set<uint32_t> alive;
  std::set<uint32_t> lost;
  // security: the participants authenticated so far, and the claims of those not (yet)
  std::set<rtps::GuidPrefix_t> authorized;
  std::map<rtps::GuidPrefix_t, std::vector<uint8_t>> unauthenticated_claims;

  // Runs fn unless the link is closing; fn may then use callbacks.
  template <class Fn>
  void guarded(Fn&& fn) {
    std::shared_lock lock(callback_mutex);
    if (!closing.load(std::memory_order_acquire)) fn();
  }

  Result<fdds::Topic*, std::string> topic(const std::string& name);

  // The robot id the participant announced, kUnknownSender if none or if it does not hold
  // that id (another participant announced it first and is still in the domain).
  uint32_t sender(const rtps::GuidPrefix_t& participant) const;
  // The robot id the participant announced, held or not; kUnknownSender if none.
  uint32_t claimed(const rtps::GuidPrefix_t& participant) const;
  uint32_t sender_locked(const rtps::GuidPrefix_t& participant) const;

  // With security, a participant's claim counts once it is authenticated: discovery reports
  // it before the handshake, and an unauthenticated participant could otherwise hold a
  // robot's id first.
  void participant_discovered(const rtps::GuidPrefix_t& participant,
                              const std::vector<uint8_t>& user_data);
  // A failed handshake (ok false) may be retried by Fast DDS and succeed later: the pending
  // claim stays until the participant leaves.
  void participant_authenticated(const rtps::GuidPrefix_t& participant, bool ok);

  bool secure() const { return !config.security_properties.empty(); }

  void claim(const rtps::GuidPrefix_t& participant, const std::vector<uint8_t>& user_data);
  // The presence of an id's new holder, kept while it did not hold the id; taken (it counts
  // now). peers_mutex held.
  std::optional<std::pair<rtps::GuidPrefix_t, fdds::InstanceHandle_t>> holder_presence_locked(
      uint32_t robot_id);
  void participant_left(const rtps::GuidPrefix_t& participant);
  // Drops a participant's claim (peers_mutex held).
  void forget_claim(const rtps::GuidPrefix_t& participant);
  // A presence sample: counts from the participant that holds the robot id; from one that
  // announced it but does not hold it (yet), it is kept for when it does.
  void presence(const rtps::GuidPrefix_t& participant, const fdds::InstanceHandle_t& writer,
                uint32_t robot_id);
  void peer_seen(const rtps::GuidPrefix_t& participant, const fdds::InstanceHandle_t& writer,
                 uint32_t robot_id);
  void peer_gone(const fdds::InstanceHandle_t& writer, std::string_view why);
  void peer_alive_again(const fdds::InstanceHandle_t& writer);
};

}  // namespace scancrew::dds_bridge
