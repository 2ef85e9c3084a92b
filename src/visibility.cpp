#include "hrbench/visibility.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "hrbench/util/error.h"

namespace hrbench {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using Segment3 = Kernel::Segment_3;
using Triangle3 = Kernel::Triangle_3;

// An AABB tree primitive that carries its geometry and the root patch it belongs to
// (a model of CGAL's AABBPrimitive concept, built from an iterator to a Tagged).
template <typename Datum_>
struct Tagged {
    Datum_ datum;
    uint32_t root;
};

template <typename Datum_>
class TaggedPrimitive {
  public:
    using Id = uint32_t;  // the root patch
    using Datum = Datum_;
    using Point = Point3;

    TaggedPrimitive() = default;
    template <typename Iterator>
    explicit TaggedPrimitive(Iterator it) : datum_(it->datum), root_(it->root) {}

    const Datum &datum() const { return datum_; }
    Id id() const { return root_; }
    Point reference_point() const { return datum_.vertex(0); }

  private:
    Datum datum_;
    Id root_ = 0;
};

using TriangleTraits = CGAL::AABB_traits<Kernel, TaggedPrimitive<Triangle3>>;
using SegmentTraits = CGAL::AABB_traits<Kernel, TaggedPrimitive<Segment3>>;

// Finds whether a query segment meets a primitive of neither of two roots, and stops
// at the first one: CGAL's Do_intersect_traits with a filter on the primitive's root
// (CGAL/AABB_tree/internal/AABB_traversal_traits.h).
template <typename Traits>
class FirstOtherHit {
  public:
    using Primitive = typename Traits::Primitive;
    using Node = CGAL::AABB_node<Traits>;

    FirstOtherHit(const Traits &traits, uint32_t p, uint32_t q) : traits_(traits), p_(p), q_(q) {}

    bool go_further() const { return !found_; }

    void intersection(const Segment3 &query, const Primitive &primitive) {
        uint32_t root = primitive.id();
        if (root != p_ && root != q_ && traits_.do_intersect_object()(query, primitive))
            found_ = true;
    }

    bool do_intersect(const Segment3 &query, const Node &node) const {
        return traits_.do_intersect_object()(query, node.bbox());
    }

    bool Found() const { return found_; }

  private:
    const Traits &traits_;
    uint32_t p_, q_;
    bool found_ = false;
};

template <typename Traits>
bool AnyOtherHit(const CGAL::AABB_tree<Traits> &tree, const Segment3 &query, uint32_t p,
                 uint32_t q) {
    FirstOtherHit<Traits> traversal(tree.traits(), p, q);
    tree.traversal(query, traversal);
    return traversal.Found();
}

Point3 ToPoint(const Vec3 &v) { return {v.x(), v.y(), v.z()}; }
Point3 ToPoint(const Vec2 &v) { return {v.x(), v.y(), 0.0}; }

}  // namespace

// The tree of the scene's dimension: 2D segments lie in the plane z = 0.
struct Occluders::Index {
    std::vector<Tagged<Triangle3>> triangles;
    std::vector<Tagged<Segment3>> segments;
    CGAL::AABB_tree<TriangleTraits> triangleTree;
    CGAL::AABB_tree<SegmentTraits> segmentTree;
};

// Collect the occluders, tagged with their root patch, and build the tree now so that
// later queries only read it.
Occluders::Occluders(const Patches<Polygon> &patches) : index_(std::make_unique<Index>()) {
    for (uint32_t k = 0; k < patches.size(); ++k) {
        const Polygon &p = patches[k].shape;
        index_->triangles.push_back({{ToPoint(p.v[0]), ToPoint(p.v[1]), ToPoint(p.v[2])}, k});
        if (p.n == 4)
            index_->triangles.push_back({{ToPoint(p.v[0]), ToPoint(p.v[2]), ToPoint(p.v[3])}, k});
    }
    index_->triangleTree.insert(index_->triangles.begin(), index_->triangles.end());
    index_->triangleTree.build();
}

Occluders::Occluders(const Patches<Segment> &patches) : index_(std::make_unique<Index>()) {
    for (uint32_t k = 0; k < patches.size(); ++k) {
        const Segment &s = patches[k].shape;
        index_->segments.push_back({{ToPoint(s.a), ToPoint(s.b)}, k});
    }
    index_->segmentTree.insert(index_->segments.begin(), index_->segments.end());
    index_->segmentTree.build();
}

Occluders::~Occluders() = default;

// The segment from _a_ to _b_ without its ends: kEndTrim of its length is cut off at
// each end, so that a patch through an end point (the back of a two-sided blocker, a
// neighbour sharing an edge) does not count, while everything in between is exact.
constexpr double kEndTrim = 1e-9;

template <typename Vec>
Segment3 Trimmed(const Vec &a, const Vec &b) {
    Vec d = b - a;
    return Segment3(ToPoint(Vec(a + kEndTrim * d)), ToPoint(Vec(b - kEndTrim * d)));
}

// A query whose trimmed ends coincide (sample points of touching elements) has nothing
// in between to block; CGAL's predicates also require a segment of positive length.
bool Occluders::Blocked(const Vec3 &a, const Vec3 &b, uint32_t p, uint32_t q) const {
    Segment3 query = Trimmed(a, b);
    return !query.is_degenerate() && AnyOtherHit(index_->triangleTree, query, p, q);
}

bool Occluders::Blocked(const Vec2 &a, const Vec2 &b, uint32_t p, uint32_t q) const {
    Segment3 query = Trimmed(a, b);
    return !query.is_degenerate() && AnyOtherHit(index_->segmentTree, query, p, q);
}

}  // namespace hrbench
