#include "visibility/visibility.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#ifdef HRBENCH_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

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

// The tree of the scene's dimension: 2D segments lie in the plane z = 0. With Embree,
// the triangles are kept for the exact test and no tree is built.
struct Occluders::Index {
    std::vector<Tagged<Triangle3>> triangles;
    std::vector<Tagged<Segment3>> segments;
    CGAL::AABB_tree<TriangleTraits> triangleTree;
    CGAL::AABB_tree<SegmentTraits> segmentTree;
};

// The segment from _a_ to _b_ without its ends: kEndTrim of its length is cut off at
// each end, so that a patch through an end point (the back of a two-sided blocker, a
// neighbour sharing an edge) does not count, while everything in between is exact.
constexpr double kEndTrim = 1e-9;

template <typename Vec>
Segment3 Trimmed(const Vec &a, const Vec &b) {
    Vec d = b - a;
    return Segment3(ToPoint(Vec(a + kEndTrim * d)), ToPoint(Vec(b - kEndTrim * d)));
}

bool HasEmbree() {
#ifdef HRBENCH_HAVE_EMBREE
    return true;
#else
    return false;
#endif
}

#ifdef HRBENCH_HAVE_EMBREE

namespace {

// Embree decides in single precision. A hit is taken as it is only when rounding cannot
// have made it: the ray crosses the triangle's plane at an angle whose sine is at least
// kMinSine, at least a margin inside the triangle and from both ends of the segment. The
// margin is kMarginUlps float roundings of the scene's extent S, scaled by S / (the
// triangle's shortest edge), as the error of Embree's edge tests is. Every other hit is
// decided by CGAL's exact test; the triangles are grown by the margin so that no exact
// hit escapes Embree, except a ray within about a degree of the plane near an edge.
constexpr double kMarginUlps = 256;
constexpr float kMinSine = 0.05f;

// A root's mask bit: with at most 32 roots, one of its own.
unsigned MaskOf(uint32_t root) { return 1u << (root % 32); }

struct DeviceDeleter {
    void operator()(RTCDevice device) const { rtcReleaseDevice(device); }
};

// One device for the process: a new one per run would start Embree's task system again.
RTCDevice Device() {
    static const std::unique_ptr<RTCDeviceTy, DeviceDeleter> device(rtcNewDevice(nullptr));
    if (!device)
        throw std::runtime_error("Embree: cannot create a device (error " +
                                 std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    return device.get();
}

}  // namespace

struct EmbreeScene {
    // Per triangle, in the order of Index::triangles (first[geomID] + primID): its root,
    // the margin, and the barycentric coordinates (of the grown triangle, opposite v0,
    // v1, v2) that lie a margin inside the true one.
    struct Triangle {
        uint32_t root;
        float margin;
        float minBary[3];
    };
    std::vector<Triangle> triangles;
    std::vector<uint32_t> first;  // by root: the index of its first triangle
    double reach = 0;             // how far rays reach beyond their ends: the margin at S
    bool maskRoots = false;       // rays leave out their roots by mask (32 roots at most)
    RTCScene scene = nullptr;

    const Triangle &Hit(unsigned geomID, unsigned primID) const {
        return triangles[first[geomID] + primID];
    }
    // The rays' mask between roots _p_ and _q_: all but theirs when masks tell roots apart.
    unsigned RayMask(uint32_t p, uint32_t q) const {
        return maskRoots ? ~(MaskOf(p) | MaskOf(q)) : ~0u;
    }

    ~EmbreeScene() {
        if (scene)
            rtcReleaseScene(scene);
    }
};

namespace {

// One batch of rays from the samples _from_ of root _p_ to the samples _to_ of root _q_
// (ray id: i * to.size() + j), as the filter sees it.
struct RayBatch {
    RTCIntersectContext context;  // first: Embree hands the filter its address
    const EmbreeScene *embree;
    const std::vector<Tagged<Triangle3>> *triangles;
    uint32_t p, q;
    const Vec3 *from, *to;
    size_t toCount;
};

// Whether the hit of lane _i_ blocks: never on the roots p and q, at once when it is
// beyond rounding, else as CGAL's exact test on the true triangle says.
bool Blocks(const RayBatch &batch, const RTCFilterFunctionNArguments *args, unsigned i) {
    RTCRayN *ray = args->ray;
    RTCHitN *hit = args->hit;
    unsigned n = args->N;
    uint32_t geom = RTCHitN_geomID(hit, n, i), prim = RTCHitN_primID(hit, n, i);
    const auto &t = batch.embree->Hit(geom, prim);
    if (t.root == batch.p || t.root == batch.q)
        return false;
    float dx = RTCRayN_dir_x(ray, n, i), dy = RTCRayN_dir_y(ray, n, i),
          dz = RTCRayN_dir_z(ray, n, i);
    float gx = RTCHitN_Ng_x(hit, n, i), gy = RTCHitN_Ng_y(hit, n, i), gz = RTCHitN_Ng_z(hit, n, i);
    float length = std::sqrt(dx * dx + dy * dy + dz * dz);
    float sine =
        std::abs(dx * gx + dy * gy + dz * gz) / (length * std::sqrt(gx * gx + gy * gy + gz * gz));
    float u = RTCHitN_u(hit, n, i), v = RTCHitN_v(hit, n, i);
    // The hit's distance from the segment's start (the ray starts _reach_ before it).
    float along = RTCRayN_tfar(ray, n, i) * length - float(batch.embree->reach);
    if (sine >= kMinSine && 1 - u - v >= t.minBary[0] && u >= t.minBary[1] && v >= t.minBary[2] &&
        along >= t.margin && length - along >= t.margin)
        return true;
    unsigned id = RTCRayN_id(ray, n, i);
    Segment3 query = Trimmed(batch.from[id / batch.toCount], batch.to[id % batch.toCount]);
    return CGAL::do_intersect(query, (*batch.triangles)[&t - batch.embree->triangles.data()].datum);
}

void OcclusionFilter(const RTCFilterFunctionNArguments *args) {
    const auto &batch = *reinterpret_cast<const RayBatch *>(args->context);
    for (unsigned i = 0; i < args->N; ++i)
        if (args->valid[i] && !Blocks(batch, args, i))
            args->valid[i] = 0;
}

// The extent S of the scene for the margins: what float rounding of a coordinate or of
// a difference of two is relative to.
double Extent(const std::vector<Tagged<Triangle3>> &triangles) {
    CGAL::Bbox_3 box;
    for (const auto &t : triangles)
        box += t.datum.bbox();
    double diagonal =
        std::hypot(box.xmax() - box.xmin(), box.ymax() - box.ymin(), box.zmax() - box.zmin());
    double far = std::hypot(std::max(-box.xmin(), box.xmax()), std::max(-box.ymin(), box.ymax()),
                            std::max(-box.zmin(), box.zmax()));
    return diagonal + far;
}

// The margin of triangle _t_ in a scene of extent _extent_ (kMarginUlps float roundings
// of S, times S over the shortest edge).
double Margin(const Triangle3 &t, double extent) {
    double shortest = std::sqrt(std::min({CGAL::squared_distance(t.vertex(0), t.vertex(1)),
                                          CGAL::squared_distance(t.vertex(1), t.vertex(2)),
                                          CGAL::squared_distance(t.vertex(2), t.vertex(0))}));
    return kMarginUlps * std::ldexp(1.0, -24) * extent * extent / shortest;
}

// Whether Embree pays: where at most 1% of the triangles grow by more than their
// inradius. A mesh of small triangles in a large room (the bunny's box: triangles of
// 1e-5 of its area) grows each by many times its size, so every ray near the surface
// meets dozens of grown triangles that the exact test then turns down (on that box, 60 us
// a ray against 3 us through CGAL's tree, with the same counts).
bool EmbreeSuits(const std::vector<Tagged<Triangle3>> &triangles) {
    double extent = Extent(triangles);
    size_t grown = 0;
    for (const auto &[t, root] : triangles) {
        double inradius = std::sqrt(t.squared_area()) * 2 /
                          (std::sqrt(CGAL::squared_distance(t.vertex(0), t.vertex(1))) +
                           std::sqrt(CGAL::squared_distance(t.vertex(1), t.vertex(2))) +
                           std::sqrt(CGAL::squared_distance(t.vertex(2), t.vertex(0))));
        grown += !(Margin(t, extent) <= inradius);
    }
    return grown * 100 <= triangles.size();
}

// Grows triangle _t_ by _margin_ (scaled about its incentre, so every edge moves out by
// the margin) into _out_, and records where the true triangle lies inside it.
void Grow(const Triangle3 &t, double margin, float out[9], EmbreeScene::Triangle &info) {
    Vec3 v[3];
    for (int k = 0; k < 3; ++k)
        v[k] = Vec3(t.vertex(k).x(), t.vertex(k).y(), t.vertex(k).z());
    double edge[3];  // opposite v0, v1, v2
    for (int k = 0; k < 3; ++k)
        edge[k] = (v[(k + 1) % 3] - v[(k + 2) % 3]).norm();
    double perimeter = edge[0] + edge[1] + edge[2];
    double twiceArea = (v[1] - v[0]).cross(v[2] - v[0]).norm();
    Vec3 incentre = (edge[0] * v[0] + edge[1] * v[1] + edge[2] * v[2]) / perimeter;
    double scale = 1 + margin * perimeter / twiceArea;  // 1 + margin / inradius
    for (int k = 0; k < 3; ++k) {
        Vec3 grown = incentre + scale * (v[k] - incentre);
        for (int c = 0; c < 3; ++c)
            out[3 * k + c] = float(grown[c]);
        // A margin inside the true edge is two margins inside the grown one, whose
        // height is scale times the true one.
        info.minBary[k] = float(2 * margin * edge[k] / (scale * twiceArea));
    }
    info.margin = float(margin);
}

// The triangles of one root patch, grown, as one Embree geometry (geomID = the root),
// with the mask bit of the root.
void AddPatch(EmbreeScene &index, const std::vector<Tagged<Triangle3>> &triangles, size_t begin,
              size_t end, double extent) {
    RTCGeometry geometry = rtcNewGeometry(Device(), RTC_GEOMETRY_TYPE_TRIANGLE);
    unsigned count = unsigned(end - begin);
    auto *vertices = static_cast<float *>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * count));
    auto *corners = static_cast<unsigned *>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), count));
    for (unsigned k = 0; k < count; ++k) {
        auto &info = index.triangles[begin + k];
        info.root = triangles[begin + k].root;
        Grow(triangles[begin + k].datum, Margin(triangles[begin + k].datum, extent),
             vertices + 9 * k, info);
        for (unsigned c = 0; c < 3; ++c)
            corners[3 * k + c] = 3 * k + c;
    }
    uint32_t root = triangles[begin].root;
    rtcSetGeometryMask(geometry, MaskOf(root));
    rtcSetGeometryOccludedFilterFunction(geometry, OcclusionFilter);
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(index.scene, geometry, root);
    rtcReleaseGeometry(geometry);
    index.first[root] = uint32_t(begin);
}

// Every root patch as a geometry of grown triangles, with the filter that decides each
// hit, in one scene committed once.
std::unique_ptr<EmbreeScene> BuildEmbree(const std::vector<Tagged<Triangle3>> &triangles,
                                         uint32_t patchCount) {
    auto index = std::make_unique<EmbreeScene>();
    double extent = Extent(triangles), ulp = std::ldexp(1.0, -24);
    index->reach = kMarginUlps * ulp * extent;
    index->maskRoots = patchCount <= 32;
    index->triangles.resize(triangles.size());
    index->first.resize(patchCount);
    index->scene = rtcNewScene(Device());
    rtcSetSceneBuildQuality(index->scene, RTC_BUILD_QUALITY_HIGH);
    for (size_t begin = 0, end; begin < triangles.size(); begin = end) {
        for (end = begin + 1;
             end < triangles.size() && triangles[end].root == triangles[begin].root;)
            ++end;
        AddPatch(*index, triangles, begin, end, extent);
    }
    rtcCommitScene(index->scene);
    if (rtcGetDeviceError(Device()) != RTC_ERROR_NONE)
        throw std::runtime_error("Embree: cannot build the scene of the occluders");
    return index;
}

// The ray of the segment from _a_ to _b_, reaching _reach_ beyond both ends so that
// hits at the ends are found and left to the filter (t in [0, 1 + 2 reach / |b - a|]).
RTCRay Ray(const Vec3 &a, const Vec3 &b, float reach, unsigned mask, unsigned id) {
    Vec3 d = b - a;
    float dx = float(d.x()), dy = float(d.y()), dz = float(d.z());
    float extra = reach / std::sqrt(dx * dx + dy * dy + dz * dz);
    RTCRay ray;
    ray.org_x = float(a.x()) - extra * dx;
    ray.org_y = float(a.y()) - extra * dy;
    ray.org_z = float(a.z()) - extra * dz;
    ray.dir_x = dx, ray.dir_y = dy, ray.dir_z = dz;
    ray.tnear = 0;
    ray.tfar = 1 + 2 * extra;
    ray.time = 0;
    ray.mask = mask;
    ray.id = id;
    ray.flags = 0;
    return ray;
}

uint64_t EmbreeCountVisible(const EmbreeScene &embree,
                            const std::vector<Tagged<Triangle3>> &triangles,
                            const std::vector<Vec3> &from, const std::vector<Vec3> &to, uint32_t p,
                            uint32_t q) {
    // The rays of one pair leave one element for another: a coherent stream, which
    // Embree traces in packets.
    RayBatch batch{{}, &embree, &triangles, p, q, from.data(), to.data(), to.size()};
    rtcInitIntersectContext(&batch.context);
    batch.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    thread_local std::vector<RTCRay> rays;
    rays.clear();
    uint64_t visible = 0;
    float reach = float(embree.reach);
    unsigned mask = embree.RayMask(p, q);
    for (size_t i = 0; i < from.size(); ++i)
        for (size_t j = 0; j < to.size(); ++j) {
            if (Trimmed(from[i], to[j]).is_degenerate())
                ++visible;  // nothing in between to block
            else
                rays.push_back(Ray(from[i], to[j], reach, mask, unsigned(i * to.size() + j)));
        }
    rtcOccluded1M(embree.scene, &batch.context, rays.data(), unsigned(rays.size()), sizeof(RTCRay));
    for (const RTCRay &ray : rays)
        visible += ray.tfar >= 0;  // Embree sets it to -inf when blocked
    return visible;
}

}  // namespace

#else

struct EmbreeScene {};

#endif

// Collect the occluders, tagged with their root patch, and build the tree (or Embree's
// scene) now so that later queries only read it.
Occluders::Occluders(const Patches<Polygon> &patches, VisibilityBackend backend)
    : index_(std::make_unique<Index>()) {
    if (backend == VisibilityBackend::Embree && !HasEmbree())
        throw std::invalid_argument("this build of hrbench has no Embree");
    for (uint32_t k = 0; k < patches.size(); ++k) {
        const Polygon &p = patches[k].shape;
        index_->triangles.push_back({{ToPoint(p.v[0]), ToPoint(p.v[1]), ToPoint(p.v[2])}, k});
        if (p.n == 4)
            index_->triangles.push_back({{ToPoint(p.v[0]), ToPoint(p.v[2]), ToPoint(p.v[3])}, k});
    }
#ifdef HRBENCH_HAVE_EMBREE
    if (backend == VisibilityBackend::Auto && EmbreeSuits(index_->triangles))
        backend = VisibilityBackend::Embree;
    if (backend == VisibilityBackend::Embree) {
        embree_ = BuildEmbree(index_->triangles, uint32_t(patches.size()));
        return;
    }
#endif
    index_->triangleTree.insert(index_->triangles.begin(), index_->triangles.end());
    index_->triangleTree.build();
}

// 2D scenes are CGAL's whatever the backend: Embree has no segments in a plane.
Occluders::Occluders(const Patches<Segment> &patches, VisibilityBackend)
    : index_(std::make_unique<Index>()) {
    for (uint32_t k = 0; k < patches.size(); ++k) {
        const Segment &s = patches[k].shape;
        index_->segments.push_back({{ToPoint(s.a), ToPoint(s.b)}, k});
    }
    index_->segmentTree.insert(index_->segments.begin(), index_->segments.end());
    index_->segmentTree.build();
}

Occluders::~Occluders() = default;

// A query whose trimmed ends coincide (sample points of touching elements) has nothing
// in between to block; CGAL's predicates also require a segment of positive length.
bool Occluders::Blocked(const Vec3 &a, const Vec3 &b, uint32_t p, uint32_t q) const {
    if (embree_)
        return CountVisible(std::vector<Vec3>{a}, std::vector<Vec3>{b}, p, q) == 0;
    Segment3 query = Trimmed(a, b);
    return !query.is_degenerate() && AnyOtherHit(index_->triangleTree, query, p, q);
}

bool Occluders::Blocked(const Vec2 &a, const Vec2 &b, uint32_t p, uint32_t q) const {
    Segment3 query = Trimmed(a, b);
    return !query.is_degenerate() && AnyOtherHit(index_->segmentTree, query, p, q);
}

uint64_t Occluders::CountVisible(const std::vector<Vec3> &from, const std::vector<Vec3> &to,
                                 uint32_t p, uint32_t q) const {
#ifdef HRBENCH_HAVE_EMBREE
    if (embree_)
        return EmbreeCountVisible(*embree_, index_->triangles, from, to, p, q);
#endif
    uint64_t visible = 0;
    for (const Vec3 &a : from)
        for (const Vec3 &b : to)
            visible += !Blocked(a, b, p, q);
    return visible;
}

uint64_t Occluders::CountVisible(const std::vector<Vec2> &from, const std::vector<Vec2> &to,
                                 uint32_t p, uint32_t q) const {
    uint64_t visible = 0;
    for (const Vec2 &a : from)
        for (const Vec2 &b : to)
            visible += !Blocked(a, b, p, q);
    return visible;
}

}  // namespace hrbench
