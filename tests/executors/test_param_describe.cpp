// ParamReader::describing(): a component's read_config() run over no parameters records each
// parameter (type, default, range, allowed names, required, description) and fails nothing;
// ComponentRegistry::parameters() runs a registered type's read_config() so.

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <limits>
#include <string>
#include <vector>

#include "core/enum_names.hpp"
#include "executors/params.hpp"
#include "executors/registry.hpp"

namespace scancrew {
namespace {

enum class Gait { kWalk, kTrot };
constexpr EnumNames<Gait, 2> kGaitNames = {{{Gait::kWalk, "walk"}, {Gait::kTrot, "trot"}}};

struct Config {
  double rate_hz = 2.5;
  double window_s = 0;
  std::string topic = "depth";
  std::string map_file;
  std::string colour = "owner";
  Gait gait = Gait::kTrot;
  uint32_t count = 7;
  bool verbose = false;
  std::vector<double> origin = {1, 2, 3};
  std::vector<std::string> robots;
};

Config read_config(ParamReader& p) {
  Config c;
  p.optional("rate_hz", c.rate_hz, {0.1, 100}).doc("camera frame rate (Hz)");
  c.window_s = 4 / c.rate_hz;  // a default derived from another parameter
  p.optional("window_s", c.window_s, {0, 60});
  p.required("map_file", c.map_file).doc("the map to load");
  if (c.map_file.empty()) p.report("map_file", "no such file");  // a check of a value
  p.optional("topic", c.topic);
  p.choice("colour", c.colour, {"owner", "none"}).doc("mesh colouring");
  p.choice("gait", c.gait, kGaitNames, true);
  p.optional("count", c.count, {1, 1e6});
  p.optional("verbose", c.verbose);
  p.optional_list("origin", c.origin, 3, {-10, 10});
  p.optional_list("robots", c.robots);
  p.optional("rate_hz", c.rate_hz, {0.1, 100});  // read twice: recorded once
  return c;
}

const ParamInfo& find(const std::vector<ParamInfo>& all, const std::string& key) {
  for (const ParamInfo& p : all)
    if (p.key == key) return p;
  ADD_FAILURE() << "no parameter " << key;
  static const ParamInfo none;
  return none;
}

TEST(ParamDescribe, RecordsEachReadWithItsDefaultRangeAndDescription) {
  ParamReader r = ParamReader::describing();
  const Config c = read_config(r);
  r.finish();
  EXPECT_TRUE(r.ok());  // the missing required key and the report() are not errors here
  EXPECT_EQ(c.rate_hz, 2.5);
  EXPECT_EQ(c.gait, Gait::kTrot);
  const auto& all = r.described();
  ASSERT_EQ(all.size(), 10U);
  EXPECT_EQ(all.front().key, "rate_hz");
  EXPECT_EQ(all.back().key, "robots");

  const ParamInfo& rate = find(all, "rate_hz");
  EXPECT_EQ(rate.type, "double");
  EXPECT_EQ(rate.default_value, "2.5");
  EXPECT_EQ(rate.range, "[0.1, 100]");
  EXPECT_FALSE(rate.required);
  EXPECT_EQ(rate.description, "camera frame rate (Hz)");
  EXPECT_EQ(find(all, "window_s").default_value, "1.6");
  EXPECT_EQ(find(all, "window_s").description, "");

  const ParamInfo& map = find(all, "map_file");
  EXPECT_TRUE(map.required);
  EXPECT_EQ(map.type, "string");
  EXPECT_EQ(map.description, "the map to load");

  const ParamInfo& colour = find(all, "colour");
  EXPECT_EQ(colour.type, "choice");
  EXPECT_EQ(colour.default_value, "owner");
  EXPECT_EQ(colour.allowed, (std::vector<std::string>{"owner", "none"}));
  EXPECT_EQ(colour.description, "mesh colouring");
  const ParamInfo& gait = find(all, "gait");
  EXPECT_EQ(gait.default_value, "trot");
  EXPECT_EQ(gait.allowed, (std::vector<std::string>{"walk", "trot"}));
  EXPECT_TRUE(gait.required);

  EXPECT_EQ(find(all, "count").type, "uint32");
  EXPECT_EQ(find(all, "count").range, "[1, 1000000]");
  EXPECT_EQ(find(all, "verbose").default_value, "false");
  EXPECT_EQ(find(all, "verbose").range, "");
  EXPECT_EQ(find(all, "origin").type, "list<double> of 3");
  EXPECT_EQ(find(all, "origin").default_value, "[1, 2, 3]");
  EXPECT_EQ(find(all, "origin").range, "[-10, 10]");
  EXPECT_EQ(find(all, "robots").type, "list<string>");
  EXPECT_EQ(find(all, "robots").default_value, "[]");
}

// A reader over a launch file records nothing, and doc() costs nothing there.
TEST(ParamDescribe, AReaderOverParametersDescribesNothing) {
  auto r = ParamReader::from_yaml_string("rate_hz: 10\nmap_file: m.bt\ngait: walk\n", "t.yaml");
  const Config c = read_config(r);
  r.finish();
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(c.rate_hz, 10);
  EXPECT_EQ(c.gait, Gait::kWalk);
  EXPECT_TRUE(r.described().empty());
  EXPECT_FALSE(r.is_describing());
}

class Described final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: a component described";
  using Config = scancrew::Config;
  static Config read_config(ParamReader& p) { return scancrew::read_config(p); }
  Described(ComponentContext context, const Config& /*config*/) : Component(std::move(context)) {}

 private:
  Result<void, std::string> on_configure() override { return {}; }
};

// effective(): each key with the value the read left, as YAML that reads back exactly; a
// default derived from another parameter is the derived value.
TEST(ParamDescribe, AReaderOverParametersRecordsTheValuesItLeft) {
  auto r = ParamReader::from_yaml_string(
      "rate_hz: 3\nmap_file: 'a \"b\".bt'\ngait: walk\nrobots: [r1, r2]\n", "t.yaml");
  (void)read_config(r);
  const auto& all = r.effective();
  ASSERT_EQ(all.size(), 10U);                                            // rate_hz read twice: once
  EXPECT_EQ(find(all, "rate_hz").default_value, "3");                    // given
  EXPECT_EQ(find(all, "window_s").default_value, "1.3333333333333333");  // derived, exact
  EXPECT_EQ(find(all, "map_file").default_value, R"("a \"b\".bt")");
  EXPECT_EQ(find(all, "gait").default_value, R"("walk")");
  EXPECT_EQ(find(all, "colour").type, "choice");
  EXPECT_EQ(find(all, "count").default_value, "7");
  EXPECT_EQ(find(all, "verbose").default_value, "false");
  EXPECT_EQ(find(all, "origin").default_value, "[1, 2, 3]");
  EXPECT_EQ(find(all, "robots").default_value, R"(["r1", "r2"])");
}

// A non-finite default ("no limit") has no launch-file form: effective() leaves it out.
TEST(ParamDescribe, EffectiveValuesLeaveOutNonFiniteDefaults) {
  auto r = ParamReader::from_yaml_string("", "t.yaml");
  double ceiling = std::numeric_limits<double>::infinity(), floor = -1.5;
  r.optional("ceiling_m", ceiling, {-100, 100});
  r.optional("floor_m", floor, {-100, 100});
  ASSERT_EQ(r.effective().size(), 1U);
  EXPECT_EQ(r.effective()[0].key, "floor_m");
  EXPECT_EQ(r.effective()[0].default_value, "-1.5");
}

TEST(ParamDescribe, TheRegistryListsARegisteredTypesParameters) {
  const auto& registry = ComponentRegistry::instance();
  const auto params = registry.parameters("test_param_described");
  ASSERT_EQ(params.size(), 10U);
  EXPECT_EQ(params[0].key, "rate_hz");
  EXPECT_EQ(params[0].description, "camera frame rate (Hz)");
  EXPECT_TRUE(registry.parameters("no_such_type").empty());
  const auto effective =
      registry.effective_parameters("test_param_described", YAML::Load("rate_hz: 8"));
  EXPECT_EQ(find(effective, "window_s").default_value, "0.5");
  EXPECT_TRUE(registry.effective_parameters("no_such_type", YAML::Node()).empty());
}

}  // namespace

SCANCREW_REGISTER_COMPONENT(Described, "test_param_described")

}  // namespace scancrew
