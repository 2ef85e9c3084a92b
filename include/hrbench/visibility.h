// Visibility between elements: exact segment queries (CGAL) against an AABB tree of
// the scene's patches, sampled on a fixed pattern so that every count is deterministic.
// See docs/3d.md for the sampling pattern and the three modes.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

// The patches of a scene as occluders, in an AABB tree: 3D faces as triangles (a quad
// as v0 v1 v2 and v0 v2 v3), 2D segments as themselves. Queries use CGAL's exact
// predicates; a segment that touches an occluder, even at one point, is blocked, except
// within 1e-9 of its length from either end (so that the back of a two-sided blocker or
// a neighbour through an end point does not count). Immutable after construction, so
// queries may run on several threads.
class Occluders {
  public:
    explicit Occluders(const Patches<Segment> &patches);
    explicit Occluders(const Patches<Polygon> &patches);
    ~Occluders();
    Occluders(const Occluders &) = delete;
    Occluders &operator=(const Occluders &) = delete;

    // True when the closed segment from _a_ to _b_ meets a patch other than the
    // roots _p_ and _q_ (the patches the segment's endpoints lie on); false for a
    // segment of no length (the sample points of touching elements may coincide).
    bool Blocked(const Vec3 &a, const Vec3 &b, uint32_t p, uint32_t q) const;
    bool Blocked(const Vec2 &a, const Vec2 &b, uint32_t p, uint32_t q) const;

  private:
    struct Index;
    std::unique_ptr<Index> index_;
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
    // and its rays in _tally_.
    template <typename Forest>
    double Fraction(const Forest &forest, uint32_t i, uint32_t j, VisibilityTally &tally) {
        samplesI_.clear(), samplesJ_.clear();
        forest.ShapeOf(i).SamplePoints(k_, samplesI_);
        forest.ShapeOf(j).SamplePoints(k_, samplesJ_);
        uint32_t p = forest[i].root, q = forest[j].root;
        uint64_t visible = 0;
        for (const auto &a : samplesI_)
            for (const auto &b : samplesJ_)
                visible += !occluders_->Blocked(a, b, p, q);
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
};

}  // namespace hrbench
