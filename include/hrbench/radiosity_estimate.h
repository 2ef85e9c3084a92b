// The radiosity that the bf oracle (oracles/bf.h) reads for an element: per root patch
// (the first pass: the patches' emission), or from a previous solution on the element
// forest of an earlier refinement of the same scene (docs/conventions.md#oracles).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "hrbench/forest.h"
#include "hrbench/scene.h"

namespace hrbench {

// An immutable lookup B(element) for any element of any refinement of one scene.
// Const after construction, so any number of threads may read it at once; a lookup is
// a function of the query's hot record alone, so it is deterministic.
template <typename Shape>
class RadiosityEstimate {
  public:
    using ElementType = Element<Shape::kDimension>;
    using Vec = typename Shape::Vec;

    // One value per root patch, in scene order: each element of a root gets its root's.
    explicit RadiosityEstimate(std::vector<double> rootValues) : values_(std::move(rootValues)) {
        CheckValues();
    }

    // The emission E of every root patch: the first pass, before anything is solved.
    static RadiosityEstimate FromEmission(const Patches<Shape> &roots) {
        std::vector<double> emission;
        for (const Patch<Shape> &p : roots)
            emission.push_back(p.material.emission);
        return RadiosityEstimate(std::move(emission));
    }

    // A previous solution: its forest (roots 0..n-1 in scene order) and one value per
    // element of it, indexed by element id (the solver's pulled, area-weighted values).
    RadiosityEstimate(Forest<Shape> forest, std::vector<double> values)
        : values_(std::move(values)), forest_(std::move(forest)) {
        if (values_.size() != forest_->Size())
            throw std::invalid_argument("a radiosity estimate needs one value per element: " +
                                        std::to_string(values_.size()) + " values for " +
                                        std::to_string(forest_->Size()) + " elements");
        CheckValues();
        for (uint32_t root = 0; root < forest_->NumRoots(); ++root)
            normals_.push_back(forest_->ShapeOf(root).Normal());
    }

    size_t NumRoots() const { return forest_ ? forest_->NumRoots() : values_.size(); }
    // Bytes held: the values, and a previous solution's forest and its roots' normals.
    size_t Bytes() const {
        return values_.size() * sizeof(double) + normals_.size() * sizeof(Vec) +
               (forest_ ? forest_->Size() * Forest<Shape>::kBytesPerElement : 0);
    }
    // The largest value anywhere: 0 when nothing emits.
    double Max() const {
        double max = 0;
        for (double b : values_)
            max = std::max(max, b);
        return max;
    }

    // The largest value of any element of each root patch, in scene order: a bound on
    // what the estimate gives any element of that patch (the cluster form of bf).
    std::vector<double> RootMax() const {
        if (!forest_)
            return values_;
        std::vector<double> max(forest_->NumRoots(), 0.0);
        for (uint32_t e = 0; e < forest_->Size(); ++e)
            max[(*forest_)[e].root] = std::max(max[(*forest_)[e].root], values_[e]);
        return max;
    }

    // The value for _query_, an element of a refinement of the same scene under the same
    // subdivision rule. Per root: that root's value. From a previous forest: descend from
    // the query's root, at each element into the child that contains the query's
    // centroid (Child()), and stop at a leaf or at the first element no larger than the
    // query (A^2 <= the query's A^2): under the same rule, the query element itself, or
    // its deepest ancestor in the previous forest when the query is finer than it.
    double operator()(const ElementType &query) const {
        uint32_t e = query.root;
        if (!forest_)
            return values_[e];
        Shape shape = forest_->RootShape(e);  // the shape of _e_, made on the way down
        for (;;) {
            const ElementType &hot = (*forest_)[e];
            if (hot.firstChild == kNoChildren || hot.sizeSquared <= query.sizeSquared)
                return values_[e];
            e = Child(hot.firstChild, shape, query.center, query.root);
        }
    }

  private:
    void CheckValues() const {
        for (double b : values_)
            if (!(b >= 0) || !std::isfinite(b))
                throw std::invalid_argument("a radiosity estimate holds a value that is "
                                            "negative or not finite");
    }

    // The child of _parent_ (a shape; its children are first .. first + arity - 1) that
    // holds _point_, whose shape then replaces _parent_'s: among those that contain it
    // (Contains()), the one with the nearest centroid, else the nearest of all (a point
    // that rounding put outside every child); equal squared distances go to the first
    // child. A query's centroid lies inside one child, off its sides by a fraction of
    // the query's size, so the rounding of the sides cannot move it.
    uint32_t Child(uint32_t first, Shape &parent, const Vec &point, uint32_t root) const {
        std::array<Shape, 4> children;
        parent.Subdivide(forest_->Mode(), children);
        uint32_t best = first;
        bool bestContains = false;
        double bestDistance = 0;
        for (uint32_t c = first; c < first + uint32_t(forest_->Arity()); ++c) {
            bool contains = Contains(children[c - first], point, root);
            double distance = ((*forest_)[c].center - point).squaredNorm();
            if (c == first || (contains && !bestContains) ||
                (contains == bestContains && distance < bestDistance))
                best = c, bestContains = contains, bestDistance = distance;
        }
        parent = children[best - first];
        return best;
    }

    // Whether _point_ lies in _shape_ or on its boundary, seen along the root's normal:
    // 2D, between the perpendiculars at the segment's ends (its parameter in [0, 1]); 3D,
    // on the inner side of every edge v_k -> v_k+1 of the counter-clockwise polygon,
    // ((v_k+1 - v_k) x (point - v_k)) . n >= 0, which ignores the point's distance
    // from the plane (the test of its projection onto the plane).
    bool Contains(const Shape &shape, const Vec &point, uint32_t root) const {
        if constexpr (Shape::kDimension == 2) {
            Vec along = shape.b - shape.a;
            return (point - shape.a).dot(along) >= 0 && (shape.b - point).dot(along) >= 0;
        } else {
            const Vec &n = normals_[root];
            for (int k = 0; k < shape.n; ++k) {
                const Vec &from = shape.v[size_t(k)], &to = shape.v[size_t((k + 1) % shape.n)];
                if ((to - from).cross(point - from).dot(n) < 0)
                    return false;
            }
            return true;
        }
    }

    std::vector<double> values_;           // per root, or per element of forest_
    std::optional<Forest<Shape>> forest_;  // the previous refinement, if any
    std::vector<Vec> normals_;             // unit front normal of each root of forest_
};

}  // namespace hrbench
