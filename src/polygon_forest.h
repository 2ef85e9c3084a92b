// Element trees of a 3D scene in one flat arena, as SegmentForest is for flatland:
// indices, not pointers, children created on demand, once, and shared.
#pragma once

#include <cstdint>
#include <vector>

#include "element_tree.h"
#include "polygon.h"
#include "scene.h"

namespace hrbench {

// The trees of every face of a 3D scene. The subdivision mode is fixed at
// construction; PolygonForestOf adds the compile-time arity the kernel loops over.
class PolygonForest {
  public:
    using ElementType = Element<3>;

    // An empty forest (no roots).
    PolygonForest() = default;
    // Creates one root element per face of _scene_; elements 0..n-1 are the roots.
    // _maxElements_ bounds the arena (a memory budget); exceeding it throws LimitError.
    PolygonForest(const Scene &scene, size_t maxElements, Subdivision mode);

    const ElementType &operator[](uint32_t i) const { return hot_[i]; }
    size_t Size() const { return hot_.size(); }
    size_t NumRoots() const { return numRoots_; }
    Subdivision Mode() const { return mode_; }
    int Arity() const { return SubdivisionArity(mode_); }

    // Returns the index of the first child of _i_, subdividing _i_ the first time it
    // is asked; later calls share the same children (2 or 4, consecutive).
    uint32_t Children(uint32_t i) {
        uint32_t first = hot_[i].firstChild;
        return first != kNoChildren ? first : Subdivide(i);
    }

    // Cold data, for visibility sampling, output and tests.
    const Polygon &Shape(uint32_t i) const { return shape_[i]; }
    int Depth(uint32_t i) const { return depth_[i]; }
    // Parent element, or the element itself for a root.
    uint32_t Parent(uint32_t i) const { return parent_[i]; }

    // Counters of the trees: elements per depth, leaves.
    std::vector<uint64_t> NodesPerDepth() const;
    uint64_t NumLeaves() const;

    // Bytes one element costs in the arena (hot and cold data).
    static constexpr size_t kBytesPerElement =
        sizeof(ElementType) + sizeof(Polygon) + sizeof(uint8_t) + sizeof(uint32_t);

  private:
    uint32_t Subdivide(uint32_t i);

    size_t numRoots_ = 0;
    size_t maxElements_ = 0;
    Subdivision mode_ = Subdivision::Binary;
    std::vector<ElementType> hot_;
    std::vector<Polygon> shape_;
    std::vector<uint8_t> depth_;
    std::vector<uint32_t> parent_;
};

// A PolygonForest whose arity the refinement kernel knows at compile time.
template <Subdivision kMode>
class PolygonForestOf : public PolygonForest {
  public:
    static constexpr int kArity = SubdivisionArity(kMode);

    PolygonForestOf(const Scene &scene, size_t maxElements)
        : PolygonForest(scene, maxElements, kMode) {}
};

using BinaryPolygonForest = PolygonForestOf<Subdivision::Binary>;
using QuadtreePolygonForest = PolygonForestOf<Subdivision::Quadtree>;

}  // namespace hrbench
