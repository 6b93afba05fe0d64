// The TSPLIB reader: the shipped instances load with their declared sizes; malformed
// files are refused with the line and the reason. Tiny files are written inline.

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "core/tsga/tsplib.hpp"

namespace scancrew::tsga {
namespace {

Result<TsplibInstance, std::string> parse(const std::string& text) {
  std::istringstream in(text);
  return parse_tsplib(in, "tiny.atsp");
}

constexpr const char* kHeader =
    "NAME: tiny\nTYPE: ATSP\nCOMMENT: three nodes\nDIMENSION: 3\n"
    "EDGE_WEIGHT_TYPE: EXPLICIT\nEDGE_WEIGHT_FORMAT: FULL_MATRIX\nEDGE_WEIGHT_SECTION\n";

TEST(Tsplib, ReadsAFullMatrixAcrossLineBreaks) {
  auto tiny = parse(std::string(kHeader) + " 9999 1 2\n 3 9999\n 4 5 6 9999\nEOF\n");
  ASSERT_TRUE(tiny) << tiny.error();
  EXPECT_EQ(tiny->name, "tiny");
  EXPECT_EQ(tiny->comment, "three nodes");
  ASSERT_EQ(tiny->costs.size(), 3u);
  EXPECT_EQ(tiny->costs(0, 2), 2.0);
  EXPECT_EQ(tiny->costs(1, 0), 3.0);
  EXPECT_EQ(tiny->costs(2, 1), 6.0);
}

TEST(Tsplib, LoadsEveryShippedInstanceWithItsDeclaredSize) {
  const std::string dir = std::string(SCANCREW_SOURCE_DIR) + "/data/tsplib_atsp/";
  for (auto [name, n] : {std::pair<const char*, size_t>{"br17", 17},
                         {"ftv33", 34},
                         {"ftv38", 39},
                         {"ftv47", 48},
                         {"ft53", 53},
                         {"ftv55", 56},
                         {"ftv64", 65},
                         {"ft70", 70},
                         {"ftv70", 71},
                         {"kro124p", 100},
                         {"ftv170", 171}}) {
    auto instance = load_tsplib(dir + name + ".atsp");
    ASSERT_TRUE(instance) << instance.error();
    EXPECT_EQ(instance->name, name);
    EXPECT_EQ(instance->costs.size(), n) << name;
  }
}

TEST(Tsplib, NamesTheLineOfANonNumericValue) {
  auto bad = parse(std::string(kHeader) + "0 1 2\n3 x7 5\n6 7 8\n");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error(), "tiny.atsp:9: 'x7' is not a number (EDGE_WEIGHT_SECTION value 5)");
}

TEST(Tsplib, RefusesTooFewAndTooManyValues) {
  auto few = parse(std::string(kHeader) + "0 1 2\n3 4 5\n6 7\nEOF\n");
  ASSERT_FALSE(few);
  EXPECT_EQ(few.error(),
            "tiny.atsp:11: EDGE_WEIGHT_SECTION ends with 8 values; DIMENSION 3 needs 9");
  auto many = parse(std::string(kHeader) + "0 1 2\n3 4 5\n6 7 8 9\n");
  ASSERT_FALSE(many);
  EXPECT_EQ(many.error(), "tiny.atsp:10: more than the 9 values of DIMENSION 3");
}

TEST(Tsplib, RefusesBadHeaders) {
  auto expect_error = [](const std::string& text, const std::string& message) {
    auto r = parse(text);
    ASSERT_FALSE(r) << text;
    EXPECT_EQ(r.error(), message);
  };
  expect_error("NAME: a\nDIMENSION: three\n",
               "tiny.atsp:2: DIMENSION 'three' is not an integer in [1, 4096]");
  expect_error("DIMENSION: 0\n", "tiny.atsp:1: DIMENSION '0' is not an integer in [1, 4096]");
  expect_error("TYPE: CVRP\n", "tiny.atsp:1: TYPE CVRP is not supported; allowed: ATSP, TSP");
  expect_error("EDGE_WEIGHT_TYPE: EUC_2D\n",
               "tiny.atsp:1: EDGE_WEIGHT_TYPE EUC_2D is not supported; allowed: EXPLICIT");
  expect_error("EDGE_WEIGHT_FORMAT: UPPER_ROW\n",
               "tiny.atsp:1: EDGE_WEIGHT_FORMAT UPPER_ROW is not supported; allowed: FULL_MATRIX");
  expect_error("NAME: a\nEDGE_WEIGHT_SECTION\n1\n",
               "tiny.atsp:2: EDGE_WEIGHT_SECTION before DIMENSION");
  expect_error("NAME: a\nDIMENSION: 2\n", "tiny.atsp:2: no EDGE_WEIGHT_SECTION");
  expect_error("NAME: a\nhello world\n",
               "tiny.atsp:2: expected 'KEYWORD: value' or EDGE_WEIGHT_SECTION, got 'hello world'");
  expect_error("NODE_COORD_TYPE: TWOD_COORDS\n",
               "tiny.atsp:1: unsupported keyword 'NODE_COORD_TYPE'");
  expect_error("", "tiny.atsp:0: no EDGE_WEIGHT_SECTION");
}

TEST(Tsplib, RefusesNonFiniteValuesAndAMissingFile) {
  auto nan = parse(std::string(kHeader) + "0 1 2\n3 nan 5\n6 7 8\n");
  ASSERT_FALSE(nan);
  EXPECT_EQ(nan.error(), "tiny.atsp:9: 'nan' is not finite");
  auto missing = load_tsplib("/nonexistent/never.atsp");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error(), "/nonexistent/never.atsp: cannot open");
}

}  // namespace
}  // namespace scancrew::tsga
