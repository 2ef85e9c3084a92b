// --method translation for two facing rectangles in space (`parallel3d` without
// offset): the plane counterpart of translation_count.cpp.
//
// A pair at level n = depth_i + depth_j has the sizes of depths ceil(n/2) and floor(n/2),
// and its oracle outcome and subtree depend only on the offset (dx, dy) of the two
// centroids, an exact multiple (cx ux, cy uy) of half the P element's sides. The pairs
// are counted by state (n, cx, cy) in a dense grid; per row of the grid the rejected
// states are one run around cx = 0, whose ends a binary search finds. Halving an
// element along x maps a state's cx as in flatland (P: 2 cx -+ 1, Q: cx -+ 1) and leaves
// cy alone; along y the other way round; a quadtree split does both.
//
// The elements need no states: with the plates one above the other, the Q element
// whose column holds a P element's centroid is its nearest partner, at the same
// offset for every P element of a level, and visited (its parent holds the centroid of
// the P element's parent). So when any pair of a level is rejected, the nearest pair of
// every element is, and every element of the plate halved at that level is halved.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "hrbench/geometry/polygon.h"
#include "hrbench/oracles/garmann.h"
#include "translation_internal.h"
#include "util/format.h"

namespace hrbench::translation {

namespace {

// P = [0,l] x [0,w] at z = 0 facing +z, Q the same rectangle at z = d facing -z, with
// their corners in the order of the `parallel3d` generator.
struct Rectangles {
    double l, w, d;
    Polygon P() const { return Polygon::Quad({0, 0, 0}, {l, 0, 0}, {l, w, 0}, {0, w, 0}); }
    Polygon Q() const { return Polygon::Quad({0, w, d}, {l, w, d}, {l, 0, d}, {0, 0, d}); }
};

Rectangles RectanglesOf(const Scene &scene) {
    const char *scope = "--method translation in 3D needs the parallel3d scene with ox = oy = 0: "
                        "P = [0,l] x [0,w] at z=0 facing +z, Q the same rectangle at z=d "
                        "facing -z, d > 0";
    if (!std::holds_alternative<Patches<Polygon>>(scene.patches) || scene.NumPatches() != 2)
        throw InputError(scope);
    const Polygon &p = scene.Get<Polygon>()[0].shape, &q = scene.Get<Polygon>()[1].shape;
    Rectangles plates{p.v[1].x(), p.v[2].y(), q.v[0].z()};
    bool shape = p.n == 4 && q.n == 4 && plates.l > 0 && plates.w > 0 && plates.d > 0 &&
                 std::isfinite(2 * plates.d) && p.v == plates.P().v && q.v == plates.Q().v;
    if (!shape)
        throw InputError(scope);
    return plates;
}

// True when the corners and centroids of elements with _splits_ halvings of a side of
// length _length_, and every difference of two such centroids, are exact in double
// precision: all lie on the grid of boundaries one halving deeper, and the sums
// v0 + v2 of a centroid (at most 2 length) need at most 53 bits on it.
bool ExactAxis(double length, int splits) {
    return FitsGrid(2 * length, LowBit(length) - (splits + 1));
}

[[noreturn]] void NotExact(const Rectangles &plates, int depth) {
    throw InputError("--method translation: the element centroids of l=" + FormatDouble(plates.l) +
                     ", w=" + FormatDouble(plates.w) +
                     " are not exact in double precision at depth " + std::to_string(depth) +
                     "; use sides with few significant bits (e.g. 8, 1000, 0.75), or "
                     "--method enumerate");
}

// One plate's elements, depth by depth, through the engine's own subdivision of its
// first element: all elements of a depth are congruent, with these sizes and sides.
class Depths {
  public:
    Depths(const Polygon &root, Subdivision mode) : mode_(mode) {
        shapes_.push_back(root);
        splits_.push_back({0, 0});
    }

    const Polygon &Shape(int depth) { return Grow(depth), shapes_[size_t(depth)]; }
    // Halvings of the x side and of the y side from the root down to _depth_.
    int SplitsX(int depth) { return Grow(depth), splits_[size_t(depth)][0]; }
    int SplitsY(int depth) { return Grow(depth), splits_[size_t(depth)][1]; }

  private:
    static double Side(const Polygon &p, int axis) {
        return std::abs(p.v[2][axis] - p.v[0][axis]);  // opposite corners of a rectangle
    }
    void Grow(int depth) {
        while (int(shapes_.size()) <= depth) {
            const Polygon &parent = shapes_.back();
            std::array<Polygon, 4> children;
            int n = parent.Subdivide(mode_, children);
            std::array<double, 4> sizes{};
            for (int c = 0; c < n; ++c)
                sizes[c] = children[c].Measure();
            if (!Polygon::Resolves(parent.Measure(), sizes, n))
                throw LimitError("the elements of the plates are too small for double precision "
                                 "at depth " +
                                 std::to_string(shapes_.size() - 1) +
                                 "; use --min-area or --max-depth");
            std::array<int, 2> splits = splits_.back();
            for (int axis = 0; axis < 2; ++axis)
                splits[axis] += Side(children[0], axis) != Side(parent, axis);
            shapes_.push_back(children[0]);
            splits_.push_back(splits);
        }
    }

    Subdivision mode_;
    std::vector<Polygon> shapes_;
    std::vector<std::array<int, 2>> splits_;
};

// The pair states of one level: index (x, y) holds the offset
// (first[0] + 2 x, first[1] + 2 y), row by row (the offsets of a level have one parity
// per axis).
struct Grid {
    int64_t first[2] = {0, 0};
    size_t size[2] = {1, 1};
    std::vector<uint64_t> pairs = {1};
    uint64_t total = 1;  // the sum of _pairs_: the level's oracle calls

    uint64_t &At(size_t x, size_t y) { return pairs[y * size[0] + x]; }
};

// Into _out_ (whose buffer is reused: fresh pages for every level cost more than the
// count), the states after halving the elements of P (_halveP_) or Q along _axis_
// (0: x, 1: y): a state c has the children 2c - 1 and 2c + 1 (P, whose unit halves),
// or c - 1 and c + 1 (Q, twice as long as P's along the axis, shared with the
// neighbouring states).
void Halve(const Grid &grid, int axis, bool halveP, Grid &out) {
    out.size[0] = grid.size[0], out.size[1] = grid.size[1];
    out.size[axis] = halveP ? 2 * grid.size[axis] : grid.size[axis] + 1;
    out.first[0] = grid.first[0], out.first[1] = grid.first[1];
    out.first[axis] = halveP ? 2 * grid.first[axis] - 1 : grid.first[axis] - 1;
    out.total = CheckedMul(grid.total, 2);
    out.pairs.assign(out.size[0] * out.size[1], 0);
    const size_t width = grid.size[0], outWidth = out.size[0];
    bool overflow = false;  // a sum of two states' pairs past 2^64 (Q only)
    for (size_t y = 0; y < grid.size[1]; ++y) {
        const uint64_t *row = &grid.pairs[y * width];
        if (axis == 0) {
            uint64_t *to = &out.pairs[y * outWidth];
            for (size_t x = 0; x < width; ++x) {
                if (halveP) {
                    to[2 * x] = to[2 * x + 1] = row[x];
                } else {
                    overflow |= __builtin_add_overflow(to[x], row[x], &to[x]);
                    to[x + 1] = row[x];
                }
            }
        } else {
            uint64_t *first = &out.pairs[(halveP ? 2 * y : y) * outWidth];
            uint64_t *second = first + outWidth;
            for (size_t x = 0; x < width; ++x) {
                overflow |= __builtin_add_overflow(first[x], row[x], &first[x]);
                second[x] = row[x];
            }
        }
    }
    if (overflow)
        Overflow();
}

}  // namespace

void CheckSpaceScope(const Scene &scene, const RefineOptions &) { RectanglesOf(scene); }

TranslationCount CountSpace(const Scene &scene, const RefineOptions &options) {
    const Rectangles plates = RectanglesOf(scene);
    const GarmannOracle<Polygon> oracle(options.eps, scene.Get<Polygon>());

    TranslationCount result;
    Counters &counters = result.record.counters;
    const int arity = SubdivisionArity(options.subdivision);
    std::vector<uint64_t> splitP, splitQ;  // elements halved, per depth, in P and in Q
    Depths depthsP(plates.P(), options.subdivision), depthsQ(plates.Q(), options.subdivision);
    uint64_t elements = 1;  // elements of a depth in one plate: arity^depth

    Grid grid, scratch;  // the level's states, and the buffer the next ones are built in
    const size_t budget = EffectiveBudget(options);
    for (int n = 0;; ++n) {
        // As in flatland: P is halved on even levels (equal sizes, ties go to the first
        // argument), Q on odd ones, P being one depth deeper.
        const int depthI = (n + 1) / 2, depthJ = n / 2;
        const bool splitsP = n % 2 == 0;
        const int splitsX = depthsP.SplitsX(depthI), splitsY = depthsP.SplitsY(depthI);
        if (!ExactAxis(plates.l, splitsX) || !ExactAxis(plates.w, splitsY))
            NotExact(plates, depthI);
        Element<3> ei{Vec3(0, 0, 0), depthsP.Shape(depthI).SquaredArea(), kNoChildren, 0};
        Element<3> ej{Vec3(0, 0, plates.d), depthsQ.Shape(depthJ).SquaredArea(), kNoChildren, 1};
        if ((ei.sizeSquared >= ej.sizeSquared) != splitsP)
            NotExact(plates, depthI);  // unequal sizes at equal depths: rounded areas

        // The centroid offset of state (cx, cy) is (cx ux, cy uy): exact, so every pair in
        // the state gives the oracle these doubles.
        const double ux = std::ldexp(plates.l, -(splitsX + 1));
        const double uy = std::ldexp(plates.w, -(splitsY + 1));
        unsigned __int128 rejectedPairs = 0;
        size_t box[2][2] = {{grid.size[0], 0}, {grid.size[1], 0}};  // [axis] = {lo, end}
        std::vector<std::pair<size_t, size_t>> runs(grid.size[1]);
        for (size_t y = 0; y < grid.size[1]; ++y) {
            ei.center.y() = double(grid.first[1] + 2 * int64_t(y)) * uy;
            auto offsetX = [&](size_t x) { return grid.first[0] + 2 * int64_t(x); };
            auto rejected = [&](size_t x) {
                ++result.oracleEvaluations;
                ei.center.x() = double(offsetX(x)) * ux;
                return !oracle.Acceptable(ei, ej);
            };
            auto [lo, end] =
                RejectedRun(grid.size[0], rejected, [&](size_t x) { return offsetX(x) < 0; });
            runs[y] = {lo, end};
            if (lo == end)
                continue;
            for (size_t x = lo; x < end; ++x)
                rejectedPairs += grid.At(x, y);
            box[0][0] = std::min(box[0][0], lo), box[0][1] = std::max(box[0][1], end);
            box[1][0] = std::min(box[1][0], y), box[1][1] = y + 1;
        }

        counters.oracleCalls = CheckedAdd(counters.oracleCalls, grid.total);
        result.pairStates += grid.pairs.size();
        const uint64_t rejectedTotal = Checked(rejectedPairs);
        const uint64_t linked = grid.total - rejectedTotal;
        counters.linksPerDepth.push_back(linked);
        counters.links = CheckedAdd(counters.links, linked);
        if (rejectedTotal == 0)
            break;
        CheckSafetyDepth(depthJ);  // the preferred element has depth depth_j on both kinds

        // Every element of the halved plate is halved (see the top of this file).
        const int depth = splitsP ? depthI : depthJ;
        Depths &halved = splitsP ? depthsP : depthsQ;
        (splitsP ? splitP : splitQ).push_back(elements);
        ++result.elementStates;
        if (!splitsP)
            elements = CheckedMul(elements, uint64_t(arity));

        // Keep the rejected states, then halve along the split axes.
        const bool halvesX = halved.SplitsX(depth + 1) != halved.SplitsX(depth);
        const bool halvesY = halved.SplitsY(depth + 1) != halved.SplitsY(depth);
        size_t keptSize[2] = {box[0][1] - box[0][0], box[1][1] - box[1][0]};
        size_t nextSize[2] = {keptSize[0], keptSize[1]};
        for (int axis = 0; axis < 2; ++axis)
            if (axis == 0 ? halvesX : halvesY)
                nextSize[axis] = splitsP ? 2 * keptSize[axis] : keptSize[axis] + 1;
        if (2 * sizeof(uint64_t) * std::max(nextSize[0] * nextSize[1], grid.pairs.size()) > budget)
            throw LimitError("--method translation would exceed the memory budget (" +
                             std::to_string(nextSize[0] * nextSize[1]) + " pair states at level " +
                             std::to_string(n + 1) + "); raise --max-memory or eps");
        scratch.first[0] = grid.first[0] + 2 * int64_t(box[0][0]);
        scratch.first[1] = grid.first[1] + 2 * int64_t(box[1][0]);
        scratch.size[0] = keptSize[0], scratch.size[1] = keptSize[1];
        scratch.pairs.assign(keptSize[0] * keptSize[1], 0);
        scratch.total = rejectedTotal;
        for (size_t y = box[1][0]; y < box[1][1]; ++y)
            for (size_t x = runs[y].first; x < runs[y].second; ++x)
                scratch.At(x - box[0][0], y - box[1][0]) = grid.At(x, y);
        std::swap(grid, scratch);
        for (int axis = 0; axis < 2; ++axis) {
            if (axis == 0 ? halvesX : halvesY) {
                Halve(grid, axis, splitsP, scratch);
                std::swap(grid, scratch);
            }
        }
    }

    SummariseTrees(std::move(splitP), std::move(splitQ), arity, counters);
    return result;
}

}  // namespace hrbench::translation
