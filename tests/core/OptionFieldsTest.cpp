// OptionFields: one key list for loading and saving, the section honoured, enums parsed once.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "smap/core/InputError.h"
#include "smap/core/OptionFields.h"

using namespace smap;

namespace
{
enum class Colour
{
    Red,
    Green
};

struct Options
{
    double ratio = 0.5;
    int count = 3;
    bool on = true;
    std::string name = "x";
    Colour colour = Colour::Red;

    core::OptionFields fields(const std::string& section)
    {
        core::OptionFields f(section, "options");
        f.add("ratio", ratio).add("count", count).add("on", on).add("name", name);
        f.addEnum("colour", colour, {{"red", Colour::Red}, {"green", Colour::Green}});
        return f;
    }
};
}  // namespace

TEST(OptionFields, SavedKeysLoadBackToTheSameValues)
{
    Options a;
    a.ratio = 0.25;
    a.count = 7;
    a.on = false;
    a.name = "seven";
    a.colour = Colour::Green;
    mrpt::config::CConfigFileMemory cfg;
    a.fields("").save(cfg);
    Options b;
    b.fields("").load(cfg);
    EXPECT_EQ(b.ratio, 0.25);
    EXPECT_EQ(b.count, 7);
    EXPECT_FALSE(b.on);
    EXPECT_EQ(b.name, "seven");
    EXPECT_EQ(b.colour, Colour::Green);
    EXPECT_EQ(cfg.read_string("options", "colour", ""), "green");
}

TEST(OptionFields, TheSectionGivenIsHonoured)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("other", "count", 11);
    cfg.write("options", "count", 5);
    Options o;
    o.fields("other").load(cfg);
    EXPECT_EQ(o.count, 11);
    o.fields("").load(cfg);
    EXPECT_EQ(o.count, 5);
}

TEST(OptionFields, AnUnknownEnumNameListsTheValidOnes)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("options", "colour", "blue");
    Options o;
    try
    {
        o.fields("").load(cfg);
        FAIL() << "'blue' was accepted";
    }
    catch (const core::InputError& e)
    {
        EXPECT_STREQ(e.what(), "[options] colour = 'blue' is not one of: red, green");
    }
    EXPECT_EQ(o.colour, Colour::Red);
}
