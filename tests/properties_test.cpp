// Property tests: the invariants of docs/conventions.md on random scenes, 2D and 3D, with
// every oracle: per root pair the links tile the pair's parameter domain and the oracle
// calls follow from the links; counts, element ids and links do not depend on the number
// of threads; count-only mode counts what store mode stores. The scenes come from a
// fixed seed, so every run tests the same ones; a failure prints the scene as JSON.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <type_traits>

#include "hrbench/hrbench.h"
#include "refinement_helpers.h"

using namespace hrbench;
using hrbench_test::CounterDifferences;
using hrbench_test::RefinementDifferences;
using hrbench_test::TilingViolations;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Random numbers that are the same on every platform: std::mt19937_64's output is
// specified by the standard, its distributions are not, so they are not used.
class Random {
  public:
    explicit Random(uint64_t seed) : engine_(seed) {}
    // Uniform in [lo, hi).
    double Uniform(double lo, double hi) {
        return lo + (hi - lo) * double(engine_() >> 11) * 0x1p-53;
    }
    // Log-uniform in [lo, hi).
    double LogUniform(double lo, double hi) {
        return std::exp(Uniform(std::log(lo), std::log(hi)));
    }
    // Uniform in {lo, ..., hi}.
    int Int(int lo, int hi) { return lo + int(engine_() % uint64_t(hi - lo + 1)); }
    bool Chance(double p) { return Uniform(0, 1) < p; }
    // A unit vector, uniform on the sphere.
    Vec3 Direction() {
        double z = Uniform(-1, 1), phi = Uniform(0, 2 * kPi), s = std::sqrt(1 - z * z);
        return Vec3(s * std::cos(phi), s * std::sin(phi), z);
    }

  private:
    std::mt19937_64 engine_;
};

Material RandomMaterial(Random &rng) {
    Material m;
    m.reflectance = rng.Uniform(0, 0.95);
    m.emission = rng.Chance(0.2) ? rng.Uniform(0, 10) : 0;
    return m;
}

// 2 to 6 segments at random places, lengths and orientations in an 8 x 8 box; after a
// segment, often a partner that faces it: reversed, moved along its front normal and a
// little along itself, sometimes shorter or longer.
Patches<Segment> RandomSegments(Random &rng) {
    size_t n = size_t(rng.Int(2, 6));
    Patches<Segment> patches;
    while (patches.size() < n) {
        Vec2 a(rng.Uniform(0, 8), rng.Uniform(0, 8));
        double angle = rng.Uniform(0, 2 * kPi);
        Segment s{a, a + rng.Uniform(0.3, 3) * Vec2(std::cos(angle), std::sin(angle))};
        patches.push_back({s, RandomMaterial(rng)});
        if (patches.size() < n && rng.Chance(0.5)) {
            Vec2 along = (s.b - s.a).normalized();
            Vec2 shift = rng.Uniform(0.2, 3) * s.Normal() + rng.Uniform(-1, 1) * along;
            double scale = rng.Chance(0.5) ? 1 : rng.Uniform(0.3, 2);
            Vec2 b = s.a + shift, a = b + scale * (s.b - s.a);
            patches.push_back({{a, b}, RandomMaterial(rng)});
        }
    }
    return patches;
}

// A random convex polygon: a triangle or a quad with corners on an ellipse of radii
// _size_ and a random aspect in the plane spanned by _u_ and _v_ around _centre_,
// counter-clockwise seen from u x v.
Polygon RandomPolygon(Random &rng, const Vec3 &centre, const Vec3 &u, const Vec3 &v, double size) {
    int n = rng.Chance(0.5) ? 3 : 4;
    double aspect = rng.Uniform(0.4, 1);
    // Corner angles at least 0.5 rad apart, so that no corner is nearly straight: the
    // n + 1 gaps share out what is left of the full turn at random.
    std::array<double, 5> gaps;
    double sum = 0;
    for (int k = 0; k <= n; ++k)
        sum += gaps[size_t(k)] = rng.Uniform(0, 1);
    double angle = rng.Uniform(0, 2 * kPi), slack = 2 * kPi - 0.5 * n;
    std::array<Vec3, 4> corners;
    for (int k = 0; k < n; ++k) {
        corners[size_t(k)] =
            centre + size * std::cos(angle) * u + size * aspect * std::sin(angle) * v;
        angle += 0.5 + slack * gaps[size_t(k)] / sum;
    }
    return n == 3 ? Polygon::Triangle(corners[0], corners[1], corners[2])
                  : Polygon::Quad(corners[0], corners[1], corners[2], corners[3]);
}

// 2 to 5 triangles and quads at random places and orientations in a 6 x 6 x 6 box; after
// one, often a partner facing it (a mirrored copy moved along its front normal), or one
// that shares an edge with it.
Patches<Polygon> RandomPolygons(Random &rng) {
    size_t n = size_t(rng.Int(2, 5));
    Patches<Polygon> patches;
    while (patches.size() < n) {
        Vec3 normal = rng.Direction();
        Vec3 u = normal.unitOrthogonal(), v = normal.cross(u);
        Vec3 centre(rng.Uniform(0, 6), rng.Uniform(0, 6), rng.Uniform(0, 6));
        Polygon p = RandomPolygon(rng, centre, u, v, rng.Uniform(0.3, 1.5));
        patches.push_back({p, RandomMaterial(rng)});
        if (patches.size() == n)
            break;
        if (rng.Chance(0.4)) {
            // Facing: the corners in reverse order, moved along the normal.
            Vec3 shift = rng.Uniform(0.3, 2.5) * normal + rng.Uniform(-0.5, 0.5) * u;
            Polygon q = p;
            for (int k = 0; k < p.n; ++k)
                q.v[size_t(k)] = p.v[size_t(p.n - 1 - k)] + shift;
            if (q.n == 3)
                q.v[3] = q.v[2];
            patches.push_back({q, RandomMaterial(rng)});
        } else if (rng.Chance(0.3)) {
            // Touching: a triangle on the edge v0 v1, folded up towards the front.
            Vec3 edge = p.v[1] - p.v[0];
            Vec3 out = normal.cross(edge).normalized();
            Vec3 apex = 0.5 * (p.v[0] + p.v[1]) + edge.norm() * (0.5 * normal - 0.3 * out);
            patches.push_back({Polygon::Triangle(p.v[1], p.v[0], apex), RandomMaterial(rng)});
        }
    }
    return patches;
}

// Whether two patches might come close enough for refinement to need a recursion
// limit: their bounding spheres (around the centroid) are less than 0.2 apart.
template <typename Shape>
bool MightTouch(const Patches<Shape> &patches) {
    auto radius = [](const Shape &s) {
        double r = 0;
        if constexpr (std::is_same_v<Shape, Segment>)
            r = 0.5 * s.Length();
        else
            for (int k = 0; k < s.n; ++k)
                r = std::max(r, (s.v[size_t(k)] - s.Centroid()).norm());
        return r;
    };
    for (size_t p = 0; p < patches.size(); ++p)
        for (size_t q = p + 1; q < patches.size(); ++q) {
            const Shape &a = patches[p].shape, &b = patches[q].shape;
            if ((a.Centroid() - b.Centroid()).norm() - radius(a) - radius(b) < 0.2)
                return true;
        }
    return false;
}

struct Case {
    Scene scene;
    RefineOptions options;
};

// A random scene and options: eps log-uniform over a range that keeps each run small
// for the oracle and dimension, and a recursion limit where patches might touch (and
// sometimes elsewhere).
template <typename Shape>
Case RandomCase(Random &rng, const Patches<Shape> &patches, const std::string &oracle) {
    Case c;
    c.scene.family = "property";
    c.scene.patches = patches;
    RefineOptions &o = c.options;
    o.oracle = oracle;
    o.storeLinks = true;
    bool flat = Shape::kDimension == 2;
    if (oracle == "garmann")
        o.eps = flat ? rng.LogUniform(0.015, 0.3) : rng.LogUniform(0.005, 0.2);
    else
        o.eps = flat ? rng.LogUniform(0.004, 0.03) : rng.LogUniform(0.0005, 0.01);
    if (oracle == "bf") {
        // bf needs an emitter: where nothing emits, every other patch (the first, the
        // third, ...) emits 1, so that a patch and the partner made after it interact.
        // Its eps is scaled by the largest emission, to refine about as deep as hanrahan.
        Patches<Shape> &lit = c.scene.template Get<Shape>();
        double brightest = 0;
        for (const Patch<Shape> &p : lit)
            brightest = std::max(brightest, p.material.emission);
        for (size_t p = 0; brightest == 0 && p < lit.size(); p += 2)
            lit[p].material.emission = 1;
        o.eps *= std::max(brightest, 1.0);
    }
    if (MightTouch(patches) || rng.Chance(0.25))
        o.maxDepth = flat ? rng.Int(6, 8) : rng.Int(5, 8);
    if (!flat && rng.Chance(0.25)) {
        o.subdivision = Subdivision::Quadtree;
        if (o.maxDepth > 4)
            o.maxDepth = 4;
    }
    return c;
}

// Refines _c_ on 1, 2 and 3 threads and in count-only mode and checks the properties.
// Returns the refinement on one thread.
template <typename Shape>
Refinement<Shape> CheckProperties(const Case &c) {
    INFO("oracle " << c.options.oracle << " eps " << c.options.eps << " max_depth "
                   << c.options.maxDepth << " subdivision "
                   << SubdivisionName(c.options.subdivision) << "\nscene " << SceneToJson(c.scene));
    Refinement<Shape> one = Refine<Shape>(c.scene, c.options);
    CHECK(TilingViolations(c.scene, one, 1e-9) == "");
    for (int threads : {2, 3}) {
        RefineOptions o = c.options;
        o.threads = threads;
        CHECK(RefinementDifferences(one, Refine<Shape>(c.scene, o)) == "");
    }
    RefineOptions o = c.options;
    o.storeLinks = false;
    Refinement<Shape> counted = Refine<Shape>(c.scene, o);
    CHECK(CounterDifferences(one.record.counters, counted.record.counters) == "");
    CHECK(counted.links.size() == 0);
    return one;
}

// How many cases were far from trivial: more than 10 links, and deep enough (link depth
// kTaskDepth = 10) that the refinement handed tasks to the worker threads.
struct Coverage {
    int cases = 0, nontrivial = 0, deep = 0, limited = 0;
    template <typename Shape>
    void Add(const Case &c, const Refinement<Shape> &r) {
        ++cases;
        nontrivial += r.record.counters.links > 10;
        deep += r.record.counters.linksPerDepth.size() > 10;
        limited += c.options.HasRecursionLimit();
    }
};

}  // namespace

// Runs `cases` random scenes from `makePatches` with every oracle, checks each, and
// checks that enough of them were nontrivial, deep and recursion-limited to mean something.
// bf draws its options from a generator of its own, so that the other oracles see the
// cases they saw before it was added, and is counted apart: it links every pair of
// patches that do not emit at once, so fewer of its cases are nontrivial.
template <typename Shape, typename MakePatches>
void CheckRandomScenes(Random &rng, int cases, MakePatches makePatches, const char *label) {
    Coverage coverage, lit;
    Random bfRng(0xbf);
    for (int k = 0; k < cases; ++k) {
        Patches<Shape> patches = makePatches(rng);
        for (const OracleInfo &oracle : OracleInfos()) {
            bool bf = std::string(oracle.name) == "bf";
            Case c = RandomCase(bf ? bfRng : rng, patches, oracle.name);
            INFO(label << " case " << k);
            (bf ? lit : coverage).Add(c, CheckProperties<Shape>(c));
        }
    }
    INFO(coverage.nontrivial << " of " << coverage.cases << " with > 10 links, " << coverage.deep
                             << " deep enough for tasks, " << coverage.limited
                             << " with a recursion limit; bf: " << lit.nontrivial << ", "
                             << lit.deep << ", " << lit.limited << " of " << lit.cases);
    CHECK(coverage.nontrivial >= coverage.cases * 3 / 4);
    CHECK(coverage.deep >= coverage.cases / 4);
    CHECK(coverage.limited >= coverage.cases / 5);
    CHECK(lit.nontrivial >= lit.cases / 2);
    CHECK(lit.deep >= lit.cases / 4);
    CHECK(lit.limited >= lit.cases / 5);
}

TEST_CASE("Random 2D scenes satisfy the invariants with every oracle", "[properties]") {
    Random rng(20240611);
    CheckRandomScenes<Segment>(rng, 50, RandomSegments, "2D");
}

TEST_CASE("Random 3D scenes satisfy the invariants with every oracle", "[properties][3d]") {
    Random rng(1991);
    CheckRandomScenes<Polygon>(rng, 20, RandomPolygons, "3D");
}
