#include <gtest/gtest.h>

#include "smap/apps/CommandLine.h"
#include "smap/core/InputError.h"

using smap::apps::CommandLine;

TEST(CommandLine, ParsesPositionalsOptionsAndFlags)
{
    CommandLine cl;
    cl.option("out").option("set").flag("quiet");
    cl.parse({"in.rawlog", "--out", "dir", "--set=a.b=1", "--set", "c.d=2", "--quiet"});
    ASSERT_EQ(cl.positionals().size(), 1u);
    EXPECT_EQ(cl.positionals()[0], "in.rawlog");
    EXPECT_EQ(cl.value("out").value(), "dir");
    EXPECT_EQ(cl.values("set"), (std::vector<std::string>{"a.b=1", "c.d=2"}));
    EXPECT_TRUE(cl.has("quiet"));
    EXPECT_FALSE(cl.value("missing").has_value());
}

TEST(CommandLine, RejectsUnknownOptionsAndBadValues)
{
    CommandLine a;
    a.option("out");
    EXPECT_THROW(a.parse({"--outt", "x"}), smap::core::InputError);
    CommandLine b;
    b.option("out");
    EXPECT_THROW(b.parse({"--out"}), smap::core::InputError);
    CommandLine c;
    c.option("delta").flag("scale");
    EXPECT_THROW(c.parse({"--scale=1"}), smap::core::InputError);
    c.parse({"--delta", "1.5x"});
    EXPECT_THROW(c.number("delta", 1.0), smap::core::InputError);
    EXPECT_THROW(c.integer("delta", 1), smap::core::InputError);
}
