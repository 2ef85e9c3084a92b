// The C kernel of examples/c_kernel (C99, hrbench/probe_c.h, conventions of its own): its
// dump of the worked example, record for record; on plates l=64 its final links against
// hrbench's (one per direction, ties split the other way) and its oracle calls against
// the two-pass count; and `hrbench check-links` judging its dumps on their conventions.
#include <catch2/catch.hpp>

#include <cstdio>
#include <set>
#include <sstream>
#include <string>

#include "cli_helpers.h"

using namespace hrbench_test;

namespace {

std::string RunCKernel(const std::string &args) {
    return RunOk(std::string(HRBENCH_C_KERNEL) + " " + args);
}

// The links a dump ends with: link lines less the links its unlink lines remove, and the
// number of links made before the marker of pass 2.
struct FinalLinks {
    std::multiset<std::string> links;
    size_t firstPass = 0;
};

FinalLinks Final(const std::string &dump) {
    FinalLinks f;
    std::istringstream in(dump);
    bool second = false;
    for (std::string line; std::getline(in, line);) {
        if (line == "pass 2")
            second = true;
        if (line.rfind("unlink ", 0) == 0) {
            auto it = f.links.find(line.substr(7));
            REQUIRE(it != f.links.end());
            f.links.erase(it);
        } else if (!line.empty() && line[0] >= '0' && line[0] <= '9') {
            f.links.insert(line);
            f.firstPass += !second;
        }
    }
    return f;
}

// "0/0110" -> "1/0110": the same element of the other plate (the plates of `parallel`
// map onto each other, orientation included, by the half turn about their centre).
std::string OtherPlate(const std::string &token) {
    return (token[0] == '0' ? "1" : "0") + token.substr(1);
}

}  // namespace

TEST_CASE("the C kernel's dump of the worked example, record for record", "[c-kernel]") {
    std::string dump = Scratch("ck_worked.dump");
    CHECK(RunCKernel("0.5 parallel 1 1 " + dump) ==
          "links 8\noracle_calls 14\ntotal_oracle_calls 16\nnodes 6\nmax_depth 1\nunlinks 2\n");
    // Pass 1 at 4 eps = 2 links the roots in each direction; pass 2 at 0.5 refuses both,
    // removes them and splits the source (a tie), then the receiver: the quarters.
    CHECK(ReadFile(dump) == "hrbench-link-dump 2\n"
                            "conventions links=directed tie=source cull=elements oracle=garmann\n"
                            "decide 0 1 accept\n0 1\n"
                            "decide 1 0 accept\n1 0\n"
                            "pass 2\n"
                            "decide 0 1 split 1\nunlink 0 1\n"
                            "decide 0 1/0 split 0\n"
                            "decide 0/0 1/0 accept\n0/0 1/0\ndecide 0/1 1/0 accept\n0/1 1/0\n"
                            "decide 0 1/1 split 0\n"
                            "decide 0/0 1/1 accept\n0/0 1/1\ndecide 0/1 1/1 accept\n0/1 1/1\n"
                            "decide 1 0 split 0\nunlink 1 0\n"
                            "decide 1 0/0 split 1\n"
                            "decide 1/0 0/0 accept\n1/0 0/0\ndecide 1/1 0/0 accept\n1/1 0/0\n"
                            "decide 1 0/1 split 1\n"
                            "decide 1/0 0/1 accept\n1/0 0/1\ndecide 1/1 0/1 accept\n1/1 0/1\n"
                            "counters links=8 oracle_calls=14 total_oracle_calls=16 passes=2 "
                            "nodes=6 forced_links=0 max_depth=1\n");
}

TEST_CASE("the C kernel ends with hrbench's links in both directions", "[c-kernel]") {
    std::string ours = Scratch("ck64.dump"), theirs = Scratch("ck64_hrbench.dump");
    std::string counts = RunCKernel("0.25 parallel 64 1 " + ours);
    REQUIRE(Cli("links parallel l=64 d=1 --eps 0.25 --format probe --out " + theirs).exitCode == 0);
    FinalLinks f = Final(ReadFile(ours));
    // hrbench's link "0/y 1/x" is the kernel's "1/x 0/y" (receiver Q, source P: a tie
    // splits P in both) and, by the half turn, its "0/x 1/y" (receiver P, source Q).
    std::multiset<std::string> expected;
    std::istringstream in(ReadFile(theirs));
    size_t hrbenchLinks = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] < '0' || line[0] > '9')
            continue;
        std::string p = line.substr(0, line.find(' ')), q = line.substr(line.find(' ') + 1);
        expected.insert(q + " " + p);
        expected.insert(OtherPlate(q) + " " + OtherPlate(p));
        ++hrbenchLinks;
    }
    CHECK(hrbenchLinks == 5092);
    CHECK(f.links == expected);
    // A pair refused at 4 eps is refused at eps, so the calls are those of one pass at
    // eps (2 L - 1 per direction) and one more for each link of pass 1, all of which
    // pass 2 refuses here; pass 2 makes all but the first pass's calls.
    // (Pass 1 makes 2 L1 - 1 calls per direction, L1 its links in that direction.)
    size_t pass1 = 2 * f.firstPass - 2, total = 2 * (2 * 5092 - 1) + f.firstPass;
    CHECK(f.firstPass == 380);
    CHECK(counts == "links 10184\noracle_calls " + std::to_string(total - pass1) +
                        "\ntotal_oracle_calls " + std::to_string(total) +
                        "\nnodes 1022\nmax_depth 8\nunlinks 380\n");
}

TEST_CASE("check-links accepts the C kernel's dumps on their conventions", "[c-kernel]") {
    std::string small = Scratch("ck_small.dump"), plates = Scratch("ck_plates.dump");
    RunCKernel("0.5 parallel 1 1 " + small);
    RunCKernel("0.25 parallel 64 1 " + plates);
    CliResult r = Cli("check-links parallel l=1 d=1 --eps 0.5 --links " + small);
    INFO(r.err);
    CHECK(r.exitCode == 0);
    r = Cli("check-links parallel l=64 d=1 --eps 0.25 --links " + plates);
    INFO(r.err);
    CHECK(r.exitCode == 0);

    // 30 segments, read from the scene file hrbench writes: element pairs are culled.
    std::string scene = Scratch("ck_random.json"), random = Scratch("ck_random.dump");
    REQUIRE(Cli("save random n=30 seed=3 --out " + scene).exitCode == 0);
    RunCKernel("0.05 " + scene + " " + random);
    CHECK(ReadFile(random).find(" cull\n") != std::string::npos);
    r = Cli("check-links --scene-file " + scene + " --eps 0.05 --links " + random);
    INFO(r.err);
    CHECK(r.exitCode == 0);
}
