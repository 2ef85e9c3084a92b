// The progress line of long runs: its text, its display on a stream (delayed, rewritten
// in place, erased at the end), and the refinement's hook, which must not change counts.
#include <catch2/catch.hpp>

#include <cstdio>
#include <string>
#include <thread>

#include "generators.h"
#include "hrbench/hrbench.h"
#include "refine/progress.h"

using namespace hrbench;

namespace {

// Everything written to _file_ so far.
std::string Contents(std::FILE *file) {
    std::fflush(file);
    std::rewind(file);
    std::string text;
    for (int c; (c = std::fgetc(file)) != EOF;)
        text += char(c);
    return text;
}

}  // namespace

TEST_CASE("The progress line names the root pair, the pass and the elapsed time", "[progress]") {
    CHECK(ProgressLine(0, 0, 136, 0.04) == "starting, 0.0 s");
    CHECK(ProgressLine(1, 5, 136, 2.25) == "root pair 5 of 136 (first pass), 2.2 s");
    CHECK(ProgressLine(2, 37, 136, 12.44) == "root pair 37 of 136, 12.4 s");
    CHECK(ProgressLine(2, 37, 0, 12.44) == "root pair 37, 12.4 s");  // --clusters: unknown
}

TEST_CASE("The display waits for its delay, rewrites one line and erases it", "[progress]") {
    RefineProgress progress;
    progress.rootPairs = 3;
    progress.StartPass(2);
    progress.At(2);
    std::FILE *out = std::tmpfile();
    REQUIRE(out);
    SECTION("a run shorter than the delay prints nothing") {
        { ProgressDisplay display(progress, out, std::chrono::milliseconds(60000)); }
        CHECK(Contents(out).empty());
    }
    SECTION("a longer one rewrites its line in place, then erases it") {
        {
            ProgressDisplay display(progress, out, std::chrono::milliseconds(0),
                                    std::chrono::milliseconds(10));
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        std::string text = Contents(out);
        CHECK(text.rfind("\rhrbench: root pair 2 of 3, ", 0) == 0);
        CHECK(text.find('\n') == std::string::npos);
        REQUIRE(text.size() >= 4);
        CHECK(text.substr(text.size() - 4) == "\r\033[K");
    }
    std::fclose(out);
}

TEST_CASE("The progress hook leaves counts alone and ends in the last pass", "[progress]") {
    Scene scene = MakeScene("cornell", {});
    RefineOptions options;
    options.eps = 0.05;
    options.minArea = 1e-3;
    options.storeLinks = false;
    for (int threads : {1, 3}) {
        INFO("threads " << threads);
        options.threads = threads;
        options.progress = nullptr;
        Refinement<Polygon> plain = Refine<Polygon>(scene, options);
        RefineProgress progress;
        options.progress = &progress;
        Refinement<Polygon> watched = Refine<Polygon>(scene, options);
        CHECK(watched.record.counters.links == plain.record.counters.links);
        CHECK(watched.record.counters.oracleCalls == plain.record.counters.oracleCalls);
        CHECK(watched.record.counters.nodes == plain.record.counters.nodes);
        CHECK(progress.rootPairs == 136);  // 17 patches
        CHECK(progress.pass == 2);
        // The pair of the last task (on one thread, of the only pass, which leaves no
        // task): some refined pair, counted among all root pairs.
        CHECK(progress.pair >= 1);
        CHECK(progress.pair <= 136);
    }
}
