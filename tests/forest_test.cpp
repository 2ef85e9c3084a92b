// The element trees of a scene (forest.h), for both shapes: children created once and
// shared, canonical positions, the tree counters, and the two limits a forest enforces
// (the memory budget and double precision).
#include <catch2/catch.hpp>

#include <cmath>

#include "hrbench/hrbench.h"

using namespace hrbench;

namespace {

Polygon UnitSquare() { return Polygon::Quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}); }

Patches<Polygon> SquareAndTriangle() {
    return {{UnitSquare(), {}}, {Polygon::Triangle({0, 0, 1}, {0, 1, 1}, {1, 0, 1}), {}}};
}

// Kept for the whole test run: a forest reads its roots' shapes from its patches.
const Patches<Segment> &TwoSegments() {
    static const Patches<Segment> patches = {{{Vec2(0, 0), Vec2(8, 0)}, {}},
                                             {{Vec2(8, 1), Vec2(0, 1)}, {}}};
    return patches;
}

// Descends through the first child of _e_ until the forest refuses; returns the depth
// reached and the message of the error (empty when none came within 300 levels).
template <typename Shape>
std::pair<int, std::string> DescendUntilRefused(Forest<Shape> &f, uint32_t e) {
    for (int depth = 0; depth < 300; ++depth) {
        try {
            e = f.Children(e);
        } catch (const LimitError &error) {
            return {depth, error.what()};
        }
    }
    return {300, ""};
}

}  // namespace

TEST_CASE("Segment forests halve elements once, first half first", "[forest][2d]") {
    Forest<Segment> f(TwoSegments(), 1000, Subdivision::Binary);
    CHECK(f.Arity() == 2);
    CHECK(f.Mode() == Subdivision::Binary);
    REQUIRE(f.Size() == 2);
    CHECK(f.NumRoots() == 2);
    CHECK(f[0].sizeSquared == 64);  // the hot record holds A^2
    CHECK(f[0].Size() == 8);
    CHECK(f[0].center == Vec2(4, 0));
    CHECK(f[1].root == 1);
    CHECK(f[0].firstChild == kNoChildren);
    uint32_t c = f.Children(1);
    CHECK(c == 2);
    CHECK(f.Children(1) == 2);  // shared
    CHECK(f.Size() == 4);
    CHECK(f[1].firstChild == 2);
    CHECK(f.ShapeOf(2).a == Vec2(8, 1));
    CHECK(f.ShapeOf(2).b == Vec2(4, 1));
    CHECK(f.ShapeOf(3).a == Vec2(4, 1));
    CHECK(f.ShapeOf(3).b == Vec2(0, 1));
    CHECK(f[3].sizeSquared == 16);
    CHECK(f[3].center == Vec2(2, 1));
    CHECK(f[3].root == 1);
    CHECK(f.Parent(3) == 1);
    CHECK(f.Parent(1) == 1);  // a root is its own parent
    CHECK(f.Depth(3) == 1);
    CHECK(f.Depth(1) == 0);
    CHECK(f.Children(0) == 4);
    CHECK(f[4].root == 0);
    CHECK(f.NumLeaves() == 4);
    CHECK(f.NodesPerDepth() == std::vector<uint64_t>{2, 4});
}

TEST_CASE("Positions are canonical: the index along the root, whatever the creation order",
          "[forest][2d]") {
    Forest<Segment> f(TwoSegments(), 1000, Subdivision::Binary);
    uint32_t first = f.Children(0);          // [0,4] and [4,8]
    uint32_t right = f.Children(first + 1);  // the second half split first
    uint32_t left = f.Children(first);
    REQUIRE(right < left);
    CHECK(f.Position(0) == 0);
    CHECK(f.Position(first) == 0);
    CHECK(f.Position(first + 1) == 1);
    CHECK(f.Position(left) == 0);
    CHECK(f.Position(left + 1) == 1);
    CHECK(f.Position(right) == 2);
    CHECK(f.Position(right + 1) == 3);
    // The interval [t0, t1] of an element in arc length along its root (links_csv.h)
    // is rootLength * [position, position + 1] / 2^depth, and its shape lies there.
    for (uint32_t e = 0; e < f.Size(); ++e) {
        INFO("element " << e);
        const Segment &root = f.ShapeOf(f[e].root);
        double rootLength = f[f[e].root].Size();
        double t0 = rootLength * std::ldexp(double(f.Position(e)), -f.Depth(e));
        double t1 = rootLength * std::ldexp(double(f.Position(e) + 1), -f.Depth(e));
        CHECK((f.ShapeOf(e).a - root.a).norm() == t0);
        CHECK((f.ShapeOf(e).b - root.a).norm() == t1);
    }
    CHECK(f.NodesPerDepth() == std::vector<uint64_t>{2, 2, 4});
    CHECK(f.NumLeaves() == 5);
}

TEST_CASE("Ids stay as made; SplitElements lists each group's parent in that order",
          "[forest][2d]") {
    // Made out of order: root 1 first, then the second half of root 0 before its first.
    Forest<Segment> f(TwoSegments(), 1000, Subdivision::Binary);
    REQUIRE(f.Children(1) == 2);   // 2, 3: the halves of root 1
    REQUIRE(f.Children(0) == 4);   // 4, 5: the halves of root 0
    REQUIRE(f.Children(5) == 6);   // 6, 7: root 0's second half split first
    REQUIRE(f.Children(4) == 8);   // 8, 9
    REQUIRE(f.Children(2) == 10);  // 10, 11: root 1's first half
    CHECK(f.SplitElements() == std::vector<uint32_t>{1, 0, 5, 4, 2});
    CHECK(f.Parent(10) == 2);
    CHECK(f.Parent(7) == 5);
    CHECK(f.Position(7) == 3);  // root 0's last quarter
    CHECK(f.Position(9) == 1);
    CHECK(f.Depth(11) == 2);
    CHECK(f.NumLeaves() == 7);
    CHECK(f.NodesPerDepth() == std::vector<uint64_t>{2, 4, 6});
}

TEST_CASE("LiftBudget lets a forest grow past the budget it was made with", "[forest]") {
    Forest<Segment> f(TwoSegments(), 4, Subdivision::Binary);
    REQUIRE(f.Children(0) == 2);
    CHECK_THROWS_AS(f.Children(1), LimitError);
    CHECK(f.Size() == 4);
    f.LiftBudget();
    CHECK(f.Children(1) == 4);
    CHECK(f.Children(3) == 6);
    CHECK(f.Size() == 8);
}

TEST_CASE("Polygon forests create children once, first child first", "[forest][3d]") {
    Patches<Polygon> patches = SquareAndTriangle();
    SECTION("binary") {
        Forest<Polygon> f(patches, 1000, Subdivision::Binary);
        CHECK(f.Arity() == 2);
        REQUIRE(f.Size() == 2);
        CHECK(f[0].sizeSquared == 1);
        CHECK(f[1].sizeSquared == 0.25);
        CHECK(f[1].Size() == 0.5);
        uint32_t c = f.Children(0);
        CHECK(c == 2);
        CHECK(f.Children(0) == 2);  // shared
        CHECK(f.Size() == 4);
        CHECK(f[2].sizeSquared == 0.25);
        CHECK(f[2].center.isApprox(Vec3(0.25, 0.5, 0)));
        CHECK(f[3].root == 0);
        CHECK(f.Parent(3) == 0);
        CHECK(f.Depth(3) == 1);
        CHECK(f.Children(1) == 4);
        CHECK(f[4].root == 1);
        CHECK(f.NumLeaves() == 4);
        CHECK(f.NodesPerDepth() == std::vector<uint64_t>{2, 4});
        std::array<Polygon, 4> halves;
        UnitSquare().Subdivide(Subdivision::Binary, halves);
        CHECK(f.ShapeOf(2).v == halves[0].v);  // the shapes of Polygon::Subdivide, in order
        CHECK(f.ShapeOf(3).v == halves[1].v);
    }
    SECTION("quadtree") {
        Forest<Polygon> f(patches, 1000, Subdivision::Quadtree);
        CHECK(f.Arity() == 4);
        CHECK(f.Children(1) == 2);
        CHECK(f.Size() == 6);
        CHECK(f[5].sizeSquared == 0.125 * 0.125);
        CHECK(f.NumLeaves() == 5);
        // Quarters of a quarter: positions count in base 4 along the subdivision order.
        uint32_t grand = f.Children(4);
        for (int k = 0; k < 4; ++k) {
            CHECK(f.Position(2 + k) == uint64_t(k));
            CHECK(f.Position(grand + k) == uint64_t(4 * 2 + k));
            CHECK(f.Depth(grand + k) == 2);
        }
        CHECK(f.NodesPerDepth() == std::vector<uint64_t>{2, 4, 4});
    }
    SECTION("the memory budget is enforced") {
        Forest<Polygon> f(patches, 3, Subdivision::Binary);
        CHECK_THROWS_AS(f.Children(0), LimitError);
    }
}

TEMPLATE_TEST_CASE("A forest refuses to grow past its memory budget, naming the budget", "[forest]",
                   Segment, Polygon) {
    Patches<TestType> patches;
    if constexpr (TestType::kDimension == 2)
        patches = TwoSegments();
    else
        patches = SquareAndTriangle();
    Forest<TestType> f(patches, 6, Subdivision::Binary);
    f.Children(0);
    f.Children(1);
    CHECK(f.Size() == 6);
    CHECK_THROWS_WITH(f.Children(2), Catch::Contains("memory budget"));
    CHECK(f.Size() == 6);  // nothing half made
    CHECK(f[2].firstChild == kNoChildren);
    CHECK(f.Children(0) == 2);  // existing children are still shared
}

TEST_CASE("A forest refuses elements too small for double precision to split", "[forest]") {
    SECTION("a segment far from the origin for its size") {
        // [1, 2] halved towards 1: [1, 1 + 2^-52] has a midpoint that rounds to 1.
        Patches<Segment> patches{{{Vec2(1, 0), Vec2(2, 0)}, {}}};
        Forest<Segment> f(patches, 1000, Subdivision::Binary);
        auto [depth, message] = DescendUntilRefused(f, 0);
        CHECK(depth == 52);
        CHECK_THAT(message, Catch::Contains("too small for double precision"));
        CHECK_THAT(message, Catch::Contains("--min-area"));
    }
    SECTION("a polygon far from the origin for its size") {
        Patches<Polygon> patches{{Polygon::Quad({1, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}), {}}};
        Forest<Polygon> f(patches, 1000, Subdivision::Binary);
        auto [depth, message] = DescendUntilRefused(f, 0);
        CHECK(depth > 90);  // both sides halve about 52 times
        CHECK(depth < 300);
        CHECK_THAT(message, Catch::Contains("too small for double precision"));
    }
}

TEST_CASE("A reserved array grows in place and keeps its values when it must move",
          "[forest][memory]") {
    ReservedArray<Vec2> a;
    a.Reserve(1000);
    REQUIRE(a.capacity() >= 1000);
    const Vec2 *start = a.begin();
    for (int k = 0; k < 1000; ++k)
        a.push_back(Vec2(k, -k));
    CHECK(a.begin() == start);  // within the reservation nothing moved
    CHECK(a.size() == 1000);

    // Past the reservation it moves, as std::vector does, values intact.
    size_t reserved = a.capacity();
    while (a.size() <= reserved)
        a.push_back(Vec2(double(a.size()), -double(a.size())));
    CHECK(a.capacity() > reserved);
    bool intact = true;
    for (size_t k = 0; k < a.size(); ++k)
        intact &= a[k] == Vec2(double(k), -double(k));
    CHECK(intact);

    // Copies are deep and keep the reservation where it is free; moves take the storage.
    ReservedArray<Vec2> copy = a;
    copy[0] = Vec2(7, 7);
    CHECK(a[0] == Vec2(0, 0));
    CHECK(copy.size() == a.size());
    if (ReservationsAreFree())
        CHECK(copy.capacity() >= a.capacity());
    const Vec2 *storage = copy.begin();
    ReservedArray<Vec2> moved = std::move(copy);
    CHECK(moved.begin() == storage);
    CHECK(moved[0] == Vec2(7, 7));

    // An up-front reservation is made only where it costs nothing.
    size_t before = a.capacity();
    a.ReserveUpFront(100 * before);
    if (ReservationsAreFree())
        CHECK(a.capacity() >= 100 * before);
    else
        CHECK(a.capacity() == before);

    // More than the address space holds is refused, and nothing is lost.
    size_t size = a.size();
    CHECK_THROWS_AS(a.Reserve(SIZE_MAX / 4), std::bad_alloc);
    CHECK(a.size() == size);
    CHECK(a[1] == Vec2(1, -1));
}

TEST_CASE("A forest with a budget grows without moving its elements", "[forest][memory]") {
    Forest<Segment> f(TwoSegments(), 1 << 12, Subdivision::Binary);
    const auto *first = &f[0];
    for (uint32_t e = 0; f.Size() + 2 <= (1 << 12); ++e)
        f.Children(e);
    CHECK(f.Size() == (1 << 12));
    if (ReservationsAreFree())  // else it grows as std::vector does
        CHECK(&f[0] == first);
}

namespace {

template <typename Shape>
bool SameShape(const Shape &a, const Shape &b) {
    if constexpr (Shape::kDimension == 2)
        return a.a == b.a && a.b == b.b;
    else
        return a.n == b.n && a.v == b.v;
}

// Splits pseudo-random elements of _f_ (children of an element are made once), keeping
// in _shapes_ every element's shape as Shape::Subdivide() makes it, element by element,
// and checks the children's records against those shapes: made from the shapes the
// forest keeps of its last elements, from its cursor's paths, or from a root's.
template <typename Shape>
void GrowAtRandom(Forest<Shape> &f, std::vector<Shape> &shapes, int splits, uint64_t state) {
    for (int k = 0; k < splits; ++k) {
        state = state * 6364136223846793005u + 1442695040888963407u;
        // Every other split among the last 5000 elements made, on both sides of the 4096
        // whose shapes the forest keeps: the refinement mostly splits recent ones.
        uint32_t e = uint32_t((state >> 33) % f.Size());
        if (k % 2 == 0 && f.Size() > 5000)
            e = uint32_t(f.Size() - 1 - (state >> 33) % 5000);
        if (f[e].firstChild != kNoChildren || f.Depth(e) >= 20)
            continue;
        uint32_t first = f.Children(e);
        std::array<Shape, 4> children;
        shapes[e].Subdivide(f.Mode(), children);
        REQUIRE(first == shapes.size());
        for (int c = 0; c < f.Arity(); ++c) {
            const Shape &child = children[size_t(c)];
            CHECK(f[first + c].center == child.Centroid());
            CHECK(f[first + c].sizeSquared == child.SquaredMeasure());
            shapes.push_back(child);
        }
    }
}

template <typename Shape>
void CheckShapesMadeAgain(const Patches<Shape> &patches, Subdivision mode) {
    Forest<Shape> f(patches, 1 << 20, mode);
    std::vector<Shape> expected;
    for (const Patch<Shape> &p : patches)
        expected.push_back(p.shape);
    GrowAtRandom(f, expected, 3000, 12345);
    REQUIRE(f.Size() > 1000);
    std::vector<Shape> all = f.AllShapes();
    REQUIRE(all.size() == f.Size());
    ShapeCursor<Shape> cursor;
    uint64_t state = 7;
    for (uint32_t k = 0; k < 3 * f.Size(); ++k) {
        // In id order, then at random: near and far from the cursor's last elements.
        state = state * 6364136223846793005u + 1442695040888963407u;
        uint32_t e = k < f.Size() ? k : uint32_t((state >> 33) % f.Size());
        INFO("element " << e << " at depth " << f.Depth(e));
        CHECK(SameShape(cursor.ShapeOf(f, e), expected[e]));
        if (k < f.Size()) {
            CHECK(SameShape(f.ShapeOf(e), expected[e]));
            CHECK(SameShape(all[e], expected[e]));
        }
    }
    // The forest grows: the cursor's paths stay valid; a copy of the forest is another.
    GrowAtRandom(f, expected, 6000, 678);
    Forest<Shape> copy = f;
    for (uint32_t e = f.Size(); e-- > 0;) {
        CHECK(SameShape(cursor.ShapeOf(f, e), expected[e]));
        CHECK(SameShape(cursor.ShapeOf(copy, e), expected[e]));
    }
}

}  // namespace

TEST_CASE("Shapes are made again from the root's, bit for bit those of the subdivisions",
          "[forest]") {
    SECTION("segments, off the axes so that midpoints round") {
        CheckShapesMadeAgain<Segment>(
            {{{Vec2(0.1, 0.3), Vec2(7.7, 1.9)}, {}}, {{Vec2(8.3, 2.1), Vec2(-0.7, 1.3)}, {}}},
            Subdivision::Binary);
    }
    Patches<Polygon> polygons = {
        {Polygon::Quad({0.1, 0, 0}, {1.3, 0.2, 0}, {1.1, 1.7, 0}, {0, 0.9, 0}), {}},
        {Polygon::Triangle({0, 0, 1}, {0.3, 1.1, 1}, {1.7, 0.1, 1}), {}}};
    SECTION("polygons, binary") { CheckShapesMadeAgain(polygons, Subdivision::Binary); }
    SECTION("polygons, quadtree") { CheckShapesMadeAgain(polygons, Subdivision::Quadtree); }
}
