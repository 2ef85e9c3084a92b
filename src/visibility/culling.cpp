#include "visibility/culling.h"

#include <algorithm>
#include <array>
#include <map>

#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "hrbench/util/error.h"

namespace hrbench {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

static Kernel::Point_2 ToPoint(const Vec2 &v) { return {v.x(), v.y()}; }

// True when no point of _other_ lies strictly in front of (left of) _patch_.
static bool WhollyBehindOrIn(const Segment &patch, const Segment &other) {
    auto a = ToPoint(patch.a), b = ToPoint(patch.b);
    return CGAL::orientation(a, b, ToPoint(other.a)) != CGAL::LEFT_TURN &&
           CGAL::orientation(a, b, ToPoint(other.b)) != CGAL::LEFT_TURN;
}

PairRelation ClassifyPair(const Segment &p, const Segment &q) {
    if (WhollyBehindOrIn(p, q) || WhollyBehindOrIn(q, p))
        return PairRelation::Culled;
    Kernel::Segment_2 sp(ToPoint(p.a), ToPoint(p.b)), sq(ToPoint(q.a), ToPoint(q.b));
    return CGAL::do_intersect(sp, sq) ? PairRelation::Touching : PairRelation::Interacting;
}

static Kernel::Point_3 ToPoint(const Vec3 &v) { return {v.x(), v.y(), v.z()}; }

// Whether corner _v_ is one of the first three corners of _patch_, coordinate for
// coordinate: its orientation against their plane is then exactly zero, which the
// predicate's floating-point filter cannot tell, so that it falls back on exact
// arithmetic (neighbours of a mesh share corners: most of a mesh's culling time).
static bool IsPlaneCorner(const Polygon &patch, const Vec3 &v) {
    return v == patch.v[0] || v == patch.v[1] || v == patch.v[2];
}

// True when no corner of _other_ lies strictly in front of the plane of _patch_:
// orientation(v0, v1, v2, c) is POSITIVE exactly when c is on the side of the front
// normal (v1 - v0) x (v2 - v0).
static bool WhollyBehindOrIn(const Polygon &patch, const Polygon &other) {
    auto a = ToPoint(patch.v[0]), b = ToPoint(patch.v[1]), c = ToPoint(patch.v[2]);
    for (int k = 0; k < other.n; ++k)
        if (!IsPlaneCorner(patch, other.v[k]) &&
            CGAL::orientation(a, b, c, ToPoint(other.v[k])) == CGAL::POSITIVE)
            return false;
    return true;
}

// Whether the polygons have a corner in common, coordinate for coordinate: their closed
// triangles then intersect, which do_intersect finds only in exact arithmetic.
static bool ShareCorner(const Polygon &p, const Polygon &q) {
    for (int i = 0; i < p.n; ++i)
        for (int j = 0; j < q.n; ++j)
            if (p.v[size_t(i)] == q.v[size_t(j)])
                return true;
    return false;
}

// A polygon as one or two triangles (a quad split along v0 v2).
static int Triangles(const Polygon &p, Kernel::Triangle_3 out[2]) {
    out[0] = {ToPoint(p.v[0]), ToPoint(p.v[1]), ToPoint(p.v[2])};
    if (p.n == 3)
        return 1;
    out[1] = {ToPoint(p.v[0]), ToPoint(p.v[2]), ToPoint(p.v[3])};
    return 2;
}

PairRelation ClassifyPair(const Polygon &p, const Polygon &q) {
    if (WhollyBehindOrIn(p, q) || WhollyBehindOrIn(q, p))
        return PairRelation::Culled;
    if (ShareCorner(p, q))
        return PairRelation::Touching;
    Kernel::Triangle_3 tp[2], tq[2];
    int np = Triangles(p, tp), nq = Triangles(q, tq);
    for (int a = 0; a < np; ++a)
        for (int b = 0; b < nq; ++b)
            if (CGAL::do_intersect(tp[a], tq[b]))
                return PairRelation::Touching;
    return PairRelation::Interacting;
}

// ---------------------------------------------------------------------------------------
// The whole scene: occlusion and orientation

namespace {

// A patch's corners and, for each line or plane it blocks light with (2D: its line; 3D:
// the plane of each triangle Occluders cuts it into), the side of a point: 1 in front,
// -1 behind, 0 in it.
int NumCorners(const Segment &) { return 2; }
int NumCorners(const Polygon &p) { return p.n; }
Vec2 Corner(const Segment &s, int c) { return c == 0 ? s.a : s.b; }
Vec3 Corner(const Polygon &p, int c) { return p.v[size_t(c)]; }
int NumPlanes(const Segment &) { return 1; }
int NumPlanes(const Polygon &p) { return p.n == 4 ? 2 : 1; }

int SideOf(const Segment &s, int, const Vec2 &v) {
    return int(CGAL::orientation(ToPoint(s.a), ToPoint(s.b), ToPoint(v)));
}

int SideOf(const Polygon &p, int plane, const Vec3 &v) {
    return int(CGAL::orientation(ToPoint(p.v[0]), ToPoint(p.v[plane + 1]), ToPoint(p.v[plane + 2]),
                                 ToPoint(v)));
}

// Which sides of a patch's lines or planes the other patches' corners lie on, each test
// asking until it knows. It asks first about a few corners far out in the scene, those
// furthest along each of the 8 (2D) or 26 (3D) directions with components -1, 0, 1,
// then about every corner in scene order: the answers are the same as from the scan
// alone, but most patches have a far corner in front and stop there, where the scan
// alone costs O(k) a patch and O(k^2) in all (the bunny's box: 75,792 patches, 5 s).
template <typename Shape>
class SideTests {
  public:
    explicit SideTests(const Patches<Shape> &patches) : patches_(patches) {
        constexpr int D = Shape::kDimension;
        constexpr int kDirections = D == 3 ? 26 : 8;
        std::vector<typename Shape::Vec> directions;
        for (int code = 0; code < (D == 3 ? 27 : 9); ++code) {
            typename Shape::Vec d;
            for (int a = 0, rest = code; a < D; ++a, rest /= 3)
                d[a] = double(rest % 3 - 1);
            if (!d.isZero())
                directions.push_back(d);
        }
        std::vector<double> best(kDirections, -std::numeric_limits<double>::infinity());
        std::vector<Far> far(kDirections);
        for (uint32_t k = 0; k < patches.size(); ++k)
            for (int c = 0; c < NumCorners(patches[k].shape); ++c)
                for (int d = 0; d < kDirections; ++d)
                    if (double along = directions[size_t(d)].dot(Corner(patches[k].shape, c));
                        along > best[size_t(d)])
                        best[size_t(d)] = along, far[size_t(d)] = {k, c};
        if (!patches.empty())
            far_ = far;
    }

    // Calls visit(side) for the side of every corner of every other patch with respect
    // to patch _r_'s line or plane _plane_ (some more than once), until it returns false.
    template <typename Visit>
    void ForEachSide(size_t r, int plane, Visit visit) const {
        const Shape &shape = patches_[r].shape;
        for (const Far &f : far_)
            if (f.patch != r &&
                !visit(SideOf(shape, plane, Corner(patches_[f.patch].shape, f.corner))))
                return;
        for (size_t k = 0; k < patches_.size(); ++k)
            for (int c = 0; k != r && c < NumCorners(patches_[k].shape); ++c)
                if (!visit(SideOf(shape, plane, Corner(patches_[k].shape, c))))
                    return;
    }

  private:
    struct Far {
        uint32_t patch = 0;
        int corner = 0;
    };
    const Patches<Shape> &patches_;
    std::vector<Far> far_;
};

// Whether the other patches have corners strictly on both sides of a line or plane of
// patch _r_.
template <typename Shape>
bool Separates(const SideTests<Shape> &sides, const Shape &shape, size_t r) {
    for (int plane = 0; plane < NumPlanes(shape); ++plane) {
        bool front = false, back = false;
        sides.ForEachSide(r, plane, [&](int side) {
            front |= side > 0, back |= side < 0;
            return !(front && back);
        });
        if (front && back)
            return true;
    }
    return false;
}

// Whether patch _r_ has every other patch behind or in its line or plane, some corner
// strictly behind: then every root pair of _r_ is culled, and it exchanges no light.
template <typename Shape>
bool FacesOut(const SideTests<Shape> &sides, size_t r) {
    bool front = false, behind = false;
    sides.ForEachSide(r, 0, [&](int side) {
        front |= side > 0, behind |= side < 0;
        return !front;
    });
    return behind && !front;
}

}  // namespace

bool CanOcclude(const Scene &scene) {
    return std::visit(
        [](const auto &patches) {
            if (patches.size() <= 2)
                return false;  // no third patch to stand between two others
            SideTests sides(patches);
            for (size_t r = 0; r < patches.size(); ++r)
                if (Separates(sides, patches[r].shape, r))
                    return true;
            return false;
        },
        scene.patches);
}

namespace {

// Union-find over _n_ items.
struct Parts {
    std::vector<uint32_t> parent;
    explicit Parts(size_t n) : parent(n) {
        for (uint32_t r = 0; r < n; ++r)
            parent[r] = r;
    }
    uint32_t Find(uint32_t r) {
        while (parent[r] != r)
            r = parent[r] = parent[parent[r]];
        return r;
    }
    void Join(uint32_t a, uint32_t b) { parent[Find(a)] = Find(b); }
};

template <int D>
struct PartFigures {
    double front = 0;  // the measure of the part's front side (signed)
    std::array<double, D> low, high;
    PartFigures() { low.fill(std::numeric_limits<double>::infinity()), high.fill(-low[0]); }
    template <typename V>
    void Add(const V &p) {
        for (int k = 0; k < D; ++k)
            low[k] = std::min(low[k], p[k]), high[k] = std::max(high[k], p[k]);
    }
    bool Inside(const PartFigures &other) const {
        for (int k = 0; k < D; ++k)
            if (low[k] < other.low[k] || high[k] > other.high[k])
                return false;
        return true;
    }
};

// Condition (2) and (3) of IsClosed over the parts' figures.
template <int D>
bool PartsEnclosed(const std::map<uint32_t, PartFigures<D>> &parts) {
    bool any = false;
    for (const auto &[root, part] : parts)
        any |= part.front > 0;
    if (!any)
        return false;
    for (const auto &[root, part] : parts) {
        if (part.front > 0)
            continue;
        bool inside = false;
        for (const auto &[other, enclosing] : parts)
            inside |= enclosing.front > 0 && part.Inside(enclosing);
        if (!inside)
            return false;
    }
    return true;
}

bool IsClosedOf(const Patches<Segment> &patches) {
    if (patches.empty())
        return false;
    // Each point: how many segments start there, how many end there, and one that starts.
    std::map<std::array<double, 2>, std::array<uint32_t, 3>> at;
    for (uint32_t r = 0; r < patches.size(); ++r) {
        const Segment &s = patches[r].shape;
        at[{s.a.x(), s.a.y()}][0]++, at[{s.a.x(), s.a.y()}][2] = r;
        at[{s.b.x(), s.b.y()}][1]++;
    }
    for (const auto &[point, counts] : at)
        if (counts[0] != 1 || counts[1] != 1)
            return false;
    Parts parts(patches.size());
    for (uint32_t r = 0; r < patches.size(); ++r) {
        const Segment &s = patches[r].shape;
        parts.Join(r, at[{s.b.x(), s.b.y()}][2]);
    }
    std::map<uint32_t, PartFigures<2>> figures;
    for (uint32_t r = 0; r < patches.size(); ++r) {
        const Segment &s = patches[r].shape;
        PartFigures<2> &f = figures[parts.Find(r)];
        f.front += (s.a.x() * s.b.y() - s.a.y() * s.b.x()) / 2;  // front on the left
        f.Add(s.a), f.Add(s.b);
    }
    return PartsEnclosed(figures);
}

bool IsClosedOf(const Patches<Polygon> &patches) {
    if (patches.empty())
        return false;
    using Key = std::array<double, 6>;
    auto key = [](const Vec3 &a, const Vec3 &b) {
        return Key{a.x(), a.y(), a.z(), b.x(), b.y(), b.z()};
    };
    // Every directed edge with its patch, sorted.
    std::vector<std::pair<Key, uint32_t>> edges;
    for (uint32_t r = 0; r < patches.size(); ++r) {
        const Polygon &p = patches[r].shape;
        for (int k = 0; k < p.n; ++k)
            edges.push_back({key(p.v[k], p.v[(k + 1) % p.n]), r});
    }
    std::sort(edges.begin(), edges.end());
    for (size_t e = 1; e < edges.size(); ++e)
        if (edges[e].first == edges[e - 1].first)
            return false;  // run the same way twice
    Parts parts(patches.size());
    for (const auto &[edge, r] : edges) {
        Key reverse{edge[3], edge[4], edge[5], edge[0], edge[1], edge[2]};
        auto back =
            std::lower_bound(edges.begin(), edges.end(), std::pair<Key, uint32_t>{reverse, 0});
        if (back == edges.end() || back->first != reverse || back->second == r)
            return false;
        parts.Join(r, back->second);
    }
    std::map<uint32_t, PartFigures<3>> figures;
    for (uint32_t r = 0; r < patches.size(); ++r) {
        const Polygon &p = patches[r].shape;
        PartFigures<3> &f = figures[parts.Find(r)];
        for (int k = 1; k + 1 < p.n; ++k)  // front toward the normal: minus the volume
            f.front -= p.v[0].dot(p.v[k].cross(p.v[k + 1])) / 6;
        for (int k = 0; k < p.n; ++k)
            f.Add(p.v[k]);
    }
    return PartsEnclosed(figures);
}

}  // namespace

bool IsClosed(const Scene &scene) {
    return std::visit([](const auto &patches) { return IsClosedOf(patches); }, scene.patches);
}

// The connected parts of a mesh: faces that share a corner (the same coordinates) are
// in one part. Returns each face's part, numbered from 0 in the order of first faces.
std::vector<uint32_t> ConnectedParts(const Patches<Polygon> &patches) {
    std::vector<uint32_t> parent(patches.size());
    for (uint32_t r = 0; r < parent.size(); ++r)
        parent[r] = r;
    auto find = [&](uint32_t r) {
        while (parent[r] != r)
            r = parent[r] = parent[parent[r]];
        return r;
    };
    std::map<std::array<double, 3>, uint32_t> firstAt;
    for (uint32_t r = 0; r < patches.size(); ++r)
        for (int k = 0; k < patches[r].shape.n; ++k) {
            const Vec3 &v = patches[r].shape.v[k];
            auto [it, added] = firstAt.insert({{v.x(), v.y(), v.z()}, r});
            if (!added)
                parent[find(r)] = find(it->second);
        }
    std::vector<uint32_t> part(patches.size());
    std::map<uint32_t, uint32_t> number;
    for (uint32_t r = 0; r < patches.size(); ++r)
        part[r] = number.insert({find(r), uint32_t(number.size())}).first->second;
    return part;
}

std::string FacingAwayHint(const Scene &scene) {
    if (scene.family != "mesh")
        return "";
    const Patches<Polygon> &patches = scene.Get<Polygon>();
    // Per connected part (an object, a room's walls): one object turned inside out among
    // others is a small share of the whole mesh, and a large one of its part.
    std::vector<uint32_t> part = ConnectedParts(patches);
    size_t parts = part.empty() ? 0 : *std::max_element(part.begin(), part.end()) + 1;
    std::vector<double> area(parts), outArea(parts);
    std::vector<size_t> faces(parts), out(parts);
    SideTests sides(patches);
    for (size_t r = 0; r < patches.size(); ++r) {
        area[part[r]] += patches[r].shape.Area();
        ++faces[part[r]];
        if (FacesOut(sides, r))
            ++out[part[r]], outArea[part[r]] += patches[r].shape.Area();
    }
    // Name the parts mostly facing away: how many, and the largest by area.
    size_t flagged = 0, worst = parts;
    for (size_t p = 0; p < parts; ++p)
        if (2 * outArea[p] > area[p]) {
            ++flagged;
            if (worst == parts || area[p] > area[worst])
                worst = p;
        }
    if (!flagged)
        return "";
    char percent[16];
    std::snprintf(percent, sizeof percent, "%.0f%%", 100 * outArea[worst] / area[worst]);
    std::string count = std::to_string(out[worst]) + " of " + (parts == 1 ? "" : "its ") +
                        std::to_string(faces[worst]) + " faces";
    std::string where = parts == 1     ? "the mesh's area (" + count + ")"
                        : flagged == 1 ? "the area of one of the mesh's " + std::to_string(parts) +
                                             " connected parts (" + count + ")"
                                       : "the area of the largest of " + std::to_string(flagged) +
                                             " of the mesh's " + std::to_string(parts) +
                                             " connected parts that face away (" + count + ")";
    return "faces holding " + std::string(percent) + " of " + where +
           " have every other face behind them and exchange no light; faces are "
           "counter-clockwise seen from their front (docs/3d.md): a room seen from inside, or "
           "a face of a part, may be the wrong way round";
}

bool RefinesRootPair(PairRelation relation, uint32_t p, uint32_t q, const RefineOptions &options) {
    if (relation == PairRelation::Touching && !options.HasRecursionLimit())
        throw InputError("patches " + std::to_string(p) + " and " + std::to_string(q) +
                         " touch, so refinement cannot terminate; set a recursion limit with "
                         "--min-area or --max-depth");
    return relation != PairRelation::Culled;
}

}  // namespace hrbench
