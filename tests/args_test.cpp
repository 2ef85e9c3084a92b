// Command-line plumbing: numbers and key=value parameters.
#include <catch2/catch.hpp>

#include "hrbench/hrbench.h"
#include "util/args.h"
#include "util/format.h"

using namespace hrbench;

TEST_CASE("Numbers parse strictly", "[args]") {
    CHECK(ParseDouble("0.25", "x") == 0.25);
    CHECK(ParseDouble("1e-3", "x") == 1e-3);
    for (const char *bad : {"", "abc", "1.5x", "nan", "inf", "-inf", "1e999"})
        CHECK_THROWS_AS(ParseDouble(bad, "x"), InputError);
    CHECK_THROWS_WITH(ParseDouble("abc", "--eps"), Catch::Contains("--eps"));
    // Out of double precision, each end named for what it is.
    CHECK_THROWS_WITH(ParseDouble("1e400", "l"), Catch::Contains("'1e400' overflows double"));
    CHECK_THROWS_WITH(ParseDouble("1e-320", "d"), Catch::Contains("'1e-320' underflows double"));
    CHECK_THROWS_WITH(ParseDouble("nan", "d"), Catch::Contains("not a finite number"));
    CHECK(ParseDouble("2.3e-308", "d") == 2.3e-308);  // the smallest normals still parse
    // Decimal notation only, as written in the documentation.
    CHECK_THROWS_WITH(ParseDouble("0x10", "l"), "l: '0x10' is not a decimal number");
    CHECK_THROWS_WITH(ParseDouble(" 5", "l"), "l: ' 5' is not a decimal number");
    CHECK(ParseInt("12", "n") == 12);
    for (const char *bad : {"-1", "1.5", "1e20"})
        CHECK_THROWS_AS(ParseInt(bad, "n"), InputError);
}

TEST_CASE("Parameters are key=value words with finite values", "[args]") {
    ParamMap p = ParseParams({"l=64", "d=0.5"});
    CHECK(p.at("l") == 64);
    CHECK(p.at("d") == 0.5);
    CHECK_THROWS_WITH(ParseParams({"l=1", "l=2"}), Catch::Contains("twice"));
    CHECK_THROWS_AS(ParseParams({"l=abc"}), InputError);
    CHECK_THROWS_AS(ParseParams({"=3"}), InputError);
    CHECK(IsParamWord("l=3"));
    CHECK_FALSE(IsParamWord("--eps=3"));
    CHECK_FALSE(IsParamWord("parallel"));
}

TEST_CASE("Doubles print in the shortest form that reads back exactly", "[args]") {
    for (double v : {0.1, 64.0, 1.0 / 3, 1e-300, -2.5})
        CHECK(std::stod(FormatDouble(v)) == v);
    CHECK(FormatDouble(0.25) == "0.25");
    CHECK(FormatDouble(64) == "64");
}
