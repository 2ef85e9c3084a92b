// The solve through cluster links (`--clusters`, docs/solve.md, Clusters): the tree's
// numbering, one cluster link by hand, energy balance and uniform radiosity in closed
// scenes, agreement with the solve without clusters, determinism across thread counts and
// the output. The clustered
// refinements here are made from a refinement without clusters: a top-down pairing of
// the cluster tree links every pair of nodes whose bounding balls are far apart, and the
// element links of the root pairs it reaches keep the light between them.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "hrbench/generators/generators.h"
#include "hrbench/hrbench.h"

using namespace hrbench;

namespace {

RefineOptions Refining(double eps, double minArea) {
    RefineOptions o;
    o.eps = eps;
    o.minArea = minArea;
    o.storeLinks = true;
    return o;
}

SolveOptions Solving(double tolerance, SolveMethod method = SolveMethod::Jacobi) {
    SolveOptions o;
    o.tolerance = tolerance;
    o.method = method;
    return o;
}

// The ball of a node: a cluster's, or for a root patch the centre of its corners' box
// and the largest distance to a corner.
template <typename Shape>
std::pair<Vector<Shape::kDimension>, double> BallOf(const Patches<Shape> &patches,
                                                    const ClusterTree<Shape> &tree,
                                                    uint32_t node) {
    if (IsCluster(node))
        return {tree[ClusterIndex(node)].center, tree[ClusterIndex(node)].radius};
    std::vector<Vector<Shape::kDimension>> corners;
    const Shape &s = patches[node].shape;
    if constexpr (Shape::kDimension == 2) {
        corners = {s.a, s.b};
    } else {
        for (int k = 0; k < s.n; ++k)
            corners.push_back(s.v[size_t(k)]);
    }
    Vector<Shape::kDimension> low = corners[0], high = corners[0];
    for (const auto &c : corners)
        low = low.cwiseMin(c), high = high.cwiseMax(c);
    Vector<Shape::kDimension> center = 0.5 * (low + high);
    double radius = 0;
    for (const auto &c : corners)
        radius = std::max(radius, (c - center).norm());
    return {center, radius};
}

// _options_' refinement of _scene_ through its cluster tree: from the root cluster with
// itself, a pair of distinct nodes is linked when their centres are more than
// _separation_ times the sum of their radii apart and the larger of the two isotropic
// form factors, A_other / (16 pi r^2) in 3D or A_other / (2 pi^2 r) in 2D, is below
// options.eps; else the larger cluster is split. A pair of root patches keeps the element
// links the refinement made between them.
template <typename Shape>
Refinement<Shape> Clustered(const Scene &scene, const RefineOptions &options, double separation) {
    const Patches<Shape> &patches = scene.Get<Shape>();
    Refinement<Shape> r = Refine<Shape>(scene, options);
    r.clusters = ClusterTree<Shape>(patches);
    const ClusterTree<Shape> &tree = r.clusters;
    std::set<std::pair<uint32_t, uint32_t>> rootPairs;
    std::function<void(uint32_t, uint32_t)> pair = [&](uint32_t x, uint32_t y) {
        if (x == y) {
            if (IsCluster(x)) {
                const uint32_t *c = tree[ClusterIndex(x)].children;
                pair(c[0], c[0]), pair(c[0], c[1]), pair(c[1], c[1]);
            }
            return;
        }
        if (!IsCluster(x) && !IsCluster(y)) {
            rootPairs.insert(std::minmax(x, y));
            return;
        }
        auto [cx, rx] = BallOf(patches, tree, x);
        auto [cy, ry] = BallOf(patches, tree, y);
        double dist = (cx - cy).norm(), larger = 0;
        for (uint32_t node : {x, y}) {
            double measure = IsCluster(node) ? tree[ClusterIndex(node)].measure
                                             : patches[node].shape.Measure();
            larger = std::max(larger, Shape::kDimension == 3
                                          ? measure / (16 * M_PI * dist * dist)
                                          : measure / (2 * M_PI * M_PI * dist));
        }
        if (dist > separation * (rx + ry) && larger < options.eps) {
            r.clusterLinks.push_back({x, y});
            return;
        }
        bool splitX = IsCluster(x) && (!IsCluster(y) || rx >= ry);
        uint32_t split = splitX ? x : y, other = splitX ? y : x;
        for (uint32_t child : tree[ClusterIndex(split)].children)
            pair(child, other);
    };
    if (tree.NumClusters() > 0)
        pair(ClusterNode(0), ClusterNode(0));
    LinkBuffer kept;
    kept.Reserve(r.links.size());
    for (const Link &l : r.links)
        if (rootPairs.count(std::minmax(r.forest[l.i].root, r.forest[l.j].root)))
            kept.Append(l);
    r.links = std::move(kept);
    r.record.counters.links = r.links.size();
    return r;
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
                quads.push_back({Polygon::Quad(a, a + du, a + du + dv, a + dv),
                                 {rho, lamp ? 1.0 : 0.0}});
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

double Imbalance(const SolveResult &r) {
    return std::abs(r.absorbedPower - r.emittedPower) / r.emittedPower;
}

// Relative differences of the leaves' radiosity of _a_ from _b_ (the same leaves): the
// largest over max |B_b|, and the area-weighted L2 norm over that of B_b.
struct Difference {
    double max = 0, l2 = 0;
};

Difference Differ(const SolveResult &a, const SolveResult &b) {
    REQUIRE(a.leaves.size() == b.leaves.size());
    double largest = 0, worst = 0, diff2 = 0, norm2 = 0;
    for (size_t k = 0; k < a.leaves.size(); ++k) {
        REQUIRE(a.leaves[k].element == b.leaves[k].element);
        double d = a.leaves[k].radiosity - b.leaves[k].radiosity, m = b.leaves[k].measure;
        largest = std::max(largest, std::abs(b.leaves[k].radiosity));
        worst = std::max(worst, std::abs(d));
        diff2 += m * d * d, norm2 += m * b.leaves[k].radiosity * b.leaves[k].radiosity;
    }
    return {worst / largest, std::sqrt(diff2 / norm2)};
}

std::vector<double> Radiosities(const SolveResult &r) {
    std::vector<double> b;
    for (const ElementRadiosity &leaf : r.leaves)
        b.push_back(leaf.radiosity);
    return b;
}

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

TEST_CASE("One cluster link between two clusters of two segments, by hand",
          "[solve][clusters]") {
    // X = {p0, p1} facing +x at x = 0 and 0.5, Y = {p2, p3} facing -x at x = 10 and 10.5.
    // X emits and does not reflect, Y reflects and does not emit: one gather is final.
    Patches<Segment> patches = {{{{0, 1}, {0, 0}}, {0, 1}},
                                {{{0.5, 2}, {0.5, 0}}, {0, 3}},
                                {{{10, 0}, {10, 1}}, {0.5, 0}},
                                {{{10.5, 0}, {10.5, 3}}, {0.8, 0}}};
    Scene scene{"file", {}, "", patches};
    RefineOptions refine = Refining(1, 0);
    Refinement<Segment> r{Forest<Segment>(patches, SIZE_MAX, refine.subdivision), {}, {}, {},
                          ClusterTree<Segment>(patches), {}};
    // The median split along x: cluster 1 = {p0, p1}, cluster 2 = {p2, p3}.
    REQUIRE(r.clusters.NumClusters() == 3);
    REQUIRE(r.clusters[1].children[0] == 0);
    REQUIRE(r.clusters[1].children[1] == 1);
    REQUIRE(r.clusters[2].children[0] == 2);
    REQUIRE(r.clusters[2].children[1] == 3);
    SolveOptions options = Solving(1e-14);
    options.plainGather = true;
    const double k2 = 1 / (2 * M_PI * M_PI);  // (1/pi)(1/pi) / 2

    SECTION("cluster to cluster: both ends isotropic") {
        r.clusterLinks = {{ClusterNode(1), ClusterNode(2)}};
        SolveResult s = SolveRefinement(scene, r, refine, options);
        // Centres: area-weighted centroids (1/3, 5/6) and (10.375, 1.25).
        double dist = std::hypot(10.375 - 1.0 / 3, 1.25 - 5.0 / 6);
        double bX = (1 * 1 + 2 * 3) / 3.0;  // pulled: area-weighted mean of E
        double hY = bX * 3 * k2 / dist;
        double bY = (1 * 0.5 * hY + 3 * 0.8 * hY) / 4;
        double hX = bY * 4 * k2 / dist;
        std::vector<double> b = {1, 3, 0.5 * hY, 0.8 * hY}, h = {hX, hX, hY, hY};
        for (size_t p = 0; p < 4; ++p) {
            CHECK(s.leaves[p].radiosity == Approx(b[p]).epsilon(1e-13));
            CHECK(s.leaves[p].irradiance == Approx(h[p]).epsilon(1e-13));
        }
        CHECK(s.emittedPower == 7);
        CHECK(s.absorbedPower == Approx(3 * hX + 0.5 * hY + 0.2 * 3 * hY).epsilon(1e-13));
        REQUIRE(s.clusters);
        CHECK(s.clusters->clusters == 3);
        CHECK(s.clusters->links == 1);
        CHECK(s.clusters->transferShare == 1);
    }
    SECTION("patch to cluster: the patch end keeps its cosine") {
        r.clusterLinks = {{0, ClusterNode(2)}};
        SolveResult s = SolveRefinement(scene, r, refine, options);
        double dx = 10.375, dy = 1.25 - 0.5, dist = std::hypot(dx, dy);
        double cosine = dx / dist;  // p0's normal is +x
        double kernel = cosine * (1 / M_PI) / (2 * dist);
        double hY = 1 * 1 * kernel;  // B_p0 A_p0
        CHECK(s.leaves[2].radiosity == Approx(0.5 * hY).epsilon(1e-13));
        CHECK(s.leaves[3].radiosity == Approx(0.8 * hY).epsilon(1e-13));
        double bY = (0.5 * hY + 3 * 0.8 * hY) / 4;
        CHECK(s.leaves[0].irradiance == Approx(bY * 4 * kernel).epsilon(1e-13));
        CHECK(s.leaves[1].irradiance == 0);  // p1 takes no part
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
        Refinement<Segment> f{Forest<Segment>(flipped, SIZE_MAX, refine.subdivision), {}, {},
                              {}, ClusterTree<Segment>(flipped), r.clusterLinks};
        SolveResult t = SolveRefinement(away, f, refine, options);
        CHECK(t.leaves[2].radiosity == 0);
        CHECK(t.leaves[3].radiosity == 0);
    }
}

TEST_CASE("A 3D cluster link transfers B A / (16 pi r^2) between isotropic ends",
          "[solve][clusters][3d]") {
    // Two clusters of two unit squares each, 10 apart along z.
    auto square = [](double x, double z, bool up, double rho, double e) {
        Vec3 a{x, 0, z}, b{x + 1, 0, z}, c{x + 1, 1, z}, d{x, 1, z};
        return Patch<Polygon>{up ? Polygon::Quad(a, b, c, d) : Polygon::Quad(a, d, c, b),
                              {rho, e}};
    };
    Patches<Polygon> patches = {square(0, 0, true, 0, 1), square(1, 0, true, 0, 2),
                                square(0, 10, false, 0.5, 0), square(1, 10, false, 0.5, 0)};
    Scene scene{"file", {}, "", patches};
    RefineOptions refine = Refining(1, 0);
    Refinement<Polygon> r{Forest<Polygon>(patches, SIZE_MAX, refine.subdivision), {}, {}, {},
                          ClusterTree<Polygon>(patches), {}};
    REQUIRE(r.clusters.NumClusters() == 3);
    REQUIRE(r.clusters[1].begin == 0);  // {p0, p1}: the split is along z
    r.clusterLinks = {{ClusterNode(1), ClusterNode(2)}};
    SolveOptions options = Solving(1e-14);
    options.plainGather = true;
    SolveResult s = SolveRefinement(scene, r, refine, options);
    double hY = 1.5 * 2 / (16 * M_PI * 100);
    CHECK(s.leaves[2].radiosity == Approx(0.5 * hY).epsilon(1e-13));
    CHECK(s.leaves[3].radiosity == Approx(0.5 * hY).epsilon(1e-13));
}

TEST_CASE("Through clusters, a closed scene of uniform emission has B = E / (1 - rho)",
          "[solve][clusters]") {
    // The consistency scale counts the cluster coefficients: uniform B stays exact.
    Scene enclosure = LitEnclosure(32, 0.5);
    for (auto &patch : enclosure.Get<Segment>())
        patch.material.emission = 1;
    Refinement<Segment> r = Clustered<Segment>(enclosure, Refining(0.05, 0.02), 1.5);
    REQUIRE(r.clusterLinks.size() > 0);
    SolveResult s = SolveRefinement(enclosure, r, Refining(0.05, 0.02), Solving(1e-12));
    for (const ElementRadiosity &leaf : s.leaves)
        CHECK(leaf.radiosity == Approx(2).epsilon(1e-9));
    CHECK(Imbalance(s) < 1e-9);
}

TEST_CASE("Through clusters, energy balances in closed scenes and the radiosity stays near "
          "the solve without clusters",
          "[solve][clusters]") {
    // Bounds: the figures of "[.cluster-figures]" (docs/solve.md, Clusters) with a margin
    // of about 1.4. The isotropic cosine misjudges surfaces that face each other (1/pi^2
    // of the transfer between two facing arcs of the enclosure, 1/16 between facing
    // walls of the box), which the consistency scale turns into a redistribution of B.
    SECTION("2D enclosure") {
        Scene scene = LitEnclosure(64, 0.7);
        RefineOptions refine = Refining(0.01, 0.01);
        Refinement<Segment> plain = Refine<Segment>(scene, refine);
        Refinement<Segment> clustered = Clustered<Segment>(scene, refine, 2);
        REQUIRE(clustered.clusterLinks.size() == 336);
        for (SolveMethod method : {SolveMethod::Jacobi, SolveMethod::GaussSeidel}) {
            SolveResult u = SolveRefinement(scene, plain, refine, Solving(1e-10, method));
            SolveResult c = SolveRefinement(scene, clustered, refine, Solving(1e-10, method));
            Difference d = Differ(c, u);
            INFO(SolveMethodName(method) << " imbalance " << Imbalance(c) << " max " << d.max
                                         << " l2 " << d.l2);
            CHECK(c.energyWarning.empty());
            CHECK(Imbalance(c) < 1e-6);  // measured 6.2e-9
            CHECK(d.l2 < 0.1);           // 0.072
            CHECK(d.max < 0.032);        // 0.023
            CHECK(c.clusters->transferShare == Approx(0.478).margin(0.001));
        }
    }
    SECTION("3D closed mesh") {
        Scene scene = GridBox(3, 0.6);
        RefineOptions refine = Refining(0.02, 0.02);
        Refinement<Polygon> plain = Refine<Polygon>(scene, refine);
        Refinement<Polygon> clustered = Clustered<Polygon>(scene, refine, 1.5);
        REQUIRE(clustered.clusterLinks.size() == 265);
        SolveResult u = SolveRefinement(scene, plain, refine, Solving(1e-10));
        SolveResult c = SolveRefinement(scene, clustered, refine, Solving(1e-10));
        Difference d = Differ(c, u);
        INFO("imbalance " << Imbalance(c) << " max " << d.max << " l2 " << d.l2);
        CHECK(c.energyWarning.empty());
        CHECK(Imbalance(c) < 0.12);  // measured 0.082
        CHECK(d.l2 < 0.07);          // 0.048
        CHECK(d.max < 0.02);         // 0.014
    }
    SECTION("cornell") {
        Scene scene = MakeScene("cornell", {});
        RefineOptions refine = Refining(0.01, 0.002);
        Refinement<Polygon> plain = Refine<Polygon>(scene, refine);
        Refinement<Polygon> clustered = Clustered<Polygon>(scene, refine, 1.5);
        REQUIRE(clustered.clusterLinks.size() == 1);
        SolveResult u = SolveRefinement(scene, plain, refine, Solving(1e-8));
        SolveResult c = SolveRefinement(scene, clustered, refine, Solving(1e-8));
        Difference d = Differ(c, u);
        INFO("imbalance " << Imbalance(c) << " max " << d.max << " l2 " << d.l2);
        CHECK(Imbalance(c) < 0.015);  // measured 0.010
        CHECK(d.l2 < 0.025);          // 0.019
        CHECK(d.max < 0.022);         // 0.016
    }
}

TEST_CASE("The solve through clusters is the same bit for bit on 1 and 2 threads",
          "[solve][clusters]") {
    Scene scene = GridBox(3, 0.6);
    RefineOptions one = Refining(0.02, 0.02), two = one;
    two.threads = 2;
    for (SolveMethod method : {SolveMethod::Jacobi, SolveMethod::GaussSeidel}) {
        SolveResult a = SolveRefinement(scene, Clustered<Polygon>(scene, one, 1.5), one,
                                        Solving(1e-10, method));
        SolveResult b = SolveRefinement(scene, Clustered<Polygon>(scene, two, 1.5), two,
                                        Solving(1e-10, method));
        CHECK(Radiosities(a) == Radiosities(b));
        CHECK(a.iterations == b.iterations);
        CHECK(a.absorbedPower == b.absorbedPower);
        CHECK(a.clusters->transferShare == b.clusters->transferShare);
    }
}

TEST_CASE("The solve's JSON gives the cluster figures only with a cluster tree",
          "[solve][clusters]") {
    Scene scene = LitEnclosure(16, 0.5);
    RefineOptions refine = Refining(0.05, 0.05);
    Refinement<Segment> clustered = Clustered<Segment>(scene, refine, 1.5);
    SolveOptions options = Solving(1e-8);
    nlohmann::json with =
        SolveToJson(scene, refine, options, SolveRefinement(scene, clustered, refine, options));
    CHECK(with["clusters"] == 15);
    CHECK(with["cluster_links"] == clustered.clusterLinks.size());
    CHECK(with["cluster_transfer_share"].get<double>() > 0);
    CHECK(with["cluster_transfer_share"].get<double>() < 1);
    std::ostringstream table;
    PrintSolveTable(with, table);
    CHECK(table.str().find("cluster_links") != std::string::npos);
    nlohmann::json without = SolveToJson(scene, refine, options, Solve(scene, refine, options));
    CHECK_FALSE(without.contains("clusters"));
    CHECK_FALSE(without.contains("cluster_links"));
    CHECK_FALSE(without.contains("cluster_transfer_share"));
    std::ostringstream plainTable;
    PrintSolveTable(without, plainTable);
    CHECK(plainTable.str().find("cluster") == std::string::npos);
}

// The figures of docs/solve.md (Clusters): run by name, prints one line per scene.
TEST_CASE("cluster-figures", "[.cluster-figures]") {
    struct Case {
        std::string name;
        Scene scene;
        RefineOptions refine;
        double separation;
    };
    Scene cornell = MakeScene("cornell", {});
    std::vector<Case> cases = {
        {"room", MakeScene("room", {{"lamp", 1}}), Refining(0.01, 0.01), 1.5},
        {"enclosure-64", LitEnclosure(64, 0.7), Refining(0.01, 0.01), 2},
        {"enclosure-256", LitEnclosure(256, 0.7), Refining(0.01, 0.005), 2},
        {"cornell", cornell, Refining(0.01, 0.002), 1.5},
        {"gridbox-3", GridBox(3, 0.6), Refining(0.02, 0.02), 1.5},
        {"gridbox-6", GridBox(6, 0.6), Refining(0.05, 0.01), 1.5},
    };
    auto seconds = [](auto f) {
        auto t = std::chrono::steady_clock::now();
        auto r = f();
        return std::make_pair(
            std::move(r),
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
    };
    for (const Case &c : cases) {
        std::visit(
            [&](const auto &patches) {
                using Shape = std::decay_t<decltype(patches.front().shape)>;
                Refinement<Shape> plain = Refine<Shape>(c.scene, c.refine);
                for (double separation : {c.separation, 2 * c.separation}) {
                    Refinement<Shape> clustered = Clustered<Shape>(c.scene, c.refine, separation);
                    auto [u, tu] = seconds(
                        [&] { return SolveRefinement(c.scene, plain, c.refine, Solving(1e-10)); });
                    auto [s, ts] = seconds([&] {
                        return SolveRefinement(c.scene, clustered, c.refine, Solving(1e-10));
                    });
                    SolveOptions plainGather = Solving(1e-10);
                    plainGather.plainGather = true;
                    SolveResult pu = SolveRefinement(c.scene, plain, c.refine, plainGather);
                    SolveResult ps = SolveRefinement(c.scene, clustered, c.refine, plainGather);
                    Difference pd = Differ(ps, pu);
                    std::cout << "  plain gather: imbalance " << Imbalance(pu) << " -> "
                              << Imbalance(ps) << " | diff max " << pd.max << " l2 " << pd.l2
                              << "\n";
                    Difference d = Differ(s, u);
                    std::cout << c.name << " separation " << separation << ": patches "
                              << patches.size() << " leaves " << s.leaves.size() << " links "
                              << plain.links.size() << " -> " << clustered.links.size()
                              << " + cluster links " << clustered.clusterLinks.size()
                              << " share " << s.clusters->transferShare << " | imbalance "
                              << Imbalance(u) << " -> " << Imbalance(s) << " | diff max "
                              << d.max << " l2 " << d.l2 << " | iterations " << u.iterations
                              << " -> " << s.iterations << " | seconds " << tu << " -> " << ts
                              << " (solve stage " << u.solve.wall << " -> " << s.solve.wall
                              << ")\n";
                }
            },
            c.scene.patches);
    }
}
