// Visibility between elements: segment queries against the scene's patches, decided
// with CGAL's exact predicates (through CGAL's AABB tree, or Embree's BVH with CGAL
// deciding the close calls), sampled on a fixed pattern so that every count is
// deterministic. See docs/3d.md for the sampling pattern, the modes and the backends.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hrbench/forest.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

// How 3D segment queries find their candidate patches: CGAL's AABB tree, or Embree's
// BVH in single precision, whose hits are accepted only where they are beyond doubt
// and otherwise decided by the same exact predicate (docs/3d.md); Auto takes Embree
// where the build has it and the scene's triangles are large beside Embree's margins,
// else CGAL. 2D scenes always use CGAL.
enum class VisibilityBackend { Auto, Cgal, Embree };

// True when this build has Embree (found when it was configured).
bool HasEmbree();

struct EmbreeScene;  // visibility.cpp

// The patches of a scene as occluders: 3D faces as triangles (a quad as v0 v1 v2 and
// v0 v2 v3), 2D segments as themselves. Queries use CGAL's exact predicates; a segment
// that touches an occluder, even at one point, is blocked, except within 1e-9 of its
// length from either end (so that the back of a two-sided blocker or a neighbour
// through an end point does not count). Immutable after construction, so queries may
// run on several threads.
class Occluders {
  public:
    // Throws std::invalid_argument when _backend_ is Embree and the build has none.
    explicit Occluders(const Patches<Segment> &patches,
                       VisibilityBackend backend = VisibilityBackend::Auto);
    explicit Occluders(const Patches<Polygon> &patches,
                       VisibilityBackend backend = VisibilityBackend::Auto);
    ~Occluders();
    Occluders(const Occluders &) = delete;
    Occluders &operator=(const Occluders &) = delete;

    // True when the closed segment from _a_ to _b_ meets a patch other than the
    // roots _p_ and _q_ (the patches the segment's endpoints lie on); false for a
    // segment of no length (the sample points of touching elements may coincide).
    bool Blocked(const Vec3 &a, const Vec3 &b, uint32_t p, uint32_t q) const;
    bool Blocked(const Vec2 &a, const Vec2 &b, uint32_t p, uint32_t q) const;

    // The number of segments from a point of _from_ to a point of _to_ that are not
    // Blocked: the same count, cast as one batch.
    uint64_t CountVisible(const std::vector<Vec3> &from, const std::vector<Vec3> &to, uint32_t p,
                          uint32_t q) const;
    uint64_t CountVisible(const std::vector<Vec2> &from, const std::vector<Vec2> &to, uint32_t p,
                          uint32_t q) const;

  private:
    struct Index;
    std::unique_ptr<Index> index_;
    std::unique_ptr<EmbreeScene> embree_;  // set when the 3D queries go through Embree
};

// Counts of the visibility policy, summed over a run.
struct VisibilityTally {
    uint64_t rays = 0;           // segment queries cast
    uint64_t queries = 0;        // element pairs whose visible fraction was estimated
    uint64_t occludedPairs = 0;  // element pairs found fully occluded (never linked)

    void Add(const VisibilityTally &o) {
        rays += o.rays, queries += o.queries, occludedPairs += o.occludedPairs;
    }
};

// The kernel's visibility policy when occlusion is ignored: compiles to nothing.
struct NoVisibility {
    static constexpr bool kEnabled = false;
};

// The kernel's visibility policy when occlusion counts: the visible fraction of a pair
// is the share of unblocked segments among all pairs of sample points. Each kernel
// (and so each thread) holds its own copy, with its own scratch space.
template <typename Shape>
class SampledVisibility {
  public:
    static constexpr bool kEnabled = true;

    SampledVisibility(const Occluders &occluders, int raysPerSide, VisibilityMode mode)
        : occluders_(&occluders), k_(raysPerSide), mode_(mode) {}

    VisibilityMode Mode() const { return mode_; }

    // Fraction in [0, 1] of the sample segments between elements _i_ and _j_ (the
    // shapes' SamplePoints, k per side) that no third patch blocks; counts the query
    // and its rays in _tally_. Keeps the samples of the last query's elements, for as
    // long as _forest_ is the same one (it may grow; ids never change).
    template <typename Forest>
    double Fraction(const Forest &forest, uint32_t i, uint32_t j, VisibilityTally &tally) {
        // One side of consecutive queries is mostly the same element (the kernel splits
        // the other): its samples are kept from the last query.
        if (&forest != forest_ || i != sampledI_) {
            samplesI_.clear();
            shapesI_.ShapeOf(forest, i).SamplePoints(k_, samplesI_);
        }
        if (&forest != forest_ || j != sampledJ_) {
            samplesJ_.clear();
            shapesJ_.ShapeOf(forest, j).SamplePoints(k_, samplesJ_);
        }
        forest_ = &forest, sampledI_ = i, sampledJ_ = j;
        uint64_t visible =
            occluders_->CountVisible(samplesI_, samplesJ_, forest[i].root, forest[j].root);
        uint64_t rays = uint64_t(samplesI_.size()) * samplesJ_.size();
        ++tally.queries;
        tally.rays += rays;
        return visible == rays ? 1.0 : double(visible) / double(rays);
    }

  private:
    const Occluders *occluders_;
    int k_;
    VisibilityMode mode_;
    std::vector<typename Shape::Vec> samplesI_, samplesJ_;
    ShapeCursor<Shape> shapesI_, shapesJ_;  // the shapes near the last query's elements
    const void *forest_ = nullptr;          // whose elements sampledI_ and sampledJ_ are
    uint32_t sampledI_ = 0, sampledJ_ = 0;
};

// Calls _f_ with the visibility policy of _options_, the one way a refinement picks
// it: NoVisibility when occlusion is ignored (compiled out of the kernel),
// SampledVisibility otherwise.
template <typename Shape, typename F>
void WithVisibility(const Patches<Shape> &patches, const RefineOptions &options, F &&f) {
    if (options.visibility == VisibilityMode::None)
        return f(NoVisibility());
    Occluders occluders(patches);
    f(SampledVisibility<Shape>(occluders, options.raysPerSide, options.visibility));
}

}  // namespace hrbench
