#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "executors/params.hpp"
#include "executors/params_impl.hpp"

namespace scancrew {
namespace {

::testing::AssertionResult has_error(const ParamReader& r, const std::string& fragment) {
  for (const auto& e : r.errors())
    if (e.find(fragment) != std::string::npos) return ::testing::AssertionSuccess();
  std::string all;
  for (const auto& e : r.errors()) all += "\n  " + e;
  return ::testing::AssertionFailure() << "no error containing '" << fragment << "' in:" << all;
}

TEST(ParamReader, ReadsTypedValuesAndKeepsDefaultsForMissingKeys) {
  auto r = ParamReader::from_yaml_string("rate_hz: 12.5\ncount: 3\nname: left\nenabled: false\n",
                                         "t.yaml");
  double rate = 1;
  uint32_t count = 0;
  std::string name;
  bool enabled = true;
  int64_t untouched = -7;
  r.required("rate_hz", rate, {0, 100});
  r.optional("count", count);
  r.optional("name", name);
  r.optional("enabled", enabled);
  r.optional("absent", untouched);
  r.finish();
  EXPECT_TRUE(r.ok());
  EXPECT_DOUBLE_EQ(rate, 12.5);
  EXPECT_EQ(count, 3u);
  EXPECT_EQ(name, "left");
  EXPECT_FALSE(enabled);
  EXPECT_EQ(untouched, -7);
}

TEST(ParamReader, NamesFileLineKeyAndWhatIsAllowed) {
  auto r = ParamReader::from_yaml_string("a: 1\nrate_hz: 5000\n", "cfg.yaml");
  double rate = 1;
  r.required("rate_hz", rate, {0.1, 1000});
  EXPECT_TRUE(has_error(
      r, "cfg.yaml:2: params.rate_hz: 5000 is out of range; allowed: a number in [0.1, 1000]"));
  EXPECT_DOUBLE_EQ(rate, 1);
}

TEST(ParamReader, ReportsMissingRequiredParameters) {
  auto r = ParamReader::from_yaml_string("{}", "cfg.yaml");
  double period = 0;
  r.required("period_s", period, {0, 10});
  EXPECT_TRUE(has_error(r, "params.period_s: missing required parameter"));
}

TEST(ParamReader, ReportsMistypedValues) {
  auto r =
      ParamReader::from_yaml_string("n: 2.5\nx: fast\nflag: maybe\nlist: [1, 2]\n", "cfg.yaml");
  int n = 0;
  double x = 0;
  bool flag = false;
  double list = 0;
  r.optional("n", n);
  r.optional("x", x);
  r.optional("flag", flag);
  r.optional("list", list);
  EXPECT_TRUE(has_error(r, "params.n: '2.5' has the wrong type; allowed: an integer"));
  EXPECT_TRUE(has_error(r, "params.x: 'fast' has the wrong type; allowed: a number"));
  EXPECT_TRUE(has_error(r, "params.flag: 'maybe' has the wrong type; allowed: true or false"));
  EXPECT_TRUE(has_error(r, "params.list: a list or mapping has the wrong type"));
}

TEST(ParamReader, RejectsNegativeValuesForUnsignedFields) {
  auto r = ParamReader::from_yaml_string("size: -3\n", "cfg.yaml");
  uint64_t size = 1;
  r.optional("size", size);
  EXPECT_TRUE(
      has_error(r, "params.size: '-3' has the wrong type; allowed: a non-negative integer"));
}

TEST(ParamReader, ReportsUnknownKeysWithTheKnownOnes) {
  auto r = ParamReader::from_yaml_string("rate_hz: 1\nrat_hz: 2\n", "cfg.yaml");
  double rate = 0;
  r.optional("rate_hz", rate);
  r.finish();
  EXPECT_TRUE(has_error(r, "cfg.yaml:2: params.rat_hz: unknown parameter; known: rate_hz"));
}

TEST(ParamReader, ChoiceListsTheAllowedValues) {
  auto r = ParamReader::from_yaml_string("mode: fastest\n", "cfg.yaml");
  std::string mode = "vio";
  r.choice("mode", mode, {"vio", "ground_truth"});
  EXPECT_TRUE(has_error(r, "'fastest' is not allowed; allowed: vio, ground_truth"));
  EXPECT_EQ(mode, "vio");
}

enum class Fruit { kApple, kPear };
constexpr EnumNames<Fruit, 2> kFruitNames = {{{Fruit::kApple, "apple"}, {Fruit::kPear, "pear"}}};

TEST(ParamReader, ChoiceOfAnEnumParsesItsNamesAndListsThem) {
  auto r = ParamReader::from_yaml_string("a: pear\nb: plum\n", "cfg.yaml");
  Fruit a = Fruit::kApple, b = Fruit::kApple, c = Fruit::kPear;
  r.choice("a", a, kFruitNames);
  r.choice("b", b, kFruitNames);
  r.choice("c", c, kFruitNames);  // missing: keeps the default
  EXPECT_EQ(a, Fruit::kPear);
  EXPECT_EQ(b, Fruit::kApple);
  EXPECT_EQ(c, Fruit::kPear);
  ASSERT_EQ(r.errors().size(), 1U);
  EXPECT_TRUE(has_error(r, "params.b: 'plum' is not allowed; allowed: apple, pear"));
  EXPECT_EQ(name_of(kFruitNames, Fruit::kPear), "pear");
}

TEST(ParamReader, ListsHaveTheirShapeChecked) {
  auto r = ParamReader::from_yaml_string("xyz: [1, 2]\nok: [1, 2, 3]\n", "cfg.yaml");
  std::vector<double> xyz, ok;
  r.optional_list("xyz", xyz, 3);
  r.optional_list("ok", ok, 3);
  EXPECT_TRUE(has_error(r, "params.xyz: wrong shape; allowed: a list of 3 numbers"));
  EXPECT_EQ(ok, (std::vector<double>{1, 2, 3}));
}

TEST(ParamReader, InvalidYamlIsAnError) {
  auto r = ParamReader::from_yaml_string("a: [1, 2\n", "cfg.yaml");
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(has_error(r, "not valid YAML"));
}

// A key twice in one mapping was silently ignored (yaml-cpp keeps both, a lookup finds the
// first); aliases that expand past the text's size are refused before anyone walks them.
TEST(ParseYaml, RefusesDuplicateKeysAndAliasBombs) {
  auto dup = parse_yaml("a: 1\nb:\n  c: 2\n  c: 3\n", "d.yaml");
  ASSERT_FALSE(dup);
  EXPECT_EQ(dup.error(), "d.yaml:4: duplicate key 'c' (first at line 3)");
  EXPECT_TRUE(
      has_error(ParamReader::from_yaml_string("x: 1\nx: 2\n", "p.yaml"), "duplicate key 'x'"));
  std::string bomb = "a0: &a0 [x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i < 12; ++i)
    bomb += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [*a" + std::to_string(i - 1) +
            ", *a" + std::to_string(i - 1) + ", *a" + std::to_string(i - 1) + ", *a" +
            std::to_string(i - 1) + "]\n";
  auto laughs = parse_yaml(bomb, "bomb.yaml");  // 8 x 4^11 = 33 M nodes from 0.5 KB
  ASSERT_FALSE(laughs);
  EXPECT_NE(laughs.error().find("aliases expand"), std::string::npos) << laughs.error();
  EXPECT_TRUE(parse_yaml("a: &x {b: 1}\nc: *x\n", "ok.yaml"));  // an alias is fine
}

// Text files are read whole, so what is read is bounded: a device (/dev/zero never ends), a
// directory and a file over kMaxTextFileBytes are refused with the reason, before reading.
TEST(ReadTextFile, RefusesDevicesDirectoriesAndHugeFiles) {
  const auto dir = std::filesystem::path(::testing::TempDir()) / "read_text_file";
  std::filesystem::create_directories(dir);
  const auto small = dir / "small.yaml";
  std::ofstream(small) << "a: 1\n";
  const auto text = read_text_file(small.string());
  ASSERT_TRUE(text) << text.error();
  EXPECT_EQ(*text, "a: 1\n");

  EXPECT_NE(read_text_file((dir / "missing.yaml").string()).error().find("no such file"),
            std::string::npos);
  // the system's reason when it is not "no such file" (a file used as a folder; EACCES alike)
  EXPECT_EQ(read_text_file((small / "x.yaml").string()).error(),
            std::make_error_code(std::errc::not_a_directory).message());
  EXPECT_NE(read_text_file("/dev/zero").error().find("not a regular file"), std::string::npos);
  EXPECT_NE(read_text_file(dir.string()).error().find("not a regular file"), std::string::npos);
  const auto huge = dir / "huge.yaml";  // sparse: no disk used
  std::ofstream(huge).close();
  std::filesystem::resize_file(huge, kMaxTextFileBytes + 1);
  EXPECT_NE(read_text_file(huge.string()).error().find("MiB a text file may have"),
            std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace scancrew
