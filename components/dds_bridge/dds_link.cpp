#include "components/dds_bridge/dds_link.hpp"

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>

#include <algorithm>
#include <cmath>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "components/dds_bridge/dds_link_impl.hpp"

namespace scancrew::dds_bridge {

using eprosima::fastrtps::Duration_t;
using eprosima::fastrtps::types::ReturnCode_t;

namespace {

// The shortest participant lease (s) the bridge sets, whatever liveliness_lease_s.
constexpr double kMinParticipantLeaseS = 1.0;

Duration_t duration(double seconds) {
  const double whole = std::floor(seconds);
  return {static_cast<int32_t>(whole),
          static_cast<uint32_t>(std::llround((seconds - whole) * 1e9))};
}

void to_dds(WireEnvelope& from, scancrew::dds::Envelope& to) {
  to.format_version(from.format_version);
  to.robot_id(from.robot_id);
  to.seq(from.seq);
  to.stamp_ns(from.stamp_ns);
  to.type_name(from.type_name);
  to.payload(std::move(from.payload));
}

WireEnvelope from_dds(scancrew::dds::Envelope&& from) {
  WireEnvelope to;
  to.format_version = from.format_version();
  to.robot_id = from.robot_id();
  to.seq = from.seq();
  to.stamp_ns = from.stamp_ns();
  to.type_name = std::move(from.type_name());
  to.payload = std::move(from.payload());
  return to;
}

constexpr std::string_view kNotGranted =
    ": the place's permissions do not grant it (scancrew keys add, from this launch file, "
    "writes permissions for what its bridges export and import)";

std::string incompatible(const std::string& topic, fdds::QosPolicyId_t policy) {
  return "DDS topic '" + topic + "': a peer's QoS is incompatible with ours (policy id " +
         std::to_string(static_cast<int>(policy)) +
         "; reliability, durability or liveliness differ between the bridges' configurations)";
}

}  // namespace

Result<fdds::Topic*, std::string> DdsLink::Impl::topic(const std::string& name) {
  if (auto it = topics.find(name); it != topics.end()) return it->second;
  fdds::Topic* t = participant->create_topic(name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  if (t == nullptr) return make_unexpected("cannot create the DDS topic '" + name + "'");
  topics.emplace(name, t);
  return t;
}

namespace {

// Discovery: binds each bridge participant's GUID to the robot id it announces.
class ParticipantListener final : public fdds::DomainParticipantListener {
 public:
  explicit ParticipantListener(DdsLink::Impl* impl) : impl_(impl) {}

  void on_participant_discovery(fdds::DomainParticipant* /*participant*/,
                                rtps::ParticipantDiscoveryInfo&& info) override {
    using Status = rtps::ParticipantDiscoveryInfo::DISCOVERY_STATUS;
    const rtps::GuidPrefix_t& prefix = info.info.m_guid.guidPrefix;
    impl_->guarded([&] {
      if (info.status == Status::DISCOVERED_PARTICIPANT ||
          info.status == Status::CHANGED_QOS_PARTICIPANT)
        impl_->participant_discovered(prefix, info.info.m_userData.data_vec());
      else
        impl_->participant_left(prefix);
    });
  }

  void onParticipantAuthentication(fdds::DomainParticipant* /*participant*/,
                                   rtps::ParticipantAuthenticationInfo&& info) override {
    using Status = rtps::ParticipantAuthenticationInfo::AUTHENTICATION_STATUS;
    impl_->guarded([&] {
      impl_->participant_authenticated(info.guid.guidPrefix,
                                       info.status == Status::AUTHORIZED_PARTICIPANT);
    });
  }

 private:
  DdsLink::Impl* impl_;
};

class DataListener final : public fdds::DataReaderListener {
 public:
  DataListener(DdsLink::Impl* impl, size_t index, std::string topic)
      : impl_(impl), index_(index), topic_(std::move(topic)) {}

  void on_data_available(fdds::DataReader* reader) override {
    impl_->guarded([&] {
      scancrew::dds::Envelope envelope;
      fdds::SampleInfo info;
      while (reader->take_next_sample(&envelope, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        const size_t bytes = scancrew::dds::Envelope::getCdrSerializedSize(envelope) + 4;
        WireEnvelope wire = from_dds(std::move(envelope));
        wire.sender_robot_id = impl_->sender(info.sample_identity.writer_guid().guidPrefix);
        wire.claimed_robot_id = impl_->claimed(info.sample_identity.writer_guid().guidPrefix);
        if (impl_->callbacks.on_sample) impl_->callbacks.on_sample(index_, std::move(wire), bytes);
        envelope = scancrew::dds::Envelope{};
      }
    });
  }
  void on_requested_incompatible_qos(fdds::DataReader* /*reader*/,
                                     const fdds::RequestedIncompatibleQosStatus& status) override {
    impl_->guarded([&] {
      if (impl_->callbacks.on_warning)
        impl_->callbacks.on_warning(incompatible(topic_, status.last_policy_id));
    });
  }

 private:
  DdsLink::Impl* impl_;
  size_t index_;
  std::string topic_;
};

class PresenceListener final : public fdds::DataReaderListener {
 public:
  explicit PresenceListener(DdsLink::Impl* impl) : impl_(impl) {}

  void on_data_available(fdds::DataReader* reader) override {
    impl_->guarded([&] {
      scancrew::dds::Envelope envelope;
      fdds::SampleInfo info;
      // a presence counts from the participant that announced the robot only (a forged one
      // could report a teammate lost or alive)
      while (reader->take_next_sample(&envelope, &info) == ReturnCode_t::RETCODE_OK)
        if (info.valid_data && envelope.type_name() == kPresenceType)
          impl_->presence(info.sample_identity.writer_guid().guidPrefix, info.publication_handle,
                          envelope.robot_id());
    });
  }
  void on_liveliness_changed(fdds::DataReader* /*reader*/,
                             const fdds::LivelinessChangedStatus& status) override {
    impl_->guarded([&] {
      if (status.not_alive_count_change > 0)
        impl_->peer_gone(status.last_publication_handle, "liveliness lost");
      else if (status.alive_count_change > 0)
        impl_->peer_alive_again(status.last_publication_handle);
    });
  }
  void on_subscription_matched(fdds::DataReader* /*reader*/,
                               const fdds::SubscriptionMatchedStatus& status) override {
    impl_->guarded([&] {
      if (status.current_count_change < 0)
        impl_->peer_gone(status.last_publication_handle, "left the domain");
    });
  }
  void on_requested_incompatible_qos(fdds::DataReader* /*reader*/,
                                     const fdds::RequestedIncompatibleQosStatus& status) override {
    impl_->guarded([&] {
      if (impl_->callbacks.on_warning)
        impl_->callbacks.on_warning(
            incompatible(std::string(kPresenceTopic), status.last_policy_id));
    });
  }

 private:
  DdsLink::Impl* impl_;
};

fdds::DataWriterQos writer_qos(fdds::Publisher* publisher, const DdsTopicQos& qos) {
  fdds::DataWriterQos w = publisher->get_default_datawriter_qos();
  w.reliability().kind = qos.reliability == Reliability::kReliable
                             ? fdds::RELIABLE_RELIABILITY_QOS
                             : fdds::BEST_EFFORT_RELIABILITY_QOS;
  w.durability().kind =
      qos.transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
  w.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  w.history().depth = static_cast<int32_t>(qos.depth);
  // a reader that lost a sample or a fragment asks for it when a heartbeat tells it what was
  // written: every 0.1 s here. Fast DDS's default period, 3 s, stalled a team stepping in
  // lockstep on a link losing 10 % of its datagrams (each step waits for the samples written
  // before it; docs/reliability.md)
  w.reliable_writer_qos().times.heartbeatPeriod = duration(0.1);
  // large samples (patches) are fragmented and sent by Fast DDS's own thread: a write on the
  // executor thread only queues (the synchronous mode sent a whole patch from it)
  w.publish_mode().kind = fdds::ASYNCHRONOUS_PUBLISH_MODE;
  w.data_sharing().off();
  return w;
}

fdds::DataReaderQos reader_qos(fdds::Subscriber* subscriber, const DdsTopicQos& qos) {
  fdds::DataReaderQos r = subscriber->get_default_datareader_qos();
  r.reliability().kind = qos.reliability == Reliability::kReliable
                             ? fdds::RELIABLE_RELIABILITY_QOS
                             : fdds::BEST_EFFORT_RELIABILITY_QOS;
  r.durability().kind =
      qos.transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
  r.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  r.history().depth = static_cast<int32_t>(qos.depth);
  r.data_sharing().off();
  return r;
}

void add_udp(fdds::DomainParticipantQos& pqos, bool loopback_only, uint32_t peers_range) {
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->maxInitialPeersRange = peers_range;
  if (loopback_only) udp->interfaceWhiteList.emplace_back("127.0.0.1");
  pqos.transport().user_transports.push_back(udp);
}

void add_peer(fdds::DomainParticipantQos& pqos, const std::string& address) {
  rtps::Locator_t locator;
  locator.kind = LOCATOR_KIND_UDPv4;
  locator.port = 0;  // the well-known ports of the first participants of the domain
  rtps::IPLocator::setIPv4(locator, address);
  pqos.wire_protocol().builtin.initialPeersList.push_back(locator);
}

// Sets the participant's discovery lease from the liveliness lease (at least 1 s).
void set_participant_lease(fdds::DomainParticipantQos& pqos, double liveliness_lease_s) {
  // a dead process is told by its participant's discovery lease, set to the liveliness lease:
  // Fast DDS 2.9's AUTOMATIC liveliness cannot tell it while another participant is alive (a
  // reader asserting one remote writer's liveliness asserts every automatic writer it tracks,
  // whoever's: LivelinessManager::assert_liveliness), so a killed robot among live ones was
  // reported lost only at the default 20 s participant lease. Announced 5 times per lease: 5
  // in a row lost (1e-5 at 10 % loss) reports a live robot lost. At least 1 s: a process
  // stalled for less (a loaded machine, a sanitizer build) is not taken for dead
  const double participant_lease_s = std::max(liveliness_lease_s, kMinParticipantLeaseS);
  pqos.wire_protocol().builtin.discovery_config.leaseDuration = duration(participant_lease_s);
  pqos.wire_protocol().builtin.discovery_config.leaseDuration_announcementperiod =
      duration(participant_lease_s / 5);
}

// Adds the configured transport and the initial peers to the participant's QoS.
Result<void, std::string> add_transports(fdds::DomainParticipantQos& pqos,
                                         const DdsLinkConfig& config) {
  if (config.transport != Transport::kBuiltin) pqos.transport().use_builtin_transports = false;
  switch (config.transport) {
    case Transport::kLoopback:
      add_udp(pqos, true, config.initial_peers_range);
      add_peer(pqos, "127.0.0.1");
      break;
    case Transport::kShm: {
      auto shm = std::make_shared<eprosima::fastdds::rtps::SharedMemTransportDescriptor>();
      shm->maxInitialPeersRange = config.initial_peers_range;
      pqos.transport().user_transports.push_back(shm);
      add_udp(pqos, true, config.initial_peers_range);
      add_peer(pqos, "127.0.0.1");
      break;
    }
    case Transport::kUdp:
      add_udp(pqos, false, config.initial_peers_range);
      break;
    case Transport::kBuiltin:
      break;
  }
  for (const std::string& peer : config.initial_peers) {
    if (!rtps::IPLocator::isIPv4(peer))
      return make_unexpected("'" + peer + "' is not an IPv4 address");
    add_peer(pqos, peer);
  }
  return {};
}

// Registers the envelope type and creates the publisher and subscriber (in the partitions).
Result<void, std::string> create_pub_sub(DdsLink::Impl& m, const DdsLinkConfig& config) {
  if (m.type.register_type(m.participant) != ReturnCode_t::RETCODE_OK)
    return make_unexpected("cannot register the DDS type " + m.type.get_type_name());

  fdds::PublisherQos pub_qos = fdds::PUBLISHER_QOS_DEFAULT;
  fdds::SubscriberQos sub_qos = fdds::SUBSCRIBER_QOS_DEFAULT;
  for (const std::string& p : config.partitions) {
    pub_qos.partition().push_back(p.c_str());
    sub_qos.partition().push_back(p.c_str());
  }
  m.publisher = m.participant->create_publisher(pub_qos);
  m.subscriber = m.participant->create_subscriber(sub_qos);
  if (m.publisher == nullptr || m.subscriber == nullptr)
    return make_unexpected("cannot create the DDS publisher or subscriber");
  return {};
}

// Creates the presence topic's writer and reader.
Result<void, std::string> create_presence(DdsLink::Impl& m, const DdsLinkConfig& config) {
  // presence: reliable, transient-local, AUTOMATIC liveliness with the configured lease
  auto topic = m.topic(std::string(kPresenceTopic));
  if (!topic) return make_unexpected(topic.error());
  const DdsTopicQos presence{
      .reliability = Reliability::kReliable, .depth = 1, .transient_local = true};
  fdds::DataWriterQos wq = writer_qos(m.publisher, presence);
  wq.liveliness().kind = fdds::AUTOMATIC_LIVELINESS_QOS;
  wq.liveliness().lease_duration = duration(config.liveliness_lease_s);
  wq.liveliness().announcement_period = duration(config.liveliness_lease_s / 3);
  m.presence_writer = m.publisher->create_datawriter(*topic, wq);
  fdds::DataReaderQos rq = reader_qos(m.subscriber, presence);
  rq.liveliness().kind = fdds::AUTOMATIC_LIVELINESS_QOS;
  rq.liveliness().lease_duration = duration(config.liveliness_lease_s);
  auto listener = std::make_unique<PresenceListener>(&m);
  m.presence_reader = m.subscriber->create_datareader(*topic, rq, listener.get());
  m.listeners.push_back(std::move(listener));
  if (m.presence_writer == nullptr || m.presence_reader == nullptr)
    return make_unexpected("cannot create the DDS presence endpoints");
  return {};
}

}  // namespace

DdsLink::DdsLink(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

DdsLink::~DdsLink() {
  close();
}

Result<std::unique_ptr<DdsLink>, std::string> DdsLink::create(const DdsLinkConfig& config,
                                                              Callbacks callbacks) {
  auto impl = std::make_unique<Impl>();
  impl->config = config;
  impl->callbacks = std::move(callbacks);

  fdds::DomainParticipantQos pqos;
  pqos.name(config.participant_name.c_str());
  pqos.user_data().data_vec(participant_user_data(config.robot_id, config.partitions));
  for (const auto& [name, value] : config.security_properties)
    pqos.properties().properties().emplace_back(name, value);
  set_participant_lease(pqos, config.liveliness_lease_s);
  if (auto transports = add_transports(pqos, config); !transports)
    return make_unexpected(transports.error());

  if (!config.intraprocess) {
    eprosima::fastrtps::LibrarySettingsAttributes library;
    library.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_OFF;
    eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(library);
  }
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  impl->participant_listener = std::make_unique<ParticipantListener>(impl.get());
  // discovery callbacks only: the readers' own listeners take their data
  impl->participant = factory->create_participant(
      config.domain_id, pqos, impl->participant_listener.get(), fdds::StatusMask::none());
  if (impl->participant == nullptr)
    return make_unexpected(
        "cannot create a DDS participant on domain " + std::to_string(config.domain_id) +
        " (transport " + std::string(name_of(kTransportNames, config.transport)) + ")" +
        (config.security_properties.empty()
             ? std::string()
             : std::string("; with DDS-Security: a certificate, key, governance or permissions "
                           "file that does not verify against the team's ca.pem (Fast DDS's "
                           "log above says which)")));
  std::unique_ptr<DdsLink> link(new DdsLink(std::move(impl)));
  Impl& m = *link->impl_;
  if (auto entities = create_pub_sub(m, config); !entities)
    return make_unexpected(entities.error());
  if (auto presence = create_presence(m, config); !presence)
    return make_unexpected(presence.error());
  return link;
}

Result<size_t, std::string> DdsLink::add_writer(const std::string& dds_topic,
                                                const DdsTopicQos& qos) {
  Impl& m = *impl_;
  auto topic = m.topic(dds_topic);
  if (!topic) return make_unexpected(topic.error());
  fdds::DataWriter* w = m.publisher->create_datawriter(*topic, writer_qos(m.publisher, qos));
  if (w == nullptr)
    return make_unexpected("cannot create a DDS writer on '" + dds_topic + "'" +
                           (m.secure() ? std::string(kNotGranted) : std::string()));
  m.writers.push_back(w);
  return m.writers.size() - 1;
}

Result<size_t, std::string> DdsLink::add_reader(const std::string& dds_topic,
                                                const DdsTopicQos& qos) {
  Impl& m = *impl_;
  auto topic = m.topic(dds_topic);
  if (!topic) return make_unexpected(topic.error());
  auto listener = std::make_unique<DataListener>(&m, m.readers.size(), dds_topic);
  fdds::DataReader* r =
      m.subscriber->create_datareader(*topic, reader_qos(m.subscriber, qos), listener.get());
  if (r == nullptr)
    return make_unexpected("cannot create a DDS reader on '" + dds_topic + "'" +
                           (m.secure() ? std::string(kNotGranted) : std::string()));
  m.listeners.push_back(std::move(listener));
  m.readers.push_back(r);
  return m.readers.size() - 1;
}

Result<void, std::string> DdsLink::announce() {
  scancrew::dds::Envelope presence;
  presence.format_version(0);
  presence.robot_id(impl_->config.robot_id);
  presence.type_name(std::string(kPresenceType));
  if (!impl_->presence_writer->write(&presence))
    return make_unexpected("cannot write the DDS presence sample");
  return {};
}

Result<size_t, std::string> DdsLink::write(size_t writer, WireEnvelope& envelope) {
  if (writer >= impl_->writers.size())
    return make_unexpected("no DDS writer " + std::to_string(writer));
  scancrew::dds::Envelope dds_envelope;
  to_dds(envelope, dds_envelope);
  const size_t bytes = scancrew::dds::Envelope::getCdrSerializedSize(dds_envelope) + 4;
  const bool ok = impl_->writers[writer]->write(&dds_envelope);
  envelope.payload = std::move(dds_envelope.payload());  // handed back for reuse
  if (!ok) return make_unexpected("the DDS write failed");
  return bytes;
}

size_t DdsLink::writer_matches(size_t writer) const {
  fdds::PublicationMatchedStatus status;
  if (writer >= impl_->writers.size() ||
      impl_->writers[writer]->get_publication_matched_status(status) != ReturnCode_t::RETCODE_OK)
    return 0;
  return static_cast<size_t>(status.current_count);
}

size_t DdsLink::reader_matches(size_t reader) const {
  fdds::SubscriptionMatchedStatus status;
  if (reader >= impl_->readers.size() ||
      impl_->readers[reader]->get_subscription_matched_status(status) != ReturnCode_t::RETCODE_OK)
    return 0;
  return static_cast<size_t>(status.current_count);
}

size_t DdsLink::peers_alive() const {
  std::lock_guard lock(impl_->peers_mutex);
  return impl_->alive.size();
}

void DdsLink::close() {
  if (!impl_ || impl_->participant == nullptr) return;
  Impl& m = *impl_;
  m.closing.store(true, std::memory_order_release);
  { std::unique_lock wait_for_callbacks(m.callback_mutex); }
  for (fdds::DataReader* r : m.readers) r->set_listener(nullptr);
  m.participant->set_listener(nullptr);
  if (m.presence_reader != nullptr) m.presence_reader->set_listener(nullptr);
  m.participant->delete_contained_entities();
  fdds::DomainParticipantFactory::get_instance()->delete_participant(m.participant);
  m.participant = nullptr;
  m.readers.clear();
  m.writers.clear();
  m.topics.clear();
}

}  // namespace scancrew::dds_bridge
