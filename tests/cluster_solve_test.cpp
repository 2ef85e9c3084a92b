// The solve through cluster links (`--clusters`, docs/solve.md, Clusters): the tree's
// numbering, cluster links by hand under both transfers, uniform radiosity and energy
// balance in closed scenes, agreement with the solve without clusters, determinism across
// thread counts and the output. The clustered refinements are the engine's own.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "cluster/direction_table.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "visibility/culling.h"

using namespace hrbench;

namespace {

RefineOptions Refining(double eps, double minArea, bool clusters = false) {
    RefineOptions o;
    o.eps = eps;
    o.minArea = minArea;
    o.storeLinks = true;
    o.clusters = clusters;
    return o;
}

SolveOptions Solving(double tolerance,
                     ClusterTransferKind transfer = ClusterTransferKind::Projected,
                     SolveMethod method = SolveMethod::Jacobi) {
    SolveOptions o;
    o.tolerance = tolerance;
    o.method = method;
    o.clusterTransfer = transfer;
    return o;
}

// The closed cube [0,1]^3 as a mesh: each face a grid of n x n quads facing inward, all
// of reflectance _rho_, the quads of the face z = 1 nearest its centre emitting 1.
Scene GridBox(int n, double rho) {
    Patches<Polygon> quads;
    auto face = [&](Vec3 origin, Vec3 u, Vec3 v, bool ceiling) {
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                Vec3 a = origin + u * i / n + v * j / n;
                Vec3 du = u / n, dv = v / n;
                bool lamp = ceiling && 2 * i + 1 >= n - 1 && 2 * i + 1 <= n + 1 &&
                            2 * j + 1 >= n - 1 && 2 * j + 1 <= n + 1;
                quads.push_back(
                    {Polygon::Quad(a, a + du, a + du + dv, a + dv), {rho, lamp ? 1.0 : 0.0}});
            }
    };
    // u x v points inward on each face.
    face({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, false);  // z = 0
    face({0, 0, 1}, {0, 1, 0}, {1, 0, 0}, true);   // z = 1
    face({0, 0, 0}, {0, 1, 0}, {0, 0, 1}, false);  // x = 0
    face({1, 0, 0}, {0, 0, 1}, {0, 1, 0}, false);  // x = 1
    face({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, false);  // y = 0
    face({0, 1, 0}, {1, 0, 0}, {0, 0, 1}, false);  // y = 1
    return {"file", {}, "", quads};
}

// The regular 2D enclosure of _n_ walls, reflectance _rho_, wall 0 emitting 1.
Scene LitEnclosure(int n, double rho) {
    Scene s = MakeScene("enclosure", {{"n", n}});
    for (auto &patch : s.Get<Segment>())
        patch.material = {rho, 0};
    s.Get<Segment>()[0].material.emission = 1;
    return s;
}

// The closed unit sphere as a mesh of _rings_ bands of 2 _rings_ faces (triangles at the
// poles, quads between), every face turned inward, reflectance _rho_, the band around
// the pole z = 1 emitting 1.
Scene Sphere(int rings, double rho) {
    Patches<Polygon> faces;
    int sectors = 2 * rings;
    auto point = [&](int i, int j) {
        double theta = M_PI * i / rings, phi = 2 * M_PI * j / sectors;
        return Vec3{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                    std::cos(theta)};
    };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < sectors; ++j) {
            Vec3 a = point(i, j), b = point(i + 1, j), c = point(i + 1, j + 1), d = point(i, j + 1);
            auto face = [&](bool turned) {
                if (i == 0)
                    return turned ? Polygon::Triangle(c, b, a) : Polygon::Triangle(a, b, c);
                if (i + 1 == rings)
                    return turned ? Polygon::Triangle(d, b, a) : Polygon::Triangle(a, b, d);
                return turned ? Polygon::Quad(d, c, b, a) : Polygon::Quad(a, b, c, d);
            };
            Polygon p = face(false);
            if (p.Normal().dot(p.Centroid()) > 0)  // facing out
                p = face(true);
            faces.push_back({p, {rho, i == 0 ? 1.0 : 0.0}});
        }
    return {"file", {}, "", faces};
}

// The unit square [x, x + 1] x [0, 1] in the plane z, facing +z (_up_) or -z, of
// reflectance _rho_ and emission _e_.
Patch<Polygon> Square(double x, double z, bool up, double rho, double e) {
    Vec3 a{x, 0, z}, b{x + 1, 0, z}, c{x + 1, 1, z}, d{x, 1, z};
    return {up ? Polygon::Quad(a, b, c, d) : Polygon::Quad(a, d, c, b), {rho, e}};
}

double Imbalance(const SolveResult &r) {
    return std::abs(r.absorbedPower - r.emittedPower) / r.emittedPower;
}

// Relative differences of the leaves' radiosity of _a_ from _b_, two refinements of the
// same root patches by the same rule (_arity_ children an element) with leaves of their
// own: over the pieces of their common refinement (each the finer of two overlapping
// leaves), the largest |B_a - B_b| over max |B_b|, and the area-weighted L2 norm over B_b's.
struct Difference {
    double max = 0, l2 = 0;
};

Difference Differ(const SolveResult &a, const SolveResult &b, int arity) {
    using Key = std::tuple<uint32_t, int, uint64_t>;
    auto index = [](const SolveResult &r) {
        std::map<Key, double> radiosity;
        for (const ElementRadiosity &leaf : r.leaves)
            radiosity[{leaf.root, leaf.depth, leaf.position}] = leaf.radiosity;
        return radiosity;
    };
    std::map<Key, double> inA = index(a), inB = index(b);
    double largest = 0, norm2 = 0, worst = 0, diff2 = 0;
    for (const ElementRadiosity &leaf : b.leaves) {
        largest = std::max(largest, std::abs(leaf.radiosity));
        norm2 += leaf.measure * leaf.radiosity * leaf.radiosity;
    }
    // A piece is found from its finer leaf by walking up the other's tree; a leaf of both
    // is found from _a_ only (_strict_ starts _b_'s walk at the parent).
    auto pieces = [&](const SolveResult &fine, const std::map<Key, double> &coarse, bool strict) {
        for (const ElementRadiosity &leaf : fine.leaves) {
            int depth = leaf.depth;
            uint64_t position = leaf.position;
            if (strict)
                --depth, position /= uint64_t(arity);
            for (; depth >= 0; --depth, position /= uint64_t(arity))
                if (auto found = coarse.find({leaf.root, depth, position}); found != coarse.end()) {
                    double d = leaf.radiosity - found->second;
                    worst = std::max(worst, std::abs(d));
                    diff2 += leaf.measure * d * d;
                    break;
                }
        }
    };
    pieces(a, inB, false);
    pieces(b, inA, true);
    return {worst / largest, std::sqrt(diff2 / norm2)};
}

std::vector<double> Radiosities(const SolveResult &r) {
    std::vector<double> b;
    for (const ElementRadiosity &leaf : r.leaves)
        b.push_back(leaf.radiosity);
    return b;
}

constexpr ClusterTransferKind kIsotropic = ClusterTransferKind::Isotropic;
constexpr ClusterTransferKind kProjected = ClusterTransferKind::Projected;

}  // namespace

TEST_CASE("The cluster tree splits at the median of the longest axis, numbered in preorder",
          "[solve][clusters]") {
    Scene s = LitEnclosure(6, 0.5);
    ClusterTree<Segment> tree(s.Get<Segment>());
    REQUIRE(tree.NumClusters() == 5);
    for (uint32_t c = 0; c < 5; ++c) {
        CHECK(tree[c].parent <= c);
        for (uint32_t child : tree[c].children)
            if (IsCluster(child))
                CHECK(tree[ClusterIndex(child)].parent == c);
            else
                CHECK(tree.ParentOfPatch(child) == c);
    }
    CHECK(tree[0].begin == 0);
    CHECK(tree[0].end == 6);
    CHECK(tree[0].measure == Approx(6.0));  // six walls of the unit circumradius
}

TEST_CASE("One cluster link between two clusters of two segments, by hand", "[solve][clusters]") {
    // X = {p0, p1} facing +x at x = 0 and 0.5, Y = {p2, p3} facing -x at x = 10 and 10.5.
    // X emits and does not reflect, Y reflects and does not emit: one gather is final.
    Patches<Segment> patches = {{{{0, 1}, {0, 0}}, {0, 1}},
                                {{{0.5, 2}, {0.5, 0}}, {0, 3}},
                                {{{10, 0}, {10, 1}}, {0.5, 0}},
                                {{{10.5, 0}, {10.5, 3}}, {0.8, 0}}};
    Scene scene{"file", {}, "", patches};
    RefineOptions refine = Refining(1, 0);
    Refinement<Segment> r{Forest<Segment>(patches, SIZE_MAX, refine.subdivision),
                          {},
                          {},
                          {},
                          ClusterTree<Segment>(patches),
                          {},
                          {}};
    // The median split along x: cluster 1 = {p0, p1}, cluster 2 = {p2, p3}.
    REQUIRE(r.clusters.NumClusters() == 3);
    REQUIRE(r.clusters[1].children[0] == 0);
    REQUIRE(r.clusters[1].children[1] == 1);
    REQUIRE(r.clusters[2].children[0] == 2);
    REQUIRE(r.clusters[2].children[1] == 3);
    SolveOptions options = Solving(1e-14, kIsotropic);
    options.plainGather = true;
    // Centres: area-weighted centroids (1/3, 5/6) and (10.375, 1.25).
    const double dx = 10.375 - 1.0 / 3, dist = std::hypot(dx, 1.25 - 5.0 / 6);
    const double bX = (1 * 1 + 2 * 3) / 3.0;  // pulled: area-weighted mean of E
    // By the flux per unit B of the far end: X gathers flux / 3, Y flux / 4.
    auto check = [&](const SolveResult &s, double flux) {
        double hY = bX * flux / 4;
        double bY = (1 * 0.5 * hY + 3 * 0.8 * hY) / 4;
        double hX = bY * flux / 3;
        std::vector<double> b = {1, 3, 0.5 * hY, 0.8 * hY}, h = {hX, hX, hY, hY};
        for (size_t p = 0; p < 4; ++p) {
            CHECK(s.leaves[p].radiosity == Approx(b[p]).epsilon(1e-13));
            CHECK(s.leaves[p].irradiance == Approx(h[p]).epsilon(1e-13));
        }
        CHECK(s.emittedPower == 7);
        CHECK(s.absorbedPower == Approx(3 * hX + 0.5 * hY + 0.2 * 3 * hY).epsilon(1e-13));
    };

    SECTION("isotropic: each cluster end at the mean cosine 1/pi") {
        r.clusterLinks = {{ClusterNode(1), ClusterNode(2)}};
        SolveResult s = SolveRefinement(scene, r, refine, options);
        check(s, (3 / M_PI) * (4 / M_PI) / (2 * dist));
        REQUIRE(s.clusters);
        CHECK(s.clusters->clusters == 3);
        CHECK(s.clusters->links == 1);
        CHECK(s.clusters->transferShare == 1);
    }
    SECTION("projected: X's patches share the normal +x (3 u_x), Y's -x (4 u_x), u_x = dx / r") {
        r.clusterLinks = {{ClusterNode(1), ClusterNode(2)}};
        options.clusterTransfer = kProjected;
        SolveResult s = SolveRefinement(scene, r, refine, options);
        check(s, (3 * dx / dist) * (4 * dx / dist) / (2 * dist));
    }
    SECTION("patch to cluster: the patch end keeps its cosine") {
        r.clusterLinks = {{0, ClusterNode(2)}};
        double ux = 10.375 / std::hypot(10.375, 1.25 - 0.5);  // p0's normal is +x
        double r0 = std::hypot(10.375, 0.75);
        for (auto [kind, projected] : {std::pair{kIsotropic, 4 / M_PI}, {kProjected, 4 * ux}}) {
            options.clusterTransfer = kind;
            SolveResult s = SolveRefinement(scene, r, refine, options);
            double flux = ux * projected / (2 * r0);  // B_p0 A_p0 = 1
            double hY = flux / 4;
            CHECK(s.leaves[2].radiosity == Approx(0.5 * hY).epsilon(1e-13));
            CHECK(s.leaves[3].radiosity == Approx(0.8 * hY).epsilon(1e-13));
            double bY = (0.5 * hY + 3 * 0.8 * hY) / 4;
            CHECK(s.leaves[0].irradiance == Approx(bY * flux).epsilon(1e-13));
            CHECK(s.leaves[1].irradiance == 0);  // p1 takes no part
        }
    }
    SECTION("a patch facing away gathers nothing") {
        r.clusterLinks = {{2, ClusterNode(1)}, {3, ClusterNode(1)}};
        // p2 and p3 face -x, toward X: they gather; flip them and nothing passes.
        SolveResult s = SolveRefinement(scene, r, refine, options);
        CHECK(s.leaves[2].radiosity > 0);
        Patches<Segment> flipped = patches;
        for (size_t p : {2, 3})
            std::swap(flipped[p].shape.a, flipped[p].shape.b);
        Scene away{"file", {}, "", flipped};
        Refinement<Segment> f{Forest<Segment>(flipped, SIZE_MAX, refine.subdivision),
                              {},
                              {},
                              {},
                              ClusterTree<Segment>(flipped),
                              r.clusterLinks,
                              {}};
        for (ClusterTransferKind kind : {kIsotropic, kProjected}) {
            options.clusterTransfer = kind;
            SolveResult t = SolveRefinement(away, f, refine, options);
            CHECK(t.leaves[2].radiosity == 0);
            CHECK(t.leaves[3].radiosity == 0);
        }
    }
}

TEST_CASE("A 3D cluster link: B A / (16 pi r^2) between isotropic ends, exact between "
          "projected ones, nothing within a plane",
          "[solve][clusters][3d]") {
    SolveOptions options = Solving(1e-14);
    options.plainGather = true;
    RefineOptions refine = Refining(1, 0);
    auto solve = [&](const Patches<Polygon> &patches, ClusterTransferKind kind) {
        Refinement<Polygon> r{Forest<Polygon>(patches, SIZE_MAX, refine.subdivision),
                              {},
                              {},
                              {},
                              ClusterTree<Polygon>(patches),
                              {},
                              {}};
        REQUIRE(r.clusters.NumClusters() == 3);
        REQUIRE(r.clusters[1].begin == 0);  // {p0, p1}, {p2, p3}
        r.clusterLinks = {{ClusterNode(1), ClusterNode(2)}};
        options.clusterTransfer = kind;
        return SolveRefinement(Scene{"file", {}, "", patches}, r, refine, options);
    };
    // Two clusters of two unit squares each, facing each other 10 apart along z: the
    // projected areas are 2 at each end, the isotropic 2/4.
    Patches<Polygon> facing = {Square(0, 0, true, 0, 1), Square(1, 0, true, 0, 2),
                               Square(0, 10, false, 0.5, 0), Square(1, 10, false, 0.5, 0)};
    for (auto [kind, projected] : {std::pair{kIsotropic, 0.5}, {kProjected, 2.0}}) {
        SolveResult s = solve(facing, kind);
        double hY = 1.5 * projected * projected / (M_PI * 100) / 2;  // B_X f f / (pi r^2) / A_Y
        CHECK(s.leaves[2].radiosity == Approx(0.5 * hY).epsilon(1e-13));
        CHECK(s.leaves[3].radiosity == Approx(0.5 * hY).epsilon(1e-13));
    }
    // The same four squares side by side on z = 0, all facing +z: two clusters of one
    // floor exchange nothing, but as isotropic clusters they do.
    Patches<Polygon> flat = {Square(0, 0, true, 0, 1), Square(1, 0, true, 0, 1),
                             Square(10, 0, true, 0.5, 0), Square(11, 0, true, 0.5, 0)};
    CHECK(solve(flat, kProjected).leaves[2].radiosity == 0);
    CHECK(solve(flat, kIsotropic).leaves[2].radiosity > 0);
}

TEST_CASE("Through clusters, a closed scene of uniform emission has B = E / (1 - rho)",
          "[solve][clusters]") {
    // The consistency scale counts the cluster coefficients: uniform B stays exact.
    Scene enclosure = LitEnclosure(256, 0.5);
    for (auto &patch : enclosure.Get<Segment>())
        patch.material.emission = 1;
    RefineOptions refine = Refining(0.1, 0.005, true);
    for (ClusterTransferKind kind : {kIsotropic, kProjected}) {
        SolveResult s = Solve(enclosure, refine, Solving(1e-12, kind));
        REQUIRE(s.record.counters.clusterLinks > 0);
        for (const ElementRadiosity &leaf : s.leaves)
            CHECK(leaf.radiosity == Approx(2).epsilon(1e-9));
        CHECK(Imbalance(s) < 1e-9);
    }
}

TEST_CASE("Through clusters, energy balances in closed scenes and the radiosity stays near "
          "the solve without clusters",
          "[solve][clusters]") {
    // Bounds: about 1.5 times the figures of "[.cluster-figures]" (docs/solve.md, Clusters),
    // the measurement beside each.
    struct Bound {
        ClusterTransferKind kind;
        double imbalance, max, l2;
    };
    auto check = [](const Scene &scene, const RefineOptions &refine, std::vector<Bound> bounds) {
        RefineOptions clustered = refine;
        clustered.clusters = true;
        SolveResult u = Solve(scene, refine, Solving(1e-10));
        for (const Bound &b : bounds) {
            SolveResult c = Solve(scene, clustered, Solving(1e-10, b.kind));
            Difference d = Differ(c, u, SubdivisionArity(refine.subdivision));
            INFO(ClusterTransferName(b.kind)
                 << ": cluster links " << c.record.counters.clusterLinks << " share "
                 << c.clusters->transferShare << " imbalance " << Imbalance(c) << " max " << d.max
                 << " l2 " << d.l2);
            CHECK(c.record.counters.clusterLinks > 0);
            CHECK(Imbalance(c) < b.imbalance);
            CHECK(d.max < b.max);
            CHECK(d.l2 < b.l2);
        }
    };
    SECTION("2D enclosure") {
        // Measured (the reciprocal scale): projected 2.6e-8, 0.000116, 0.00058; isotropic
        // 2.6e-8, 0.00476, 0.0306 (the imbalance is the tolerance's).
        check(LitEnclosure(256, 0.7), Refining(0.1, 0.005),
              {{kProjected, 5e-8, 0.00018, 0.00087}, {kIsotropic, 5e-8, 0.0071, 0.046}});
    }
    SECTION("closed cube, 6 x 6 quads a face") {
        // Measured (the reciprocal scale): projected 3.7e-9, 0.00506, 0.00831; isotropic
        // 3.7e-9, 0.0213, 0.0709.
        check(GridBox(6, 0.6), Refining(0.2, 0.04),
              {{kProjected, 1e-8, 0.0076, 0.0125}, {kIsotropic, 1e-8, 0.032, 0.1}});
    }
    SECTION("closed sphere, 8 bands of 16 faces") {
        // Measured (the reciprocal scale): projected 2.2e-9, 0.00099, 0.00186; isotropic
        // 2.2e-9, 0.0336, 0.0808.
        check(Sphere(8, 0.6), Refining(0.2, 0.04),
              {{kProjected, 1e-8, 0.0015, 0.0028}, {kIsotropic, 1e-8, 0.05, 0.12}});
    }
}

TEST_CASE("The solve through clusters is the same bit for bit on 1, 2 and 3 threads",
          "[solve][clusters]") {
    Scene scene = GridBox(6, 0.6);
    for (SolveMethod method : {SolveMethod::Jacobi, SolveMethod::GaussSeidel}) {
        std::vector<SolveResult> results;
        for (int threads : {1, 2, 3}) {
            RefineOptions refine = Refining(0.2, 0.04, true);
            refine.threads = threads;
            results.push_back(Solve(scene, refine, Solving(1e-10, kProjected, method)));
        }
        REQUIRE(results[0].record.counters.clusterLinks > 0);
        for (size_t k = 1; k < results.size(); ++k) {
            CHECK(Radiosities(results[k]) == Radiosities(results[0]));
            CHECK(results[k].iterations == results[0].iterations);
            CHECK(results[k].absorbedPower == results[0].absorbedPower);
            CHECK(results[k].clusters->transferShare == results[0].clusters->transferShare);
        }
    }
}

TEST_CASE("The solve's JSON gives the cluster transfer and its share only with clusters",
          "[solve][clusters]") {
    Scene scene = LitEnclosure(256, 0.5);
    RefineOptions refine = Refining(0.1, 0.005, true);
    SolveOptions options = Solving(1e-8, kIsotropic);
    nlohmann::json with = SolveToJson(scene, refine, options, Solve(scene, refine, options));
    CHECK(with["clusters"] == true);
    CHECK(with["cluster_nodes"] == 255);
    CHECK(with["cluster_links"].get<uint64_t>() > 0);
    CHECK(with["cluster_transfer"] == "isotropic");
    CHECK(with["cluster_transfer_share"].get<double>() > 0);
    CHECK(with["cluster_transfer_share"].get<double>() < 1);
    CHECK(with["cluster_rays"] == 0);  // the enclosure cannot occlude: --visibility none
    CHECK(with["occluded_cluster_links"] == 0);
    std::ostringstream table;
    PrintSolveTable(with, table);
    CHECK(table.str().find("cluster_transfer ") != std::string::npos);
    refine.clusters = false;
    nlohmann::json without = SolveToJson(scene, refine, options, Solve(scene, refine, options));
    CHECK(without["clusters"] == false);
    CHECK(without["cluster_links"] == 0);
    CHECK_FALSE(without.contains("cluster_transfer"));
    CHECK_FALSE(without.contains("cluster_transfer_share"));
    CHECK_FALSE(without.contains("cluster_rays"));
    CHECK_FALSE(without.contains("occluded_cluster_links"));
    std::ostringstream plainTable;
    PrintSolveTable(without, plainTable);
    CHECK(plainTable.str().find("cluster") == std::string::npos);
}

TEST_CASE("solve --clusters through the command line: its fields, the same JSON on 1, 2 and "
          "3 threads, and what it refuses",
          "[solve][clusters][cli]") {
    using hrbench_test::Cli;
    // The enclosure of 256 walls with wall 0 emitting 1, as a scene file.
    const std::string file = hrbench_test::Scratch("lit_enclosure.json");
    REQUIRE(Cli("save enclosure n=256 --out " + file).exitCode == 0);
    nlohmann::json saved = nlohmann::json::parse(hrbench_test::ReadFile(file));
    saved["patches"][0]["emission"] = 1;
    std::ofstream(file) << saved.dump();
    const std::string scene =
        "solve --scene-file " + file + " --eps 0.1 --min-area 0.005 --reflectance 0.7 --json ";
    // The JSON without what may differ between runs: times, context and the thread count.
    auto steady = [&](const std::string &args) {
        hrbench_test::CliResult r = Cli(scene + args);
        INFO(args << ": " << r.err);
        REQUIRE(r.exitCode == 0);
        nlohmann::json j = nlohmann::json::parse(r.out);
        for (auto it = j.begin(); it != j.end();)
            if (it.key().find("seconds") != std::string::npos || it.key() == "context" ||
                it.key() == "threads")
                it = j.erase(it);
            else
                ++it;
        return j;
    };
    nlohmann::json j = steady("--clusters --threads 1");
    CHECK(j["clusters"] == true);
    CHECK(j["cluster_nodes"] == 255);
    uint64_t clusterLinks = j["cluster_links"];
    CHECK(clusterLinks > 0);
    CHECK(j["element_links"].get<uint64_t>() + clusterLinks == j["links"].get<uint64_t>());
    CHECK(j["cluster_transfer"] == "projected");
    double share = j["cluster_transfer_share"];
    CHECK(share > 0.5);  // measured 0.968
    CHECK(share < 1);
    double emitted = j["emitted_power"], absorbed = j["absorbed_power"];
    CHECK(emitted == Approx(2 * std::sin(M_PI / 256)));     // one wall of 256 emits 1
    CHECK(std::abs(absorbed - emitted) < 0.041 * emitted);  // measured 0.0273
    CHECK(j["energy_balance_warning"].is_null());
    CHECK(steady("--clusters --threads 2") == j);
    CHECK(steady("--clusters --threads 3") == j);
    CHECK(steady("--clusters --cluster-transfer projected") == j);
    nlohmann::json isotropic = steady("--clusters --cluster-transfer isotropic");
    CHECK(isotropic["cluster_transfer"] == "isotropic");
    CHECK(isotropic["cluster_links"] == clusterLinks);
    CHECK(isotropic["radiosity"] != j["radiosity"]);

    nlohmann::json without = steady("");
    CHECK(without["clusters"] == false);
    CHECK(without["cluster_links"] == 0);
    CHECK_FALSE(without.contains("cluster_transfer"));
    CHECK_FALSE(without.contains("cluster_transfer_share"));
    CHECK_FALSE(without.contains("cluster_rays"));
    CHECK_FALSE(without.contains("occluded_cluster_links"));
    CHECK(steady("--threads 2") == without);

    nlohmann::json caps = nlohmann::json::parse(Cli("capabilities --json").out);
    CHECK(caps["cluster_transfers"].size() == ClusterTransfers().size());
    for (const nlohmann::json &option : caps["options"])
        if (option["name"] == "clusters" || option["name"] == "cluster_transfer") {
            CHECK(std::count(option["commands"].begin(), option["commands"].end(), "solve") == 1);
            if (option["name"] == "cluster_transfer")
                CHECK(option["choices"] == nlohmann::json{"projected", "isotropic"});
        }
    hrbench_test::CheckError(scene + "--cluster-transfer isotropic", 2, "add --clusters");
    hrbench_test::CheckError(scene + "--clusters --cluster-transfer sideways", 2,
                             "unknown cluster_transfer 'sideways'");
    hrbench_test::CheckError("run enclosure n=16 --eps 0.1 --cluster-transfer isotropic", 2,
                             "does not apply to run");
}

// The figures of docs/solve.md (Clusters): run by name, prints one line per scene and
// transfer.
TEST_CASE("cluster-figures", "[.cluster-figures]") {
    struct Case {
        std::string name;
        Scene scene;
        std::vector<RefineOptions> refines;
    };
    std::vector<Case> cases = {
        {"enclosure-256", LitEnclosure(256, 0.7), {Refining(0.05, 0.005), Refining(0.1, 0.005)}},
        {"room", MakeScene("room", {{"lamp", 1}}), {Refining(0.05, 0.01)}},
        {"cornell", MakeScene("cornell", {}), {Refining(0.05, 0.002), Refining(0.2, 0.002)}},
        {"gridbox-6",
         GridBox(6, 0.6),
         {Refining(0.05, 0.01), Refining(0.2, 0.01), Refining(0.2, 0.04)}},
        {"sphere-12", Sphere(12, 0.6), {Refining(0.05, 0.01), Refining(0.2, 0.01)}},
        {"sphere-8", Sphere(8, 0.6), {Refining(0.2, 0.01), Refining(0.2, 0.04)}},
    };
    for (const Case &c : cases)
        for (const RefineOptions &refine : c.refines) {
            SolveResult u = Solve(c.scene, refine, Solving(1e-10));
            std::cout << c.name << " eps " << refine.eps << " min-area " << refine.minArea
                      << ": leaves " << u.leaves.size() << " links " << u.record.counters.links
                      << " imbalance " << Imbalance(u) << " solve s " << u.solve.wall << "\n";
            RefineOptions clustered = refine;
            clustered.clusters = true;
            for (ClusterTransferKind kind : {kProjected, kIsotropic}) {
                SolveResult s = Solve(c.scene, clustered, Solving(1e-10, kind));
                Difference d = Differ(s, u, SubdivisionArity(refine.subdivision));
                const Counters &k = s.record.counters;
                std::cout << "  " << ClusterTransferName(kind) << ": leaves " << s.leaves.size()
                          << " element links " << k.elementLinks << " cluster links "
                          << k.clusterLinks << " share " << s.clusters->transferShare
                          << " imbalance " << Imbalance(s) << " max " << d.max << " l2 " << d.l2
                          << " iterations " << u.iterations << " -> " << s.iterations << " solve s "
                          << s.solve.wall << " coefficients s " << u.coefficients.wall << " -> "
                          << s.coefficients.wall << "\n";
            }
        }
}

TEST_CASE("The direction table holds a projected measure exactly at its directions and "
          "close to it between them",
          "[solve][clusters]") {
    // Three patches of mixed normals, as a cluster of them tables them.
    std::vector<std::pair<Vec3, double>> patches = {
        {Vec3(0, 0, 1), 2.0}, {Vec3(1, 1, 0).normalized(), 1.0}, {Vec3(-1, 2, -2) / 3, 0.5}};
    auto exact = [&](const Vec3 &u) {
        double sum = 0;
        for (auto [n, area] : patches)
            sum += area * std::max(0.0, n.dot(u));
        return sum;
    };
    using Table = DirectionTable<3>;
    std::vector<double> table(Table::kSize);
    for (size_t m = 0; m < Table::kSize; ++m)
        table[m] = exact(Table::Direction(m));
    auto tabled = [&](const Vec3 &u) {
        auto lookup = Table::Lookup(u);
        double sum = 0;
        for (size_t w = 0; w < lookup.index.size(); ++w)
            sum += lookup.weight[w] * table[lookup.index[w]];
        return sum;
    };
    for (size_t m = 0; m < Table::kSize; ++m)
        CHECK(tabled(Table::Direction(m)) == Approx(table[m]).margin(1e-12));
    // Between directions: within 6% of the total area (3.5) over a spiral of directions.
    double worst = 0;
    for (int k = 0; k < 2000; ++k) {
        double z = 1 - (2 * k + 1) / 2000.0, phi = k * M_PI * (3 - std::sqrt(5.0));
        Vec3 u(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
        worst = std::max(worst, std::abs(tabled(u) - exact(u)));
    }
    CHECK(worst < 0.06 * 3.5);
    // 2D: linear in angle between 64 directions, so exact at them (any values).
    using Circle = DirectionTable<2>;
    for (size_t m = 0; m < Circle::kSize; ++m) {
        auto lookup = Circle::Lookup(Circle::Direction(m));
        double value = 0;
        for (size_t w = 0; w < 2; ++w)
            value += lookup.weight[w] * double(lookup.index[w] * lookup.index[w] + 1);
        CHECK(value == Approx(double(m * m + 1)).margin(1e-9));
    }
}

TEST_CASE("A cluster link is weighed by the share of unblocked segments between its ends' "
          "sample patches",
          "[solve][clusters][3d]") {
    // X = {p0, p1} at z = 0 facing +z, Y = {p2, p3} at z = 10 facing -z, and a blocker
    // p4 in the plane z = 5 over x in [x0, x1], y in [-1, 2].
    auto solve = [&](double x0, double x1) {
        Patches<Polygon> patches = {
            Square(0, 0, true, 0, 1),
            Square(1, 0, true, 0, 2),
            Square(0, 10, false, 0.5, 0),
            Square(1, 10, false, 0.5, 0),
            {Polygon::Quad({x0, -1, 5}, {x1, -1, 5}, {x1, 2, 5}, {x0, 2, 5}), {0, 0}}};
        RefineOptions refine = Refining(1, 0);
        refine.visibility = VisibilityMode::Fraction;
        refine.raysPerSide = 2;  // two sample patches an end: all four segments
        Refinement<Polygon> r{Forest<Polygon>(patches, SIZE_MAX, refine.subdivision),
                              {},
                              {},
                              {},
                              ClusterTree<Polygon>(patches),
                              {},
                              {}};
        // Split along z: {p0, p1} is cluster 1; {p4, p2, p3} cluster 2, {p2, p3} cluster 3.
        REQUIRE(r.clusters[1].children[0] == 0);
        REQUIRE(r.clusters[3].children[0] == 2);
        r.clusterLinks = {{ClusterNode(1), ClusterNode(3)}};
        SolveOptions options = Solving(1e-14);
        options.plainGather = true;
        return SolveRefinement(Scene{"file", {}, "", patches}, r, refine, options);
    };
    // The segments between the centroids x = 0.5, 1.5 cross z = 5 at x = 0.5, 1, 1, 1.5.
    const double unblocked = 1.5 * 2 * 2 / (M_PI * 100) / 2 * 0.5;  // B_Y, as in the test above
    for (auto [x0, x1, visible, occluded] : {std::tuple{3.0, 4.0, 1.0, 0},  // beside the path
                                             {-1.0, 0.9, 0.75, 0},          // blocks x = 0.5
                                             {-1.0, 1.2, 0.25, 0},          // and both x = 1
                                             {-1.0, 3.0, 0.0, 1}}) {        // all four
        INFO("blocker over x in [" << x0 << ", " << x1 << "]");
        SolveResult s = solve(x0, x1);
        CHECK(s.leaves[2].radiosity == Approx(unblocked * visible).margin(1e-15));
        CHECK(s.clusters->rays == 4);
        CHECK(s.clusters->occludedLinks == uint64_t(occluded));
    }
}

namespace {

// A regular tetrahedron's four faces, facing out, of reflectance _rho_, centred at
// _centre_ with corners at distance _size_ from it.
Patches<Polygon> Tetrahedron(Vec3 centre, double size, double rho) {
    double k = size / std::sqrt(3.0);
    Vec3 a = centre + k * Vec3{1, 1, 1}, b = centre + k * Vec3{1, -1, -1},
         c = centre + k * Vec3{-1, 1, -1}, d = centre + k * Vec3{-1, -1, 1};
    Patches<Polygon> faces;
    for (auto [p, q, r, far] : {std::tuple{a, b, c, d}, {a, b, d, c}, {a, c, d, b}, {b, c, d, a}}) {
        Polygon t = Polygon::Triangle(p, q, r);
        if (t.Normal().dot(far - p) > 0)  // facing the fourth corner: inward
            t = Polygon::Triangle(p, r, q);
        faces.push_back({t, {rho, 0}});
    }
    return faces;
}

// GridBox(n, rho) with every corner computed from its grid indices alone, so that the
// cells that share a corner give it the same coordinates (GridBox's a + u / n need not
// equal the next cell's a), as IsClosed compares them.
Scene ExactGridBox(int n, double rho) {
    Scene s = GridBox(n, rho);
    for (auto &patch : s.Get<Polygon>())
        for (int k = 0; k < patch.shape.n; ++k)
            for (int c = 0; c < 3; ++c)
                patch.shape.v[k][c] = std::round(patch.shape.v[k][c] * n) / n;
    return s;
}

// ExactGridBox(n, rho) with the tetrahedron of _size_ at its centre.
Scene BoxWithTetrahedron(int n, double rho, double size) {
    Scene s = ExactGridBox(n, rho);
    for (const auto &face : Tetrahedron({0.5, 0.5, 0.5}, size, 0.5))
        s.Get<Polygon>().push_back(face);
    return s;
}

}  // namespace

TEST_CASE("IsClosed holds when every edge is run back by one other patch and every part "
          "lies inside a part facing inward",
          "[solve][clusters][3d]") {
    CHECK(IsClosed(ExactGridBox(6, 0.5)));
    CHECK_FALSE(IsClosed(GridBox(6, 0.5)));  // corners that differ in the last bit
    CHECK(IsClosed(BoxWithTetrahedron(4, 0.5, 0.2)));
    // The sphere's seam: its corners at longitude 2 pi differ from those at 0 in the last
    // bit (sin(2 pi) is not 0), and corners are compared exactly.
    CHECK_FALSE(IsClosed(Sphere(8, 0.5)));
    Scene open = ExactGridBox(3, 0.5);
    open.Get<Polygon>().pop_back();  // a hole: the edges around it are run one way only
    CHECK_FALSE(IsClosed(open));
    Scene outward = ExactGridBox(3, 0.5);  // every face turned: the box faces out, fronts unbounded
    for (auto &patch : outward.Get<Polygon>())
        std::swap(patch.shape.v[1], patch.shape.v[3]);
    CHECK_FALSE(IsClosed(outward));
    CHECK_FALSE(IsClosed(Scene{"file", {}, "", Tetrahedron({0, 0, 0}, 1, 0.5)}));
    Scene beside = ExactGridBox(3, 0.5);  // a closed tetrahedron outside the box's bounding box
    for (const auto &face : Tetrahedron({3, 0.5, 0.5}, 0.2, 0.5))
        beside.Get<Polygon>().push_back(face);
    CHECK_FALSE(IsClosed(beside));
    Scene twice = ExactGridBox(3, 0.5);  // a face given twice: its edges run the same way twice
    twice.Get<Polygon>().push_back(twice.Get<Polygon>()[0]);
    CHECK_FALSE(IsClosed(twice));
    CHECK(IsClosed(MakeScene("enclosure", {{"n", 7}})));
    CHECK_FALSE(IsClosed(MakeScene("parallel", {})));
}

TEST_CASE("Through clusters, the reciprocal scale makes each leaf's row exact and keeps "
          "power the same both ways, so closed scenes balance",
          "[solve][clusters][3d]") {
    SECTION("a closed box that cannot occlude, rows to their exact form factor sums") {
        // The consistent gather's imbalance here was 0.0197 (Through clusters, energy
        // balances ...): reciprocity broken by the per-leaf scale.
        SolveResult s = Solve(GridBox(6, 0.6), Refining(0.2, 0.04, true), Solving(1e-12));
        REQUIRE(s.record.counters.clusterLinks > 0);
        CHECK(s.gather == "reciprocal");
        CHECK(s.reciprocalError < 1e-10);
        CHECK(Imbalance(s) < 1e-9);
    }
    SECTION("a closed box with a tetrahedron in it, occluded, rows to 1") {
        RefineOptions refine = Refining(0.2, 0.02, true);
        refine.visibility = VisibilityMode::Fraction;
        Scene scene = BoxWithTetrahedron(6, 0.6, 0.25);
        SolveResult s = Solve(scene, refine, Solving(1e-12));
        REQUIRE(s.record.counters.clusterLinks > 0);
        CHECK(s.gather == "reciprocal");
        CHECK(Imbalance(s) < 1e-9);
        SolveOptions plain = Solving(1e-12);
        plain.plainGather = true;
        SolveResult p = Solve(scene, refine, plain);
        CHECK(p.gather == "plain");
        INFO("plain gather's imbalance " << Imbalance(p));
        CHECK(Imbalance(p) > 100 * Imbalance(s));
        // The same bit for bit on 3 threads.
        refine.threads = 3;
        SolveResult t = Solve(scene, refine, Solving(1e-12));
        CHECK(Radiosities(t) == Radiosities(s));
        CHECK(t.absorbedPower == s.absorbedPower);
        CHECK(t.reciprocalSteps == s.reciprocalSteps);
    }
    SECTION("the closed occluded box with uniform emission has B = E / (1 - rho) = 2") {
        // Every row goes to 1, so a uniform B is reproduced exactly, occluders and all.
        RefineOptions refine = Refining(0.2, 0.02, true);
        refine.visibility = VisibilityMode::Fraction;
        Scene scene = BoxWithTetrahedron(6, 0.5, 0.25);
        for (auto &patch : scene.Get<Polygon>())
            patch.material = {0.5, 1};
        SolveResult s = Solve(scene, refine, Solving(1e-12));
        CHECK(s.gather == "reciprocal");
        for (const ElementRadiosity &leaf : s.leaves)
            CHECK(leaf.radiosity == Approx(2).epsilon(1e-9));
        CHECK(Imbalance(s) < 1e-9);
    }
    SECTION("an open box, occluded, its rows unknown, stays plain") {
        RefineOptions refine = Refining(0.2, 0.02, true);
        refine.visibility = VisibilityMode::Fraction;
        Scene scene = BoxWithTetrahedron(6, 0.6, 0.25);
        auto &faces = scene.Get<Polygon>();
        faces.erase(faces.begin(), faces.begin() + 36);  // the floor z = 0
        SolveResult s = Solve(scene, refine, Solving(1e-12));
        REQUIRE(s.record.counters.clusterLinks > 0);
        CHECK(s.gather == "plain");
        CHECK(s.absorbedPower < s.emittedPower);  // light leaves through the opening
    }
    SECTION("the 2D enclosure with uniform emission stays exact") {
        Scene enclosure = LitEnclosure(256, 0.5);
        for (auto &patch : enclosure.Get<Segment>())
            patch.material.emission = 1;
        SolveResult s = Solve(enclosure, Refining(0.1, 0.005, true), Solving(1e-12));
        CHECK(s.gather == "reciprocal");
        for (const ElementRadiosity &leaf : s.leaves)
            CHECK(leaf.radiosity == Approx(2).epsilon(1e-9));
        CHECK(Imbalance(s) < 1e-9);
    }
}
