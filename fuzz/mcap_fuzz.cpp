// The MCAP recording reader (components/recorder/recording.hpp, mcap_reader.hpp) as replay
// uses it: open, collect the scancrew channels, then every message, each decoded as its
// topic's type.
#include <span>

#include "components/recorder/recording.hpp"
#include "fuzz/fuzz_input.hpp"
#include "interfaces/codec.hpp"
#include "interfaces/message_fields.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using scancrew::recorder::RecordingReader;
  auto reader = RecordingReader::open(scancrew::fuzz::as_file(data, size));
  if (!reader) return 0;
  if (!reader->scan_topics()) return 0;
  for (int records = 0; records < 100000; ++records) {
    auto entry = reader->next();
    if (!entry || !*entry) break;
    const auto& topics = reader->topics();
    if ((*entry)->topic >= topics.size()) continue;
    const std::span<const uint8_t> bytes = (*entry)->message;
    scancrew::msg::with_wire_message(topics[(*entry)->topic].type, [&]<class T>() {
      T message;
      (void)scancrew::msg::decode(bytes, message);
    });
  }
  return 0;
}
