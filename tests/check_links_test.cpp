// The probe (hrbench/probe.h), the link dump and `hrbench check-links`: it accepts the
// dumps of hrbench and of the independent kernel of examples/tiny_kernel, and rejects a
// missing, an overlapping and an unacceptable link, each with its line and exit code 4.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>

#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "hrbench/probe.h"
#include "hrbench/scene_io.h"
#include "visibility/culling.h"

using namespace hrbench_test;

namespace {

// The dump of `parallel l=1 d=1 --eps 0.5`, worked by hand in docs/conventions.md: P is
// split first (a tie), then Q, and the four quarters are linked.
const std::string kHeader = "hrbench-link-dump 1\n";
const std::string kQuarters = "0/0 1/0\n0/0 1/1\n0/1 1/0\n0/1 1/1\n";
const std::string kSmall = "check-links parallel l=1 d=1 --eps 0.5 --links ";

std::string WriteScratch(const std::string &name, const std::string &text) {
    std::string path = Scratch(name);
    std::ofstream(path) << text;
    return path;
}

// The link lines of a dump, without the header and the counters line.
std::multiset<std::string> LinkLines(const std::string &dump) {
    std::multiset<std::string> lines;
    std::istringstream in(dump);
    for (std::string line; std::getline(in, line);)
        if (line != "hrbench-link-dump 1" && line.rfind("counters", 0) != 0)
            lines.insert(line);
    return lines;
}

// Runs the tiny kernel on parallel plates l, d with _eps_; returns its standard output.
std::string RunTinyKernel(const std::string &args) {
    return RunOk(std::string(HRBENCH_TINY_KERNEL) + " " + args);
}

hrbench::LinkDump Parse(const std::string &text, int arity = 2, size_t patches = 2) {
    std::istringstream in(text);
    return hrbench::ReadLinkDump(in, "d", arity, patches);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// The probe and the dump format

TEST_CASE("check-links accepts hrbench's own dumps, 2D and 3D", "[check-links]") {
    std::string dump = Scratch("own.dump");
    for (std::string config :
         {"parallel l=64 d=1 --eps 0.25", "room w=2 h=1 --eps 0.1 --min-area 0.01",
          "enclosure n=6 --eps 0.2 --max-depth 6", "cornell --eps 0.5 --min-area 0.001",
          "parallel3d --eps 0.5 --subdivision quadtree",
          "angled l=1.9 angle=37.3 gap=0.07 --eps 0.231"}) {
        INFO(config);
        REQUIRE(Cli("links " + config + " --format probe --threads 2 --out " + dump).exitCode == 0);
        CliResult r = Cli("check-links " + config + " --links " + dump);
        CHECK(r.exitCode == 0);
        CHECK(r.err.empty());
        CHECK_THAT(r.out, Catch::Contains(": ok: "));
    }

    // The numbers of the README's example, from the links, hrbench and the counters line.
    Cli("links parallel l=64 d=1 --eps 0.25 --format probe --out " + dump);
    CliResult r = Cli("check-links parallel l=64 d=1 --eps 0.25 --links " + dump);
    CHECK_THAT(r.out, Catch::Contains("5092 links tile the 1 refined root pair exactly"));
    CHECK_THAT(r.out,
               Catch::Contains("links                    5092           5092           5092"));
    CHECK_THAT(r.out,
               Catch::Contains("oracle_calls            10183          10183          10183"));
    CHECK_THAT(r.out,
               Catch::Contains("nodes                    1022           1022           1022"));

    // Culled pairs are counted and skipped: the Cornell box has 55 of its 136.
    Cli("links cornell --eps 0.5 --min-area 0.001 --format probe --out " + dump);
    r = Cli("check-links cornell --eps 0.5 --min-area 0.001 --links " + dump);
    CHECK_THAT(r.out,
               Catch::Contains("5792 links tile the 81 refined root pairs exactly (55 culled)"));
    CHECK_THAT(r.out,
               Catch::Contains("forced_links             1086           1086           1086"));
}

TEST_CASE("the tiny kernel counts as hrbench and check-links accepts its dump", "[check-links]") {
    std::string tiny = Scratch("tiny.dump"), own = Scratch("own64.dump");
    CHECK(RunTinyKernel("64 1 0.25 " + tiny) ==
          "links 5092\noracle_calls 10183\nnodes 1022\nmax_depth 8\n");
    CliResult r = Cli("check-links parallel l=64 d=1 --eps 0.25 --links " + tiny);
    CHECK(r.exitCode == 0);
    CHECK_THAT(r.out, Catch::Contains("5092 links tile"));
    // The same links as hrbench's (hrbench orders them by its worker tasks).
    Cli("links parallel l=64 d=1 --eps 0.25 --format probe --out " + own);
    CHECK(LinkLines(ReadFile(tiny)) == LinkLines(ReadFile(own)));

    // Plates 1 by 1: the four quarters of the worked example, in ProjectKernel's order.
    RunTinyKernel("1 1 0.5 " + tiny);
    CHECK(ReadFile(tiny) == kHeader + kQuarters +
                                "counters links=4 oracle_calls=7 nodes=6 forced_links=0 "
                                "max_depth=1\n");
}

// ---------------------------------------------------------------------------------------
// Violations: one line on stderr, exit code 4

TEST_CASE("check-links rejects a missing link", "[check-links]") {
    std::string path = WriteScratch("missing.dump", kHeader + "0/0 1/0\n0/0 1/1\n0/1 1/1\n");
    CheckError(kSmall + path, hrbench::kExitViolation,
               "missing.dump: missing link: nothing covers the element pair 0/1 1/0 of "
               "patches 0 and 1");
    // A whole root pair without links.
    path = WriteScratch("empty.dump", kHeader);
    CheckError(kSmall + path, hrbench::kExitViolation,
               "missing link: nothing covers the element pair 0 1");

    // One link line less in the tiny kernel's dump: the gap is that link.
    std::string tiny = Scratch("tiny_missing.dump");
    RunTinyKernel("64 1 0.25 " + tiny);
    std::istringstream in(ReadFile(tiny));
    std::string text, line, dropped;
    for (int k = 1; std::getline(in, line); ++k)
        (k == 100 ? dropped : text) += line + "\n";
    WriteScratch("tiny_missing.dump", text);
    CheckError("check-links parallel l=64 d=1 --eps 0.25 --links " + tiny, hrbench::kExitViolation,
               "missing link: nothing covers the element pair " +
                   dropped.substr(0, dropped.size() - 1) + " of patches 0 and 1");
}

TEST_CASE("check-links rejects an overlapping link", "[check-links]") {
    // The right half of P against all of Q, on top of two quarters.
    std::string path = WriteScratch("overlap.dump", kHeader + kQuarters + "0/1 1\n");
    CheckError(kSmall + path, hrbench::kExitViolation,
               "overlap.dump:6: overlapping links: 0/1 1 overlaps 0/1 1/0 of line 4");
    // A link given twice.
    path = WriteScratch("twice.dump", kHeader + kQuarters + "1/1 0/0\n");
    CheckError(kSmall + path, hrbench::kExitViolation,
               "twice.dump:6: overlapping links: 0/0 1/1 overlaps 0/0 1/1 of line 3");
    // Crossing links, neither inside the other: P's left half against Q, Q's left half
    // against P.
    path = WriteScratch("cross.dump", kHeader + "0/0 1\n0 1/0\n0/1 1/1\n");
    CheckError(kSmall + path, hrbench::kExitViolation,
               "cross.dump:3: overlapping links: 0 1/0 overlaps 0/0 1 of line 2");
}

TEST_CASE("check-links rejects an unacceptable link", "[check-links]") {
    // P's left half against all of Q: max(0.5, 1) = 1 > 0.5 * 1.031, refused.
    std::string path = WriteScratch("refused.dump", kHeader + "0/0 1\n0/1 1/0\n0/1 1/1\n");
    CheckError(kSmall + path, hrbench::kExitViolation,
               "refused.dump:2: unacceptable link: 0/0 1 is refused by the oracle garmann "
               "(eps 0.5) and no recursion limit forces it");
    // Links below a pair the oracle accepts: with eps 2, P and Q are linked whole.
    path = WriteScratch("quarters.dump", kHeader + kQuarters);
    CheckError("check-links parallel l=1 d=1 --eps 2 --links " + path, hrbench::kExitViolation,
               "quarters.dump:2: unacceptable link: 0/0 1/0 lies below the pair 0 1, which the "
               "oracle garmann (eps 2) accepts");
    // ... or below a pair where a recursion limit forces a link.
    CheckError(kSmall + path + " --max-depth 0", hrbench::kExitViolation,
               "quarters.dump:2: unacceptable link: 0/0 1/0 lies below the pair 0 1, where "
               "--max-depth 0 forces a link");
    // A tiling that splits Q first, where the tie splits P.
    path = WriteScratch("q_first.dump", kHeader + "0 1/0\n0 1/1\n");
    CheckError(kSmall + path, hrbench::kExitViolation,
               "q_first.dump:2: link off the subdivision: 0 1/0 keeps element 0 whole, but "
               "ProjectKernel splits it in the refused pair 0 1");
    // The tiny kernel's links for eps 0.25 are too coarse for eps 0.2.
    std::string tiny = Scratch("tiny_eps.dump");
    RunTinyKernel("64 1 0.25 " + tiny);
    CheckError("check-links parallel l=64 d=1 --eps 0.2 --links " + tiny, hrbench::kExitViolation,
               "is refused by the oracle garmann (eps 0.2) and no recursion limit forces it");
}

TEST_CASE("check-links rejects wrong counters and links outside the refined pairs",
          "[check-links]") {
    std::string path = WriteScratch("counts.dump", kHeader + kQuarters +
                                                       "counters links=4 oracle_calls=8 nodes=6\n");
    CheckError(kSmall + path, hrbench::kExitViolation,
               "counts.dump:6: counts: the counters line says oracle_calls=8, the links give 7");
    path = WriteScratch("self.dump", kHeader + "0/0 0/1\n");
    CheckError(kSmall + path, hrbench::kExitViolation,
               "self.dump:2: link within one patch: 0/0 0/1 (both elements of patch 0)");

    // A link between the first culled pair of the Cornell box, which is never refined.
    hrbench::Scene scene = hrbench::MakeScene("cornell", {});
    hrbench::RefineOptions options;
    options.eps = 0.5;
    options.minArea = 0.001;
    bool foundCulled = false;
    const auto &patches = scene.Get<hrbench::Polygon>();
    for (uint32_t p = 0; p < patches.size() && !foundCulled; ++p)
        for (uint32_t q = p + 1; q < patches.size() && !foundCulled; ++q) {
            if (hrbench::ClassifyPair(patches[p].shape, patches[q].shape) !=
                hrbench::PairRelation::Culled)
                continue;
            foundCulled = true;
            std::string text = kHeader + std::to_string(p) + " " + std::to_string(q) + "\n";
            hrbench::LinkDump dump = Parse(text, 2, patches.size());
            CHECK_THROWS_WITH(hrbench::CheckLinks(scene, options, dump),
                              Catch::Contains("d:2: link between a culled pair: " +
                                              std::to_string(p) + " " + std::to_string(q)));
        }
    CHECK(foundCulled);
}

TEST_CASE("check-links refuses malformed dumps and bad usage with exit code 2", "[check-links]") {
    std::string path = WriteScratch("bad.dump", kHeader + kQuarters + "0/1 1/2\n");
    CheckError(kSmall + path, 2, "bad.dump:6: bad element '1/2'");
    path = WriteScratch("csv.dump", "root_i,elem_i,t0_i\n");
    CheckError(kSmall + path, 2, "csv.dump:1: not a link dump");
    CheckError(kSmall + Scratch("absent.dump"), 2, "cannot read link dump");
    CheckError("check-links parallel l=1 d=1 --eps 0.5", 2, "check-links needs --links F");
    CheckError("check-links parallel l=1 d=1 --links x", 2, "check-links needs --eps");
    CheckError("check-links parallel --eps 0.5 --links x --threads 2", 2,
               "--threads does not apply to check-links");
    // What hrbench cannot refine, check-links cannot check: touching walls need a limit.
    path = WriteScratch("room.dump", kHeader + kQuarters);
    CheckError("check-links room --eps 0.5 --links " + path, 2, "touch");
    // A dump is a regular file: a FIFO (which would wait for a writer) and a device are
    // refused before anything is read.
    std::string fifo = Scratch("links.fifo");
    std::remove(fifo.c_str());
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    CheckError(kSmall + fifo, 2,
               "cannot read link dump '" + fifo + "': it is a FIFO, not a regular file");
    CheckError(kSmall + "/dev/zero", 2,
               "cannot read link dump '/dev/zero': it is a character device, not a regular file");
    std::remove(fifo.c_str());
}

TEST_CASE("check-links on a small dump ends quickly however large the scene's refinement",
          "[check-links]") {
    // parallel l=1000 at eps 1e-6 refines to 5.8e15 links (--method translation): the
    // dump is checked first, and its one link is refused at once.
    std::string path = WriteScratch("one.dump", kHeader + "0 1\n");
    [[maybe_unused]] auto start = std::chrono::steady_clock::now();
    CheckError("check-links parallel l=1000 d=1 --eps 1e-6 --links " + path,
               hrbench::kExitViolation,
               "one.dump:2: unacceptable link: 0 1 is refused by the oracle garmann (eps 1e-06)");
    // 9 million refined root pairs (3000 plates facing 3000) and a dump for the first: the
    // second is missing, found without refining the scene or caching every pair's culling
    // (refining it first takes 10 s and 1.2 GB).
    path = WriteScratch("first.dump", kHeader + "0 3000\n");
    CheckError("check-links array k=3000 --eps 100 --links " + path, hrbench::kExitViolation,
               "first.dump: missing link: nothing covers the element pair 0 3001 of patches 0 "
               "and 3001");
#ifndef __SANITIZE_ADDRESS__
    // Every one of the 9 million pairs is visited to count its violation (0.5 s in a
    // release build); the sanitizers make that some 30 times slower, so the bound that
    // tells a scan from a refinement holds only without them.
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(8));
#endif
}

// ---------------------------------------------------------------------------------------
// Version 2: a kernel judged on its own conventions and decisions

namespace {

// A small kernel of its own, on 2D segments, with conventions unlike hrbench's: a link
// per direction (receiver, source), ties split the second patch's element, element
// pairs whose centres face away culled, its own oracle (max(A_r, A_s) <= eps * distance
// of the centres), and two passes: refine at eps 1, then re-evaluate every link at
// eps 0.5, unlinking and refining the refused ones.
class TwoPassKernel {
  public:
    struct Seg {
        double ax, ay, bx, by;
        double nx, ny;  // the root's front normal: (b - a) turned +90 degrees
        hrbench::probe::ElementPath path;
        double Size2() const {
            double dx = bx - ax, dy = by - ay;
            return dx * dx + dy * dy;
        }
        double Cx() const { return 0.5 * (ax + bx); }
        double Cy() const { return 0.5 * (ay + by); }
        Seg Child(int c) const {
            double mx = 0.5 * (ax + bx), my = 0.5 * (ay + by);
            return c == 0 ? Seg{ax, ay, mx, my, nx, ny, path.Child(0)}
                          : Seg{mx, my, bx, by, nx, ny, path.Child(1)};
        }
    };

    TwoPassKernel(std::ostream &out, std::vector<Seg> roots)
        : probe_(&out, "links=directed tie=second cull=elements oracle=own"),
          roots_(std::move(roots)) {
        for (size_t k = 0; k < roots_.size(); ++k)
            Created(roots_[k].path);
    }

    void Run() {
        for (size_t r = 0; r < roots_.size(); ++r)
            for (size_t s = 0; s < roots_.size(); ++s)
                if (r != s)
                    Call(roots_[r], roots_[s], 1.0, false);
        probe_.Pass();
        std::vector<std::pair<Seg, Seg>> live = std::move(links_);
        links_.clear();
        for (const auto &[r, s] : live)
            Call(r, s, 0.5, true);
        probe_.Finish();
    }

  private:
    static bool Faces(const Seg &from, const Seg &to) {
        return from.nx * (to.Cx() - from.Cx()) + from.ny * (to.Cy() - from.Cy()) > 0;
    }
    void Created(const hrbench::probe::ElementPath &path) {
        if (created_.insert(path.ToString()).second)
            probe_.ElementCreated(path.Depth());
    }
    // One call on receiver _r_ and source _s_; _live_ when (r, s) is a link of an
    // earlier pass.
    void Call(const Seg &r, const Seg &s, double eps, bool live) {
        if (!Faces(r, s) || !Faces(s, r))
            return probe_.Cull(r.path, s.path);
        double dx = r.Cx() - s.Cx(), dy = r.Cy() - s.Cy();
        double a = std::sqrt(std::max(r.Size2(), s.Size2()));
        if (a <= eps * std::sqrt(dx * dx + dy * dy)) {
            links_.push_back({r, s});
            return probe_.Accept(r.path, s.path, !live);
        }
        if (live)
            probe_.Unlink(r.path, s.path);
        // The larger element; a tie splits the element of the patch later in the scene.
        bool splitR =
            r.Size2() > s.Size2() || (r.Size2() == s.Size2() && r.path.root > s.path.root);
        const Seg &split = splitR ? r : s;
        probe_.Split(r.path, s.path, split.path);
        for (int c = 0; c < 2; ++c) {
            Seg child = split.Child(c);
            Created(child.path);
            if (splitR)
                Call(child, s, eps, false);
            else
                Call(r, child, eps, false);
        }
    }

    hrbench::probe::Probe probe_;
    std::vector<Seg> roots_;
    std::vector<std::pair<Seg, Seg>> links_;
    std::set<std::string> created_;
};

// P: (0,0) -> (3,0), facing +y; Q: (1,2) -> (1,0.5), facing +x. P's left part lies
// behind Q's line, so the kernel culls element pairs there.
const char *kTeeScene =
    R"({"format": "hrbench-scene", "schema_version": 1, "dimension": 2, "patches": [
        {"a": [0, 0], "b": [3, 0], "reflectance": 1.0},
        {"a": [1, 2], "b": [1, 0.5], "reflectance": 1.0}]})";

std::string TeeDump() {
    using Seg = TwoPassKernel::Seg;
    std::ostringstream out;
    TwoPassKernel kernel(out, {Seg{0, 0, 3, 0, 0, 1, hrbench::probe::ElementPath::Root(0)},
                               Seg{1, 2, 1, 0.5, 1.5, 0, hrbench::probe::ElementPath::Root(1)}});
    kernel.Run();
    return out.str();
}

// The category ids of a check-links --json answer.
std::set<std::string> JsonCategories(const std::string &out) {
    std::set<std::string> ids;
    nlohmann::json j = nlohmann::json::parse(out);
    for (const auto &c : j["categories"])
        ids.insert(c["category"].get<std::string>());
    return ids;
}

// The decisions of `parallel l=1 d=1 --eps 0.5` (docs/conventions.md's worked example),
// hrbench's conventions: P split (a tie, the first), then Q in each half.
const std::string kDecided = "hrbench-link-dump 2\n"
                             "decide 0 1 split 0\n"
                             "decide 0/0 1 split 1\n"
                             "decide 0/0 1/0 accept\n0/0 1/0\n"
                             "decide 0/0 1/1 accept\n0/0 1/1\n"
                             "decide 0/1 1 split 1\n"
                             "decide 0/1 1/0 accept\n0/1 1/0\n"
                             "decide 0/1 1/1 accept\n0/1 1/1\n";

}  // namespace

TEST_CASE("check-links passes a two-pass kernel with its own conventions", "[check-links]") {
    std::string text = TeeDump();
    INFO(text);
    // Both directions refined, culled element pairs, pass 2 unlinking and refining.
    CHECK(text.rfind("hrbench-link-dump 2\nconventions links=directed", 0) == 0);
    CHECK(text.find("decide 1 0 ") != std::string::npos);
    CHECK(text.find(" cull\n") != std::string::npos);
    CHECK(text.find("pass 2\n") != std::string::npos);
    CHECK(text.find("unlink ") != std::string::npos);
    std::string scene = WriteScratch("tee.json", kTeeScene);
    std::string dump = WriteScratch("tee.dump", text);
    // Reflectance 1.0, which no oracle reads: check-links takes the scene.
    CliResult r = Cli("check-links --scene-file " + scene + " --eps 0.5 --links " + dump);
    INFO(r.err);
    CHECK(r.exitCode == 0);
    CHECK_THAT(r.out, Catch::Contains("each direction, exactly"));
    CHECK_THAT(r.out, Catch::Contains("the kernel's own oracle"));
    CHECK(Cli("run --scene-file " + scene + " --eps 0.5").exitCode == 2);
    // The kernel's counters agree with the record; a wrong one is a counter mismatch.
    hrbench::Scene tee = hrbench::SceneFromJson(kTeeScene, "tee", false);
    hrbench::RefineOptions options;
    options.eps = 0.5;
    hrbench::LinkDump parsed = Parse(text, 2, 2);
    hrbench::LinkCheck check = hrbench::CheckLinks(tee, options, parsed);
    CHECK(check.passes == 2);
    CHECK_FALSE(check.engineCompared);
    CHECK(check.fromLinks.links + 0 > 0);
    size_t at = text.find("total_oracle_calls=");
    std::string wrong =
        text.substr(0, at) + "total_oracle_calls=1" + text.substr(text.find(' ', at));
    CliResult bad = Cli("check-links --scene-file " + scene + " --eps 0.5 --links " +
                        WriteScratch("tee_wrong.dump", wrong) + " --json");
    CHECK(bad.exitCode == hrbench::kExitViolation);
    CHECK(JsonCategories(bad.out) == std::set<std::string>{"counter-mismatch"});
    // The same links under hrbench's conventions are not where ProjectKernel links.
    CHECK(Cli("check-links --scene-file " + scene + " --eps 0.5 --links " + dump +
              " --conventions links=undirected")
              .exitCode == 2);  // disagrees with the dump's line
}

TEST_CASE("check-links sums up every violation by category, in text and JSON", "[check-links]") {
    // The decided dump passes, counted against hrbench's refinement.
    std::string ok = WriteScratch("decided.dump", kDecided + "counters links=4 oracle_calls=7 "
                                                             "nodes=6 total_oracle_calls=7 "
                                                             "passes=1\n");
    CliResult r = Cli(kSmall + ok);
    INFO(r.err);
    CHECK(r.exitCode == 0);
    CHECK_THAT(r.out, Catch::Contains("total_oracle_calls"));

    auto expect = [&](const std::string &name, const std::string &text, const std::string &id,
                      const std::string &label) {
        std::string path = WriteScratch(name, text);
        CliResult summary = Cli(kSmall + path + " --summary");
        INFO(summary.out << summary.err);
        CHECK(summary.exitCode == hrbench::kExitViolation);
        CHECK_THAT(summary.out, Catch::Contains(id + " (" + label + "): "));
        CHECK_THAT(summary.err, Catch::Contains(label));
        CliResult json = Cli(kSmall + path + " --json");
        CHECK(json.exitCode == hrbench::kExitViolation);
        CHECK(JsonCategories(json.out).count(id) == 1);
        CHECK(nlohmann::json::parse(json.out)["ok"] == false);
    };
    auto without = [](std::string text, const std::string &line) {
        return text.erase(text.find(line), line.size());
    };
    // The kernel decides to link 0/1 1/0, but no link line says so.
    expect("d_missing.dump", without(kDecided, "0/1 1/0\n"), "missing-link", "missing link");
    // A link on top of two.
    expect("d_overlap.dump", kDecided + "0/1 1\n", "overlapping-link", "overlapping links");
    // The kernel says it splits P, but its links keep P whole.
    expect("d_split.dump",
           "hrbench-link-dump 2\nconventions oracle=own\ndecide 0 1 split 0\n"
           "decide 0 1/0 accept\n0 1/0\ndecide 0 1/1 accept\n0 1/1\n",
           "split-mismatch", "split inconsistent with its decision");
    // A link that the declared oracle, garmann, refuses: 0/0 against all of Q.
    expect("d_refused.dump",
           "hrbench-link-dump 2\nconventions oracle=garmann\ndecide 0 1 split 0\n"
           "decide 0/0 1 accept\n0/0 1\n"
           "decide 0/1 1 split 1\ndecide 0/1 1/0 accept\n0/1 1/0\n"
           "decide 0/1 1/1 accept\n0/1 1/1\n",
           "unacceptable-link", "unacceptable link");

    // Several at once: each category counted, by root pair, the first line on stderr.
    std::string many = WriteScratch("d_many.dump", without(kDecided, "0/1 1/0\n") + "0/0 1\n" +
                                                       "counters links=9\n");
    CliResult all = Cli(kSmall + many + " --json");
    CHECK(all.exitCode == hrbench::kExitViolation);
    auto j = nlohmann::json::parse(all.out);
    CHECK(j["violations"] == 2);
    CHECK(JsonCategories(all.out) == std::set<std::string>{"overlapping-link", "counter-mismatch"});
    CHECK(j["root_pairs"][0]["pair"] == nlohmann::json({0, 1}));
    CHECK(j["root_pairs"][0]["count"] == 1);
    CHECK_THAT(all.err, Catch::Contains("the first of 2 violations"));
}

TEST_CASE("check-links judges --ff-estimate against the oracle in force, the dump's first",
          "[check-links]") {
    const std::string scene = "parallel l=4 d=1 --eps 0.05 ";
    std::string own = Scratch("hanrahan.dump");
    REQUIRE(Cli("links " + scene +
                "--oracle hanrahan --ff-estimate solid-angle --format probe "
                "--out " +
                own)
                .exitCode == 0);
    // The same links, in a dump whose conventions line names the oracle.
    std::string text = ReadFile(own);
    std::string dump = WriteScratch("named.dump", "hrbench-link-dump 2\nconventions "
                                                  "oracle=hanrahan\n" +
                                                      text.substr(text.find('\n') + 1));
    // The dump says oracle=hanrahan: --ff-estimate applies, though --oracle is not given.
    CliResult r = Cli("check-links " + scene + "--ff-estimate solid-angle --links " + dump);
    INFO(r.err);
    CHECK(r.exitCode == 0);
    // Without an oracle in the dump, --oracle's (here the default, garmann) is in force.
    CheckError("check-links " + scene + "--ff-estimate solid-angle --links " + own, 2,
               "--ff-estimate applies to the oracles hanrahan and bf only, not to garmann");
    CheckError("check-links " + scene + "--oracle garmann --ff-estimate solid-angle --links " + own,
               2, "--ff-estimate applies to the oracles hanrahan and bf only, not to garmann");
}

TEST_CASE("check-links --all writes every violation, one line each, in the dump's order",
          "[check-links]") {
    // Each of the four links given twice: four overlaps, of which --summary keeps 3.
    std::string text = "hrbench-link-dump 2\ndecide 0 1 split 0\ndecide 0/0 1 split 1\n"
                       "decide 0/0 1/0 accept\ndecide 0/0 1/1 accept\ndecide 0/1 1 split 1\n"
                       "decide 0/1 1/0 accept\ndecide 0/1 1/1 accept\n";
    for (const char *link : {"0/0 1/0", "0/0 1/1", "0/1 1/0", "0/1 1/1"})
        text += std::string(link) + "\n" + link + "\n";
    std::string path = WriteScratch("d_twice.dump", text);
    CliResult every = Cli(kSmall + path + " --all");
    INFO(every.out << every.err);
    CHECK(every.exitCode == hrbench::kExitViolation);
    std::istringstream lines(every.out);
    std::vector<std::string> got;
    for (std::string line; std::getline(lines, line);)
        got.push_back(line);
    REQUIRE(got.size() == 4);
    for (size_t i = 0; i < got.size(); ++i)
        CHECK_THAT(got[i], Catch::StartsWith(path + ":" + std::to_string(10 + 2 * i) +
                                             ": overlapping links: "));
    CHECK_THAT(every.err, Catch::Contains("the first of 4 violations; --summary or --json lists "
                                          "them, --all every one"));
    CliResult summary = Cli(kSmall + path + " --summary");
    CHECK_THAT(summary.out, Catch::Contains("overlapping-link (overlapping links): 4"));
    CHECK_THAT(summary.out, !Catch::Contains(":16: overlapping"));
    CHECK(Cli(kSmall + path + " --all --json").exitCode == hrbench::kExitInput);
}

TEST_CASE("version 2 dumps: the probe's records and malformed ones", "[check-links]") {
    using namespace hrbench::probe;
    std::ostringstream dump;
    Probe probe(&dump, "split=recorded");
    ElementPath p = ElementPath::Root(0), q = ElementPath::Root(1);
    probe.Split(p, q, q);
    probe.Accept(p, q.Child(0));
    probe.Forced(p, q.Child(1), Limit::MaxDepth);
    probe.Pass();
    probe.Unlink(p, q.Child(1), true);
    probe.Cull(p, q.Child(1));
    probe.Finish();
    CHECK(dump.str() == "hrbench-link-dump 2\nconventions split=recorded\n"
                        "decide 0 1 split 1\ndecide 0 1/0 accept\n0 1/0\n"
                        "decide 0 1/1 forced max_depth\n0 1/1\npass 2\nunlink 0 1/1\n"
                        "decide 0 1/1 cull\ncounters links=1 oracle_calls=0 "
                        "total_oracle_calls=3 passes=2 nodes=0 forced_links=0 max_depth=0\n");
    std::ostringstream other;
    Probe v1(&other);
    CHECK_THROWS_AS(v1.Pass(), std::logic_error);

    hrbench::LinkDump d = Parse(dump.str());
    CHECK(d.version == 2);
    CHECK(d.decisions.size() == 4);
    CHECK(d.unlinks.size() == 1);
    CHECK(d.passes == 2);
    CHECK_THROWS_WITH(Parse("hrbench-link-dump 2\n0 1\npass 3\n"),
                      Catch::Contains("d:3: expected 'pass 2'"));
    CHECK_THROWS_WITH(Parse("hrbench-link-dump 2\n0 1\nconventions tie=second\n"),
                      Catch::Contains("d:3: the conventions line must come before"));
    CHECK_THROWS_WITH(Parse("hrbench-link-dump 2\ndecide 0 1 split 0/1\n"),
                      Catch::Contains("neither 0 nor 1"));
    // Version 1 knows no such records.
    CHECK_THROWS_WITH(Parse("hrbench-link-dump 1\npass 2\n"),
                      Catch::Contains("d:2: bad element 'pass'"));
    std::string path = WriteScratch("conv.dump", "hrbench-link-dump 2\nconventions tie=sideways\n");
    CheckError(kSmall + path, 2, "convention tie=sideways: the values are first, second");
    path = WriteScratch("conv2.dump", "hrbench-link-dump 2\nconventions oracle=hanrahan\n");
    CheckError(kSmall + path + " --oracle garmann", 2, "disagrees with the dump's oracle=hanrahan");
}

TEST_CASE("check-links judges a version 1 dump under conventions given on the command line",
          "[check-links]") {
    // Q split first, where hrbench's tie splits P: off the subdivision under hrbench's
    // rules, consistent when the kernel's split is taken as it is and its oracle its own.
    std::string path = WriteScratch("q_first2.dump", kHeader + "0 1/0\n0 1/1\n");
    CheckError(kSmall + path, hrbench::kExitViolation, "link off the subdivision");
    // One syntax everywhere: tokens separated by spaces, as in the dump's conventions
    // line; a comma reads as a space.
    CHECK(Cli(kSmall + path + " --conventions 'split=recorded oracle=own'").exitCode == 0);
    CHECK(Cli(kSmall + path + " --conventions split=recorded,oracle=own").exitCode == 0);
    CHECK(Cli(kSmall + path + " --conventions ' split=recorded, oracle=own '").exitCode == 0);
    std::string commas =
        WriteScratch("q_first_commas.dump",
                     "hrbench-link-dump 2\nconventions split=recorded,oracle=own\n0 1/0\n0 1/1\n");
    CHECK(Cli(kSmall + commas).exitCode == 0);
    CheckError(kSmall + path + " --conventions split=recorded", hrbench::kExitViolation,
               "unacceptable link: 0 1/0 is refused by the oracle garmann");
    // garmann accepts P and Q at eps 1 exactly (max(A) = r = 1): with accept=lt the pair
    // is on the boundary and may be split, with hrbench's <= it must be linked.
    path = WriteScratch("halves.dump", kHeader + "0/0 1\n0/1 1\n");
    std::string eps1 = "check-links parallel l=1 d=1 --eps 1 --links " + path;
    CheckError(eps1, hrbench::kExitViolation, "lies below the pair 0 1, which the oracle garmann");
    CliResult lt = Cli(eps1 + " --conventions accept=lt --json");
    INFO(lt.err);
    CHECK(lt.exitCode == 0);
    nlohmann::json j = nlohmann::json::parse(lt.out);
    CHECK(j["ok"] == true);
    CHECK(j["conventions"]["accept"] == "lt");
    CHECK(j["counters"]["dump"]["oracle_calls"] == 3);
    CHECK(j["counters"]["hrbench"] == nullptr);  // hrbench's rules differ
    CheckError(eps1 + " --conventions accept=maybe", 2, "convention accept=maybe");
    // Directed links judged by garmann: each direction tiled on its own, receiver first.
    std::string both = "hrbench-link-dump 2\nconventions links=directed\n" + kQuarters +
                       "1/0 0/0\n1/1 0/0\n1/0 0/1\n1/1 0/1\ncounters links=8 oracle_calls=14\n";
    CliResult directed = Cli(kSmall + WriteScratch("directed.dump", both));
    INFO(directed.err);
    CHECK(directed.exitCode == 0);
    std::string one = "hrbench-link-dump 2\nconventions links=directed\n" + kQuarters;
    CheckError(kSmall + WriteScratch("one_way.dump", one), hrbench::kExitViolation,
               "missing link: nothing covers the element pair 1 0 of patches 1 and 0");

    // Plates back to back: culled under hrbench's rules, refined with cull=none.
    std::string scene = WriteScratch(
        "back.json", R"({"format": "hrbench-scene", "schema_version": 1, "dimension": 2,
        "patches": [{"a": [0, 0], "b": [1, 0]}, {"a": [1, -1], "b": [0, -1]}]})");
    std::string back = "check-links --scene-file " + scene + " --eps 1 --links ";
    path = WriteScratch("back.dump", kHeader + "0 1\n");
    CheckError(back + path, hrbench::kExitViolation, "link between a culled pair: 0 1");
    CHECK(Cli(back + path + " --conventions cull=none,oracle=own").exitCode == 0);
    CheckError(back + WriteScratch("back_none.dump", kHeader) + " --conventions cull=none",
               hrbench::kExitViolation, "missing link: nothing covers the element pair 0 1");
    CheckError(eps1 + " --conventions links=directed", 2,
               "links=directed needs a dump of version 2");
}
