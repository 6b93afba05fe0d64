// ParamReader::describing(): a component's read_config() run over no parameters records each
// parameter (type, default, range, allowed names, required, description) and fails nothing;
// ComponentRegistry::parameters() runs a registered type's read_config() so.

#include <gtest/gtest.h>

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

TEST(ParamDescribe, TheRegistryListsARegisteredTypesParameters) {
  const auto& registry = ComponentRegistry::instance();
  const auto params = registry.parameters("test_param_described");
  ASSERT_EQ(params.size(), 10U);
  EXPECT_EQ(params[0].key, "rate_hz");
  EXPECT_EQ(params[0].description, "camera frame rate (Hz)");
  EXPECT_TRUE(registry.parameters("no_such_type").empty());
}

}  // namespace

SCANCREW_REGISTER_COMPONENT(Described, "test_param_described")

}  // namespace scancrew
