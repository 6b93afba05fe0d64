// Fast DDS side of `scancrew bench ipc`: Fast DDS 2.9, one participant, a writer and a
// reader of a plain fixed-size type in the same process, intra-process delivery on
// (INTRAPROCESS_FULL, the library default), data-sharing on, samples loaned on both
// sides (loan_sample / take with loans), shared-memory transport only (no network).
//  - same_thread: write, then take on the same thread;
//  - cross_thread: a reader thread blocked in a WaitSet on DATA_AVAILABLE takes it.

#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <fastdds/dds/core/condition/WaitSet.hpp>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <memory>
#include <thread>

#include "bench/ipc/cpu_pinning.hpp"
#include "bench/ipc/ipc_bench.hpp"
#include "bench/ipc/latency_samples.hpp"
#include "executors/clock.hpp"

namespace scancrew::bench {

namespace dds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

namespace {

template <size_t N>
struct PlainBlob {
  int64_t t0_ns;
  uint64_t seq;
  std::array<uint8_t, N> data;
};

// TopicDataType of a plain (memcpy-able, fixed-size) struct: what data-sharing and loans
// require. Serialisation is a 4-byte CDR little-endian header plus the raw bytes.
template <class T>
class PlainType final : public dds::TopicDataType {
 public:
  explicit PlainType(const std::string& name) {
    setName(name.c_str());
    m_typeSize = static_cast<uint32_t>(sizeof(T) + 4);
    m_isGetKeyDefined = false;
  }
  bool serialize(void* data, rtps::SerializedPayload_t* payload) override {
    payload->encapsulation = CDR_LE;
    const uint8_t header[4] = {0, 1, 0, 0};
    std::memcpy(payload->data, header, 4);
    std::memcpy(payload->data + 4, data, sizeof(T));
    payload->length = static_cast<uint32_t>(sizeof(T) + 4);
    return true;
  }
  bool deserialize(rtps::SerializedPayload_t* payload, void* data) override {
    std::memcpy(data, payload->data + 4, sizeof(T));
    return true;
  }
  std::function<uint32_t()> getSerializedSizeProvider(void* /*data*/) override {
    return [] { return static_cast<uint32_t>(sizeof(T) + 4); };
  }
  void* createData() override { return new T(); }
  void deleteData(void* data) override { delete static_cast<T*>(data); }
  bool getKey(void* /*data*/, rtps::InstanceHandle_t* /*handle*/, bool /*force_md5*/) override {
    return false;
  }
  bool is_bounded() const override { return true; }
  bool is_plain() const override { return true; }
  bool construct_sample(void* memory) const override {
    new (memory) T;
    return true;
  }
};

// A participant on the shared-memory transport only (no network); nullptr when Fast DDS
// refuses it.
dds::DomainParticipant* create_participant(dds::DomainParticipantFactory* factory) {
  dds::DomainParticipantQos pqos;
  pqos.name("scancrew_bench_ipc");
  pqos.transport().use_builtin_transports = false;
  auto shm = std::make_shared<eprosima::fastdds::rtps::SharedMemTransportDescriptor>();
  pqos.transport().user_transports.push_back(shm);
  return factory->create_participant(42, pqos);
}

// The writer's and the reader's common QoS: reliable, the last 4 samples, data-sharing.
template <class Qos>
void keep_last_four_shared(Qos& qos) {
  qos.reliability().kind = dds::RELIABLE_RELIABILITY_QOS;
  qos.history().kind = dds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 4;
  qos.resource_limits().max_samples = 4;
  qos.data_sharing().automatic();
}

struct Endpoints {
  dds::TypeSupport type;
  dds::DataWriter* writer = nullptr;
  dds::DataReader* reader = nullptr;
};

// Registers PlainBlob<N>'s type on `participant` and creates a writer (synchronous) and a
// reader of its topic; the participant owns them.
template <size_t N>
Endpoints create_endpoints(dds::DomainParticipant* participant) {
  Endpoints endpoints;
  endpoints.type =
      dds::TypeSupport(new PlainType<PlainBlob<N>>("scancrew::bench::Blob" + std::to_string(N)));
  endpoints.type.register_type(participant);
  dds::Topic* topic = participant->create_topic(
      "bench_blob_" + std::to_string(N), endpoints.type.get_type_name(), dds::TOPIC_QOS_DEFAULT);
  dds::Publisher* publisher = participant->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
  dds::Subscriber* subscriber = participant->create_subscriber(dds::SUBSCRIBER_QOS_DEFAULT);

  dds::DataWriterQos wqos = publisher->get_default_datawriter_qos();
  keep_last_four_shared(wqos);
  wqos.publish_mode().kind = dds::SYNCHRONOUS_PUBLISH_MODE;
  endpoints.writer = publisher->create_datawriter(topic, wqos);

  dds::DataReaderQos rqos = subscriber->get_default_datareader_qos();
  keep_last_four_shared(rqos);
  endpoints.reader = subscriber->create_datareader(topic, rqos);
  return endpoints;
}

// Waits up to 5 s for the writer to match the reader (local, no discovery traffic leaves the
// process).
void wait_for_match(dds::DataWriter* writer) {
  const int64_t match_deadline = monotonic_now_ns() + 5'000'000'000;
  dds::PublicationMatchedStatus matched;
  while (monotonic_now_ns() < match_deadline) {
    writer->get_publication_matched_status(matched);
    if (matched.current_count > 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// Takes everything available with loans, recording latency at take time.
template <class Blob>
void take_all(dds::DataReader* reader, DeliveryState& state) {
  dds::LoanableSequence<Blob> data;
  dds::SampleInfoSeq infos;
  size_t n = 0;
  while (reader->take(data, infos) == ReturnCode_t::RETCODE_OK) {
    const int64_t now = monotonic_now_ns();
    for (dds::LoanableCollection::size_type i = 0; i < infos.length(); ++i) {
      if (!infos[i].valid_data) continue;
      if (state.measuring.load(std::memory_order_relaxed)) state.samples.add(now - data[i].t0_ns);
      ++n;
    }
    reader->return_loan(data, infos);
  }
  if (n) state.received.fetch_add(n, std::memory_order_release);
}

// cross_thread's reader: a thread pinned to CPU 1, blocked in a WaitSet on DATA_AVAILABLE
// (100 ms at most, to see `stop`), taking what arrived.
template <class Blob>
std::thread start_reader_thread(dds::DataReader* reader, DeliveryState& state) {
  return std::thread([reader, &state] {
    pin_to_cpu(1);
    dds::WaitSet waitset;
    dds::StatusCondition& condition = reader->get_statuscondition();
    condition.set_enabled_statuses(dds::StatusMask::data_available());
    waitset.attach_condition(condition);
    dds::ConditionSeq active;
    while (!state.stop.load()) {
      if (waitset.wait(active, eprosima::fastrtps::Duration_t(0, 100'000'000)) ==
          ReturnCode_t::RETCODE_OK)
        take_all<Blob>(reader, state);
    }
  });
}

// The measured loop: loans, stamps and writes warm-up + options.samples samples, waiting for
// each (await_delivery); counts in result.lost the ones not loaned or not delivered.
template <class Blob>
void write_samples(const Endpoints& endpoints, bool cross_thread, const IpcOptions& options,
                   DeliveryState& state, IpcResult& result) {
  const auto take = [&] { take_all<Blob>(endpoints.reader, state); };
  const int warmup = 500;  // unrecorded: the receiving thread and core settle
  for (int i = 0; i < warmup + options.samples; ++i) {
    state.measuring.store(i >= warmup, std::memory_order_relaxed);
    const uint64_t before = state.received.load(std::memory_order_acquire);
    const int64_t t0 = monotonic_now_ns();
    void* raw = nullptr;
    if (endpoints.writer->loan_sample(raw) != ReturnCode_t::RETCODE_OK) {
      ++result.lost;
      continue;
    }
    auto* blob = static_cast<Blob*>(raw);
    blob->t0_ns = t0;
    blob->seq = static_cast<uint64_t>(i);
    endpoints.writer->write(raw);
    if (!await_delivery(state.received, before, cross_thread, options.gap_us, take)) ++result.lost;
  }
}

template <size_t N>
IpcResult run_case(bool cross_thread, const IpcOptions& options) {
  using Blob = PlainBlob<N>;
  IpcResult result{"fastdds", cross_thread ? "cross_thread" : "same_thread", N};

  auto* factory = dds::DomainParticipantFactory::get_instance();
  dds::DomainParticipant* participant = create_participant(factory);
  if (participant == nullptr) {
    result.lost = static_cast<size_t>(options.samples);
    return result;
  }
  const Endpoints endpoints = create_endpoints<N>(participant);
  wait_for_match(endpoints.writer);

  DeliveryState state(static_cast<size_t>(options.samples));
  std::thread reader_thread;
  if (cross_thread) {
    pin_to_cpu(0);
    reader_thread = start_reader_thread<Blob>(endpoints.reader, state);
  }
  write_samples<Blob>(endpoints, cross_thread, options, state, result);
  state.stop.store(true);
  if (reader_thread.joinable()) {
    reader_thread.join();
    unpin();
  }

  participant->delete_contained_entities();
  factory->delete_participant(participant);
  state.samples.summarise(result);
  return result;
}

template <size_t N>
void add_case(std::vector<IpcResult>& out, size_t payload, const IpcOptions& options) {
  if (payload != N) return;
  for (bool cross : {false, true}) out.push_back(run_case<N>(cross, options));
}

}  // namespace

std::vector<IpcResult> bench_fastdds(const IpcOptions& options) {
  eprosima::fastrtps::LibrarySettingsAttributes library;
  library.intraprocess_delivery = options.fastdds_intraprocess
                                      ? eprosima::fastrtps::INTRAPROCESS_FULL
                                      : eprosima::fastrtps::INTRAPROCESS_OFF;
  eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(library);
  std::vector<IpcResult> out;
  for (size_t payload : options.payload_bytes) {
    add_case<64>(out, payload, options);
    add_case<4096>(out, payload, options);
    add_case<(256 << 10)>(out, payload, options);
    add_case<(1 << 20)>(out, payload, options);
    add_case<(4 << 20)>(out, payload, options);
    add_case<(16 << 20)>(out, payload, options);
  }
  return out;
}

}  // namespace scancrew::bench
