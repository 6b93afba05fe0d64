// The plain Fast DDS side of `scancrew bench dds` (dds_bench.hpp): two DomainParticipants in
// this process, robot 1's with a DataWriter and robot 2's with a DataReader of the bridge's
// Envelope type on kDdsBenchTopic, set up as DdsLink sets up a bridge's (dds_link.cpp):
//   - transport: UDPv4 only, on 127.0.0.1, unicast discovery to 127.0.0.1 (32 participants);
//   - QoS: reliable, volatile, keep-last `depth`, a heartbeat every 0.1 s, asynchronous
//     publish mode, data-sharing off, the bench's partition;
//   - security: the participant properties of places robot_1 and robot_2 (team_keys.hpp).
// The envelope's payload is the bench payload itself (the bridge's is the patch encoded
// around it: about 100 bytes more). The reader's listener takes each sample on Fast DDS's
// thread and hands its payload to the Arrivals, as a bridge's listener copies it to its inbox.

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>

#include <chrono>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <thread>

#include "bench/dds/dds_pair.hpp"
#include "components/dds_bridge/idl/envelopePubSubTypes.h"
#include "components/dds_bridge/team_keys.hpp"
#include "executors/clock.hpp"
#include "interfaces/map_msgs.hpp"
#include "interfaces/message_fields.hpp"

namespace scancrew::bench {

namespace {

namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

class ReaderListener final : public fdds::DataReaderListener {
 public:
  explicit ReaderListener(Arrivals& arrivals) : arrivals_(arrivals) {}
  // as the bridge's listener: a local envelope (Fast DDS may call from more than one thread)
  void on_data_available(fdds::DataReader* reader) override {
    scancrew::dds::Envelope envelope;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&envelope, &info) == ReturnCode_t::RETCODE_OK)
      if (info.valid_data) arrivals_.arrived(envelope.payload());
  }

 private:
  Arrivals& arrivals_;
};

// One participant with its publisher or subscriber; deletes everything it made.
class Participant {
 public:
  ~Participant() {
    if (participant_ == nullptr) return;
    participant_->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
  Participant() = default;
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  Result<void, std::string> create(const PairSetup& s, const std::string& place) {
    fdds::DomainParticipantQos pqos;
    pqos.name(("scancrew_bench_dds_" + place).c_str());
    if (!s.keys_dir.empty()) {
      auto properties = dds_bridge::security_properties(s.keys_dir, place);
      if (!properties) return make_unexpected(properties.error());
      for (const auto& [name, value] : *properties)
        pqos.properties().properties().emplace_back(name, value);
    }
    pqos.transport().use_builtin_transports = false;
    auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
    udp->maxInitialPeersRange = 32;
    udp->interfaceWhiteList.emplace_back("127.0.0.1");
    pqos.transport().user_transports.push_back(udp);
    rtps::Locator_t peer;
    peer.kind = LOCATOR_KIND_UDPv4;
    peer.port = 0;
    rtps::IPLocator::setIPv4(peer, "127.0.0.1");
    pqos.wire_protocol().builtin.initialPeersList.push_back(peer);
    participant_ =
        fdds::DomainParticipantFactory::get_instance()->create_participant(s.domain_id, pqos);
    if (participant_ == nullptr)
      return make_unexpected("cannot create the Fast DDS participant of " + place);
    if (type_.register_type(participant_) != ReturnCode_t::RETCODE_OK)
      return make_unexpected("cannot register the Envelope type");
    topic_ =
        participant_->create_topic(kDdsBenchTopic, type_.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    if (topic_ == nullptr) return make_unexpected("cannot create the topic");
    return {};
  }

  fdds::DataWriter* add_writer(const PairSetup& s) {
    fdds::PublisherQos qos = fdds::PUBLISHER_QOS_DEFAULT;
    qos.partition().push_back(s.partition.c_str());
    fdds::Publisher* publisher = participant_->create_publisher(qos);
    if (publisher == nullptr) return nullptr;
    fdds::DataWriterQos w = publisher->get_default_datawriter_qos();
    w.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    w.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
    w.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    w.history().depth = static_cast<int32_t>(s.depth);
    w.reliable_writer_qos().times.heartbeatPeriod = eprosima::fastrtps::Duration_t(0, 100'000'000);
    w.publish_mode().kind = fdds::ASYNCHRONOUS_PUBLISH_MODE;
    w.data_sharing().off();
    return publisher->create_datawriter(topic_, w);
  }

  fdds::DataReader* add_reader(const PairSetup& s, fdds::DataReaderListener* listener) {
    fdds::SubscriberQos qos = fdds::SUBSCRIBER_QOS_DEFAULT;
    qos.partition().push_back(s.partition.c_str());
    fdds::Subscriber* subscriber = participant_->create_subscriber(qos);
    if (subscriber == nullptr) return nullptr;
    fdds::DataReaderQos r = subscriber->get_default_datareader_qos();
    r.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    r.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
    r.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    r.history().depth = static_cast<int32_t>(s.depth);
    r.data_sharing().off();
    return subscriber->create_datareader(topic_, r, listener);
  }

 private:
  fdds::DomainParticipant* participant_ = nullptr;
  fdds::TypeSupport type_{new scancrew::dds::EnvelopePubSubType()};
  fdds::Topic* topic_ = nullptr;
};

class FastDdsPair final : public DdsPair {
 public:
  explicit FastDdsPair(Arrivals& arrivals) : listener_(arrivals) {
    envelope_.format_version(msg::kMessageFormatVersion);
    envelope_.robot_id(1);
    envelope_.type_name(msg::TsdfPatch::kTypeName);
  }
  // Fast DDS 2.9 can deadlock when a writer is deleted while it unmatches a reader that just
  // left (seen here): the writer goes first, once its samples are acknowledged, and the
  // reader once it has unmatched it (each wait bounded)
  ~FastDdsPair() override {
    if (writer_ != nullptr) writer_->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(2, 0));
    sender_.reset();
    const int64_t deadline = monotonic_now_ns() + 5'000'000'000;
    fdds::SubscriptionMatchedStatus r;
    while (reader_ != nullptr && monotonic_now_ns() < deadline &&
           reader_->get_subscription_matched_status(r) == ReturnCode_t::RETCODE_OK &&
           r.current_count > 0)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    receiver_.reset();
  }
  FastDdsPair(const FastDdsPair&) = delete;
  FastDdsPair& operator=(const FastDdsPair&) = delete;

  Result<void, std::string> create(const PairSetup& s) {
    sender_ = std::make_unique<Participant>();
    receiver_ = std::make_unique<Participant>();
    if (auto ok = sender_->create(s, "robot_1"); !ok) return ok;
    if (auto ok = receiver_->create(s, "robot_2"); !ok) return ok;
    writer_ = sender_->add_writer(s);
    reader_ = receiver_->add_reader(s, &listener_);
    if (writer_ == nullptr || reader_ == nullptr)
      return make_unexpected("cannot create the DataWriter or the DataReader");
    const int64_t deadline = monotonic_now_ns() + 30'000'000'000;
    while (monotonic_now_ns() < deadline) {
      fdds::PublicationMatchedStatus w;
      fdds::SubscriptionMatchedStatus r;
      writer_->get_publication_matched_status(w);
      reader_->get_subscription_matched_status(r);
      if (w.current_count >= 1 && r.current_count >= 1) return {};
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return make_unexpected("the DataWriter and the DataReader did not match in 30 s");
  }

  bool send(size_t payload_bytes, uint32_t phase, uint32_t index) override {
    std::vector<uint8_t>& payload = envelope_.payload();
    payload.resize(payload_bytes);
    envelope_.seq(envelope_.seq() + 1);
    envelope_.stamp_ns(monotonic_now_ns());
    stamp_payload(payload, phase, index);
    return writer_->write(&envelope_);
  }

 private:
  ReaderListener listener_;
  std::unique_ptr<Participant> sender_, receiver_;
  fdds::DataWriter* writer_ = nullptr;
  fdds::DataReader* reader_ = nullptr;
  scancrew::dds::Envelope envelope_;
};

}  // namespace

Result<std::unique_ptr<DdsPair>, std::string> make_fastdds_pair(const PairSetup& setup,
                                                                Arrivals& arrivals) {
  // as a bridge with `intraprocess: false`: a library-wide setting, read when a participant
  // is created
  eprosima::fastrtps::LibrarySettingsAttributes library;
  library.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_OFF;
  eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(library);
  auto pair = std::make_unique<FastDdsPair>(arrivals);
  if (auto ok = pair->create(setup); !ok) return make_unexpected(ok.error());
  return std::unique_ptr<DdsPair>(std::move(pair));
}

}  // namespace scancrew::bench
