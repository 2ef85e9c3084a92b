// The link dump as an input (hrbench/link_dump.h): the probe's dump format and the
// reader, line numbers in every message. `hrbench check-links` on dumps is
// check_links_test.cpp's; these cases need no executable, and run in the sanitizer build
// of `make test` (the CTest label core).
#include <catch2/catch.hpp>

#include <sstream>
#include <string>

#include "hrbench/hrbench.h"
#include "hrbench/link_dump.h"
#include "hrbench/probe.h"

namespace {

// The dump of `parallel l=1 d=1 --eps 0.5`, worked by hand in docs/conventions.md: P is
// split first (a tie), then Q, and the four quarters are linked.
const std::string kHeader = "hrbench-link-dump 1\n";
const std::string kQuarters = "0/0 1/0\n0/0 1/1\n0/1 1/0\n0/1 1/1\n";

hrbench::LinkDump Parse(const std::string &text, int arity = 2, size_t patches = 2) {
    std::istringstream in(text);
    return hrbench::ReadLinkDump(in, "d", arity, patches);
}

}  // namespace

TEST_CASE("the probe counts as hrbench does and writes the dump format", "[check-links]") {
    using namespace hrbench::probe;
    ElementPath p = ElementPath::Root(0), q = ElementPath::Root(1);
    CHECK(p.ToString() == "0");
    CHECK(q.Child(1).Child(0).ToString() == "1/10");
    CHECK(q.Child(1).Child(0).Depth() == 2);

    std::ostringstream dump;
    Probe probe(&dump);
    for (int d : {0, 0, 1, 1, 1, 1})
        probe.ElementCreated(d);
    for (int k = 0; k < 7; ++k)
        probe.OracleCall();
    for (int a : {0, 1})
        for (int b : {0, 1})
            probe.Link(p.Child(a), q.Child(b), a == 1 && b == 1);
    probe.Finish();
    CHECK(dump.str() == kHeader + kQuarters +
                            "counters links=4 oracle_calls=7 nodes=6 forced_links=1 max_depth=1\n");
    CHECK(probe.Counts().links == 4);
    CHECK(probe.Counts().forcedLinks == 1);

    Probe counting;  // no dump: counts only
    counting.Link(p, q);
    CHECK(counting.Counts().links == 1);
}

TEST_CASE("a link dump is read with its line numbers", "[check-links]") {
    hrbench::LinkDump d =
        Parse(kHeader + "# comment\n\n  1/01\t0  \n0/1 1/0\r\ncounters links=2 nodes=6\n");
    REQUIRE(d.links.size() == 2);
    CHECK(d.links[0].line == 4);
    CHECK(d.Name(d.links[0].i) == "0");  // written j first: ordered by root
    CHECK(d.Name(d.links[0].j) == "1/01");
    CHECK(d.Digit(d.links[0].j, 1) == 1);
    CHECK(d.Name(d.links[1].j) == "1/0");
    CHECK(d.countersLine == 6);
    CHECK(d.counters == std::vector<std::pair<std::string, uint64_t>>{{"links", 2}, {"nodes", 6}});

    auto rejects = [](const std::string &text, const std::string &message, int arity = 2) {
        INFO(text);
        CHECK_THROWS_WITH(Parse(text, arity), message);
    };
    rejects("", "d:1: empty file; a link dump starts with 'hrbench-link-dump 1' or "
                "'hrbench-link-dump 2'");
    rejects("root_i,elem_i\n", "d:1: not a link dump: the first line must be "
                               "'hrbench-link-dump 1' or 'hrbench-link-dump 2' (the "
                               "versions this engine reads)");
    // A version-2 dump with a damaged header is told both versions, not only 1.
    rejects("hrbench-link-dump 2x\n", "d:1: not a link dump: the first line must be "
                                      "'hrbench-link-dump 1' or 'hrbench-link-dump 2' (the "
                                      "versions this engine reads)");
    rejects(kHeader + "0/0 1/0\n0/2 1\n",
            "d:3: bad element '0/2': path digits must be 0 to 1 with 2 children per element");
    rejects(kHeader + "0/3 1\n",
            "d:2: bad element '0/3': path digits must be 0 to 2 with 3 "
            "children per element",
            3);
    rejects(kHeader + "0/1 2\n", "d:2: element '2': the scene has no patch 2 (2 patches)");
    rejects(kHeader + "0/ 1\n", "d:2: bad element '0/': empty path after '/'");
    rejects(kHeader + "-1 1\n", "d:2: bad element '-1': expected ROOT or ROOT/PATH");
    rejects(kHeader + "0 1 1\n", "d:2: expected a link, two elements ROOT or ROOT/PATH, or a "
                                 "counters line; got 3 fields");
    rejects(kHeader + "0/" + std::string(49, '0') + " 1\n",
            "d:2: element '0/" + std::string(49, '0') + "' is deeper than the safety depth 48");
    rejects(kHeader + "counters links=1\ncounters links=1\n",
            "d:3: a second counters line (the first is line 2)");
    CHECK_THROWS_WITH(Parse(kHeader + "counters leaves=1\n"),
                      Catch::Contains("d:2: unknown counter 'leaves'"));
    rejects(kHeader + "counters links=x\n", "d:2: counter links needs a whole number, as links=12");
    rejects(kHeader + "counters links=1 links=1\n", "d:2: counter links is given twice");
    // Any counter a run can report, up to 2^64 - 1, and nothing beyond it.
    hrbench::LinkDump largest = Parse(kHeader + "counters links=18446744073709551615 nodes=007\n");
    CHECK(largest.counters ==
          std::vector<std::pair<std::string, uint64_t>>{{"links", UINT64_MAX}, {"nodes", 7}});
    rejects(kHeader + "counters links=18446744073709551616\n",
            "d:2: counter links=18446744073709551616 is beyond 2^64 - 1 = "
            "18446744073709551615, the largest counter");
    rejects(kHeader + "counters nodes=" + std::string(30, '9') + "\n",
            "d:2: counter nodes=" + std::string(30, '9') +
                " is beyond 2^64 - 1 = 18446744073709551615, the largest counter");
    rejects(kHeader + "counters links=+1\n",
            "d:2: counter links needs a whole number, as links=12");
}

TEST_CASE("conventions read alike with spaces or commas between tokens", "[check-links]") {
    using Tokens = std::vector<std::pair<std::string, std::string>>;
    Tokens tokens = {{"links", "directed"}, {"tie", "receiver"}, {"hrbench", ""}};
    CHECK(hrbench::ParseConventionTokens("links=directed tie=receiver hrbench") == tokens);
    CHECK(hrbench::ParseConventionTokens("links=directed,tie=receiver,hrbench") == tokens);
    CHECK(hrbench::ParseConventionTokens(" links=directed, tie=receiver\thrbench ,") == tokens);
    CHECK(hrbench::ParseConventionTokens("").empty());
    hrbench::LinkDump d = Parse("hrbench-link-dump 2\nconventions links=directed,tie=receiver\n");
    CHECK(d.conventions == Tokens{{"links", "directed"}, {"tie", "receiver"}});
}
