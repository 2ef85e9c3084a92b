// ProjectKernel on 3D scenes and with visibility: a hand-computed case, the tiling and
// oracle-call invariants for both subdivisions, thread independence, occlusion, errors.
#include <catch2/catch.hpp>

#include <map>

#include "generators.h"
#include "hrbench.h"
#include "mesh_io.h"
#include "oracles3d.h"
#include "refinement_helpers.h"

using namespace hrbench;

namespace {

RefineOptions Options3D(double eps, OracleKind oracle = OracleKind::Garmann,
                        Subdivision subdivision = Subdivision::Binary) {
    RefineOptions o;
    o.eps = eps;
    o.oracle = oracle;
    o.subdivision = subdivision;
    o.storeLinks = true;
    return o;
}

// Per root pair: the links tile P x Q (sum of A_i A_j = A_P A_Q) and the oracle calls
// follow from the links: 2L - 1 (binary) or (4L - 1) / 3 (quadtree).
void CheckTiling(const Scene &scene, const Refinement &r, Subdivision subdivision) {
    const PolygonForest &f = r.forest3d;
    std::map<std::pair<uint32_t, uint32_t>, double> area;
    for (const Link &link : r.links)
        area[{f[link.i].root, f[link.j].root}] += f[link.i].size * f[link.j].size;
    uint64_t links = 0;
    for (const PairTally &pair : r.pairs) {
        INFO("pair " << pair.p << " " << pair.q);
        if (subdivision == Subdivision::Binary)
            CHECK(pair.oracleCalls == 2 * pair.links - 1);
        else
            CHECK(3 * pair.oracleCalls == 4 * pair.links - 1);
        double expected = scene.faces[pair.p].polygon.Area() * scene.faces[pair.q].polygon.Area();
        CHECK_THAT(area[std::make_pair(pair.p, pair.q)],
                   Catch::Matchers::WithinRel(expected, 1e-12));
        links += pair.links;
    }
    CHECK(links == r.counters.links);
    CHECK(r.links.size() == r.counters.links);
    uint64_t nodes = 0;
    for (uint64_t n : r.counters.nodesPerDepth)
        nodes += n;
    CHECK(nodes == r.counters.nodes);
    CHECK(r.counters.nodes == f.Size());
}

}  // namespace

TEST_CASE("Two unit squares at distance 1 give the hand-computed 3D counts", "[3d][refine]") {
    Scene scene = MakeScene("parallel3d", {});
    SECTION("eps = 1 accepts the root pair: max(1, 1) <= 1 * 1^2") {
        Refinement r = Refine(scene, Options3D(1));
        CHECK(r.counters.links == 1);
        CHECK(r.counters.oracleCalls == 1);
        CHECK(r.counters.nodes == 2);
    }
    SECTION("eps = 0.5 halves both plates along x; two pairs are ties r^2 = 1, accepted") {
        // (P,Q) rejected, P halved; (P0,Q) rejected (1 > 0.5 * 1.0625), Q halved;
        // (P0,Q0) 0.5 <= 0.5 * 1, (P0,Q1) 0.5 <= 0.5 * 1.25; (P1,Q) rejected, Q's halves
        // shared; (P1,Q0), (P1,Q1) accepted.
        Refinement r = Refine(scene, Options3D(0.5));
        CHECK(r.counters.nodes == 6);
        CHECK(r.counters.leaves == 4);
        CHECK(r.counters.links == 4);
        CHECK(r.counters.oracleCalls == 7);
        CHECK(r.counters.maxDepth == 1);
        CHECK(r.counters.linksPerDepth == std::vector<uint64_t>{0, 0, 4});
        REQUIRE(r.links.size() == 4);
        CHECK(r.forest3d[r.links[0].i].center.isApprox(Vec3(0.25, 0.5, 0)));
        CHECK(r.forest3d[r.links[0].j].center.isApprox(Vec3(0.25, 0.5, 1)));
    }
    SECTION("quadtree, eps = 0.5: both plates in four, 16 links") {
        // (P,Q) rejected; (P_k,Q): 1 > 0.5 r^2 for every quarter, Q split; quarters at
        // r^2 >= 1 satisfy 0.25 <= 0.5 r^2.
        Refinement r = Refine(scene, Options3D(0.5, OracleKind::Garmann, Subdivision::Quadtree));
        CHECK(r.counters.nodes == 10);
        CHECK(r.counters.links == 16);
        CHECK(r.counters.oracleCalls == 21);
    }
}

TEST_CASE("3D links tile every root pair and oracle calls follow from the links",
          "[3d][refine]") {
    std::vector<std::pair<Scene, double>> cases = {
        {MakeScene("parallel3d", {{"l", 4}, {"w", 2}, {"ox", 0.5}}), 0.05},
        {MakeScene("angled3d", {{"angle", 70}}), 0.1},
        {MakeScene("occluded3d", {}), 0.1},
        {MakeScene("array3d", {{"k", 2}}), 0.2},
        {MakeScene("random3d", {{"n", 8}, {"seed", 4}, {"size", 3}}), 0.2},
    };
    for (const auto &[scene, eps] : cases) {
        INFO(scene.family);
        for (OracleKind oracle : {OracleKind::Garmann, OracleKind::Hanrahan})
            for (Subdivision s : {Subdivision::Binary, Subdivision::Quadtree}) {
                Refinement r = Refine(scene, Options3D(oracle == OracleKind::Garmann ? eps : eps / 4,
                                                       oracle, s));
                CHECK(r.counters.links > 2);
                CHECK(r.counters.rays == 0);
                CHECK(r.counters.visibilityQueries == 0);
                CHECK(r.counters.occludedPairs == 0);
                CheckTiling(scene, r, s);
            }
    }
}

TEST_CASE("Every 3D link satisfies the 3D oracle unless forced", "[3d][refine]") {
    Scene scene = MakeScene("perpendicular3d", {{"gap", 0}});
    RefineOptions o = Options3D(0.05);
    o.minArea = 1e-3;
    Refinement r = Refine(scene, o);
    Garmann3DOracle oracle(0.05);
    uint64_t unacceptable = 0;
    for (const Link &link : r.links)
        unacceptable += !oracle.Acceptable(r.forest3d[link.i], r.forest3d[link.j]);
    CHECK(unacceptable == r.counters.forcedLinks);
    CHECK(r.counters.forcedLinks > 0);
    CheckTiling(scene, r, Subdivision::Binary);
}

TEST_CASE("3D counts and links do not depend on the number of threads", "[3d][refine]") {
    Scene scene = MakeScene("parallel3d", {{"l", 4}, {"w", 4}});
    for (VisibilityMode mode : {VisibilityMode::None, VisibilityMode::Fraction}) {
        RefineOptions o = Options3D(0.05);
        o.visibility = mode;
        o.raysPerSide = 2;
        Refinement one = Refine(scene, o);
        o.threads = 4;
        Refinement four = Refine(scene, o);
        CHECK(hrbench_test::CounterDifferences(one.counters, four.counters) == "");
        CHECK(hrbench_test::SameLinks(one.links, four.links));
        CHECK(one.counters.links > 1000);  // enough for tasks on several threads
    }
}

TEST_CASE("Visibility none counts nothing; fraction on an unoccluded scene changes nothing",
          "[3d][visibility][refine]") {
    Scene scene = MakeScene("parallel3d", {{"l", 2}});
    RefineOptions o = Options3D(0.05);
    Refinement none = Refine(scene, o);
    o.visibility = VisibilityMode::Fraction;
    Refinement fraction = Refine(scene, o);
    CHECK(none.counters.links == fraction.counters.links);
    CHECK(none.counters.oracleCalls == fraction.counters.oracleCalls);
    CHECK(fraction.counters.visibilityQueries == fraction.counters.oracleCalls);
    CHECK(fraction.counters.rays == 81 * fraction.counters.visibilityQueries);  // k = 3
    CHECK(fraction.counters.occludedPairs == 0);
}

TEST_CASE("A blocker that hides everything leaves no link between the plates",
          "[3d][visibility][refine]") {
    Scene scene = MakeScene("occluded3d", {{"bl", 10}});
    RefineOptions o = Options3D(0.1);
    o.visibility = VisibilityMode::Fraction;
    Refinement r = Refine(scene, o);
    uint64_t plateLinks = 0;
    for (const Link &link : r.links)
        plateLinks += r.forest3d[link.i].root == 0 && r.forest3d[link.j].root == 1;
    CHECK(plateLinks == 0);
    CHECK(r.counters.occludedPairs >= 1);
    // Each call links, is occluded or splits in two: calls = 2 (links + occluded) - pairs.
    CHECK(r.counters.oracleCalls == 2 * (r.counters.links + r.counters.occludedPairs) -
                                        (r.counters.rootPairs - r.counters.culledPairs));
}

TEST_CASE("An occluder reduces the links of the plates with visibility fraction",
          "[3d][visibility][refine]") {
    RefineOptions o = Options3D(0.02);
    o.visibility = VisibilityMode::Fraction;
    Refinement open = Refine(MakeScene("parallel3d", {}), o);
    Refinement blocked = Refine(MakeScene("occluded3d", {}), o);
    uint64_t plateLinks = 0;
    for (const Link &link : blocked.links)
        plateLinks += blocked.forest3d[link.i].root == 0 && blocked.forest3d[link.j].root == 1;
    CHECK(plateLinks < open.counters.links);
    CHECK(blocked.counters.occludedPairs > 0);
    CHECK(blocked.counters.oracleCalls ==
          2 * (blocked.counters.links + blocked.counters.occludedPairs) -
              (blocked.counters.rootPairs - blocked.counters.culledPairs));
}

TEST_CASE("Visibility refine splits partially visible pairs down to the limit",
          "[3d][visibility][refine]") {
    Scene scene = MakeScene("occluded3d", {});
    RefineOptions o = Options3D(0.1);
    o.visibility = VisibilityMode::Refine;
    CHECK_THROWS_WITH(Refine(scene, o), Catch::Contains("--visibility refine"));
    o.maxDepth = 6;
    Refinement refine = Refine(scene, o);
    o.visibility = VisibilityMode::Fraction;
    Refinement fraction = Refine(scene, o);
    CHECK(refine.counters.forcedLinks > 0);
    CHECK(refine.counters.links > fraction.counters.links);
}

TEST_CASE("Visibility applies to 2D scenes: the occluded family", "[visibility][refine]") {
    RefineOptions o;
    o.eps = 0.05;
    o.storeLinks = true;
    Scene scene = MakeScene("occluded", {{"l", 4}});
    Refinement none = Refine(scene, o);
    o.visibility = VisibilityMode::Fraction;
    Refinement fraction = Refine(scene, o);
    CHECK(none.counters.occludedPairs == 0);
    CHECK(fraction.counters.occludedPairs > 0);
    CHECK(fraction.counters.rays == 9 * fraction.counters.visibilityQueries);  // k = 3
    CHECK(fraction.counters.oracleCalls ==
          2 * (fraction.counters.links + fraction.counters.occludedPairs) -
              (fraction.counters.rootPairs - fraction.counters.culledPairs));
    // Unoccluded 2D: the worked example is unchanged by visibility.
    Scene parallel = MakeScene("parallel", {{"l", 64}, {"d", 1}});
    o.eps = 0.25;
    Refinement worked = Refine(parallel, o);
    CHECK(worked.counters.links == 5092);
    CHECK(worked.counters.oracleCalls == 10183);
}

TEST_CASE("The Cornell box loads and refines", "[3d][refine]") {
    Scene scene = MakeScene("cornell", {});
    RefineOptions o = Options3D(0.02, OracleKind::Hanrahan);
    o.minArea = 1e-2;
    o.storeLinks = false;
    CHECK_THROWS_AS(Refine(scene, Options3D(0.02, OracleKind::Hanrahan)), InputError);  // touching
    Refinement r = Refine(scene, o);
    CHECK(r.counters.rootPairs == 17 * 16 / 2);
    CHECK(r.counters.culledPairs > 20);  // coplanar light and ceiling, faces of each block
    CHECK(r.counters.links > 1000);
    CHECK(r.counters.forcedLinks > 0);
    o.visibility = VisibilityMode::Fraction;
    Refinement visible = Refine(scene, o);
    CHECK(visible.counters.occludedPairs > 0);
    CHECK(visible.counters.links < r.counters.links);
}

TEST_CASE("Bad 3D refinement options are input errors naming the flag", "[3d][refine]") {
    Scene scene3 = MakeScene("parallel3d", {});
    Scene scene2 = MakeScene("parallel", {});
    RefineOptions o = Options3D(0.1);
    o.raysPerSide = 0;
    CHECK_THROWS_WITH(Refine(scene3, o), Catch::Contains("--rays-per-side"));
    o = Options3D(0.1, OracleKind::Garmann, Subdivision::Quadtree);
    CHECK_THROWS_WITH(Refine(scene2, o), Catch::Contains("--subdivision quadtree"));
    CHECK_THROWS_WITH(Refine(MakeScene("perpendicular3d", {{"gap", 0}}), Options3D(0.1)),
                      Catch::Contains("touch"));
}

TEST_CASE("An OBJ mesh refines as the family it copies", "[3d][mesh][refine]") {
    Scene mesh = LoadMesh(std::string(HRBENCH_TEST_DATA) + "/two_plates.obj");
    Refinement a = Refine(mesh, Options3D(0.03));
    Refinement b = Refine(MakeScene("parallel3d", {}), Options3D(0.03));
    CHECK(a.counters.links == b.counters.links);
    CHECK(a.counters.nodes == b.counters.nodes);
    CHECK(a.counters.oracleCalls == b.counters.oracleCalls);
}
