// Element trees of all root patches in one flat arena: indices, not pointers,
// and no allocation per element beyond the arena's amortised growth.
#pragma once

#include <cstdint>
#include <vector>

#include "scene.h"

namespace hrbench {

// What the refinement kernel reads for every oracle call (32 bytes in 2D).
template <int D>
struct Element {
    Eigen::Matrix<double, D, 1> center;  // centroid (2D: the midpoint, where it is halved)
    double size;                         // A: length (2D) or area (3D)
    uint32_t firstChild;  // index of the first child (children are consecutive); 0 if a leaf
    uint32_t root;        // index of the root patch in scene order
};

// Element 0 is always a root, so it can never be anyone's child.
constexpr uint32_t kNoChildren = 0;

// Elements per depth, from the depth of every element.
std::vector<uint64_t> DepthHistogram(const std::vector<uint8_t> &depths);

// Elements without children.
template <typename ElementType>
uint64_t CountLeaves(const std::vector<ElementType> &elements) {
    uint64_t leaves = 0;
    for (const ElementType &e : elements)
        leaves += e.firstChild == kNoChildren;
    return leaves;
}

// The trees of a flatland scene: every segment halved at its midpoint, on demand.
class SegmentForest {
  public:
    using ElementType = Element<2>;
    static constexpr int kArity = 2;  // binary subdivision

    // Creates one root element per patch of _scene_; elements 0..n-1 are the roots.
    // _maxElements_ bounds the arena (a memory budget); exceeding it throws LimitError.
    SegmentForest(const Scene &scene, size_t maxElements);

    const ElementType &operator[](uint32_t i) const { return hot_[i]; }
    size_t Size() const { return hot_.size(); }
    size_t NumRoots() const { return numRoots_; }

    // Returns the index of the first child of _i_, halving _i_ at its midpoint the
    // first time it is asked; later calls share the same two children.
    uint32_t Children(uint32_t i) {
        uint32_t first = hot_[i].firstChild;
        return first != kNoChildren ? first : Subdivide(i);
    }

    // Cold data, for output and tests.
    int Depth(uint32_t i) const { return depth_[i]; }
    // Parent element, or the element itself for a root.
    uint32_t Parent(uint32_t i) const { return parent_[i]; }
    const Vec2 &Start(uint32_t i) const { return start_[i]; }
    const Vec2 &End(uint32_t i) const { return end_[i]; }
    // Interval [T0, T1] of the element in arc length along its root, from the root's start.
    double T0(uint32_t i) const;
    double T1(uint32_t i) const;

    // Counters of the trees: elements per depth, leaves, deepest element.
    std::vector<uint64_t> NodesPerDepth() const;
    uint64_t NumLeaves() const;

  private:
    uint32_t Subdivide(uint32_t i);

    size_t numRoots_;
    size_t maxElements_;
    std::vector<ElementType> hot_;
    std::vector<Vec2> start_, end_;
    std::vector<uint8_t> depth_;
    std::vector<uint32_t> parent_;
    std::vector<uint64_t> position_;  // index of the element among the 2^depth of its depth
    std::vector<double> rootLength_;
};

}  // namespace hrbench
