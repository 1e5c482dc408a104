#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "smap/core/JsonWriter.h"

using smap::core::JsonValue;

TEST(JsonWriter, WritesOrderedKeysAndRoundTripNumbers)
{
    auto j = JsonValue::object();
    j.set("b", 0.1).set("a", 3).set("s", "x\"y\\z\n").set("t", true);
    auto arr = JsonValue::array();
    arr.push(JsonValue::number(1.5))
        .push(JsonValue::number(std::numeric_limits<double>::quiet_NaN()));
    j.set("arr", arr);
    j.set("b", 0.30000000000000004);  // replaces in place
    const std::string s = j.dump(0);
    EXPECT_EQ(s,
              "{\n\"b\": 0.30000000000000004,\n\"a\": 3,\n\"s\": \"x\\\"y\\\\z\\n\",\n\"t\": "
              "true,\n\"arr\": [\n1.5,\nnull\n]\n}\n");
}

TEST(JsonWriter, EmptyContainers)
{
    EXPECT_EQ(JsonValue::object().dump(), "{}\n");
    EXPECT_EQ(JsonValue::array().dump(), "[]\n");
}
