// The dds_bridge tests' harness (bridge_harness.hpp): the test components' registrations,
// once per test executable.

#include "tests/components/dds_bridge/bridge_harness.hpp"

namespace scancrew::dds_bridge::testing {

SCANCREW_REGISTER_COMPONENT(Source, "test_dds_source")
SCANCREW_REGISTER_COMPONENT(Sink, "test_dds_sink")

}  // namespace scancrew::dds_bridge::testing
