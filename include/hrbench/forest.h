// The element trees of every root patch of a scene, for one shape, in one flat arena:
// indices, not pointers, children created on demand, once, and shared by every later
// branch that reaches the element (docs/conventions.md).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "hrbench/geometry/subdivision.h"
#include "hrbench/scene.h"
#include "hrbench/util/reserved_array.h"

namespace hrbench {

// What the refinement kernel reads for every oracle call (32 bytes in 2D, 40 in 3D).
template <int D>
struct Element {
    Vector<D> center;  // centroid, where the oracle measures distances
    // A^2, the squared size: squared length (2D) or squared area (3D), computed once by
    // Shape::SquaredMeasure() with the formula of docs/conventions.md. The kernel picks
    // the element to split by comparing it, exactly; whoever needs A itself takes
    // Size() = sqrt(A^2), which is Shape::Measure().
    double sizeSquared;
    uint32_t firstChild;  // index of the first child (children are consecutive); 0 if a leaf
    uint32_t root;        // index of the root patch in scene order

    // The element size A: length (2D) or area (3D).
    double Size() const { return std::sqrt(sizeSquared); }
};
static_assert(sizeof(Element<2>) == 32 && sizeof(Element<3>) == 40,
              "the hot record is 32 bytes in 2D, 40 in 3D");

// The least double s >= 0 with sqrt(s) >= _size_ (+infinity if there is none), so that
// sqrt(s) < size exactly when s < SquaredSizeBound(size), for every double s >= 0 (the
// square root is correctly rounded, hence monotone). Lets a bound on A be checked on A^2
// with no square root and no rounding of its own.
double SquaredSizeBound(double size);

// Element 0 is always a root, so it can never be anyone's child.
constexpr uint32_t kNoChildren = 0;

template <typename Shape>
class Forest;

// The shapes of the elements on two paths down the trees of one forest (one per root,
// the two roots used last), kept between calls: the shape of an element near the last
// one asked for in its tree is made from their deepest common ancestor's, in a few
// subdivisions, where Forest::ShapeOf() makes it from the root's. Two paths, since the
// refinement splits the elements of a pair by turns. The forest may grow between calls
// (ids never change); a cursor asked about another forest starts again.
template <typename Shape>
class ShapeCursor {
  public:
    const Shape &ShapeOf(const Forest<Shape> &forest, uint32_t e);

  private:
    void Clear() { paths_[0].Clear(), paths_[1].Clear(); }

    struct Path {
        std::vector<uint32_t> ids;  // ids[d]: the path's element at depth d (ids[0] its root)
        std::vector<Shape> shapes;  // and its shape
        void Clear() { ids.clear(), shapes.clear(); }
    };
    const Forest<Shape> *forest_ = nullptr;
    Path paths_[2];
    int last_ = 0;                 // the path used last
    std::vector<uint32_t> below_;  // scratch: from the element asked for up to its path
};

template <typename Shape>
class Forest {
  public:
    using ElementType = Element<Shape::kDimension>;

    // Bytes one element costs in the arena, at most: hot record and depth, and its share
    // (half, or a quarter in a quadtree) of its sibling group's parent. Shapes are not
    // kept: ShapeOf() makes them again from the root's.
    static constexpr size_t kBytesPerElement =
        sizeof(ElementType) + sizeof(uint8_t) + sizeof(uint32_t) / 2;

    // Creates one root element per patch; elements 0..n-1 are the roots. _maxElements_
    // bounds the arena (a memory budget): growing past it throws LimitError. A finite
    // bound is reserved as address space where that is free (ReservationsAreFree()),
    // so that growing to it moves nothing. The roots' shapes are read from _patches_,
    // not copied (a copy took 104 bytes a polygon, 208 MB for 2M triangles, and as
    // much again in each worker's copy of the forest): the patches must outlive the
    // forest and its copies, in place. A temporary would not, and is refused.
    Forest(const Patches<Shape> &patches, size_t maxElements, Subdivision mode);
    Forest(const Patches<Shape> &&, size_t, Subdivision) = delete;
    // A forest of no patches, for a result that a run sets later.
    explicit Forest(Subdivision mode) : Forest(kNoPatches, SIZE_MAX, mode) {}

    // The hot data of element _i_.
    const ElementType &operator[](uint32_t i) const { return hot_[i]; }
    size_t Size() const { return hot_.size(); }
    size_t NumRoots() const { return numRoots_; }
    Subdivision Mode() const { return mode_; }
    int Arity() const { return arity_; }

    // Makes room for _n_ elements in all, so that growing to that many moves nothing.
    void Reserve(size_t n) {
        hot_.Reserve(n), depth_.Reserve(n);
        splitElement_.Reserve(n / arity_ + 1);
    }

    // Returns the index of the first child of _i_, subdividing _i_ the first time it is
    // asked; later calls share the same children (Arity() of them, consecutive).
    uint32_t Children(uint32_t i) {
        uint32_t first = hot_[i].firstChild;
        return first != kNoChildren ? first : Subdivide(i);
    }

    // The element split into each sibling group, in the order the groups were made
    // (group g: elements NumRoots() + g * Arity() onwards): the shape of the trees
    // without their geometry, and the order they grew in.
    std::vector<uint32_t> SplitElements() const {
        return std::vector<uint32_t>(splitElement_.begin(), splitElement_.end());
    }

    // Lifts the memory budget: the union of several workers' forests grows past any
    // one worker's budget, and a run's forest carries none, whatever the thread count.
    void LiftBudget() { maxElements_ = SIZE_MAX; }
    // Bounds the arena to _maxElements_ from now on: a worker's share of what a run's
    // budget leaves after its first pass.
    void LimitBudget(size_t maxElements) { maxElements_ = maxElements; }

    // Cold data, for output and tests. The shape of element _i_, made again from its
    // root's by subdividing down the path to _i_: the subdivision is deterministic, so
    // it is the same shape, bit for bit, every time. Costs Depth(i) subdivisions;
    // ShapeCursor (below) makes the shapes of nearby elements in a few.
    Shape ShapeOf(uint32_t i) const;
    const Shape &RootShape(uint32_t root) const { return (*patches_)[root].shape; }
    // The shape of every element, in id order, made in one pass over the sibling groups
    // in the order they were made: for work that needs the shapes of many elements.
    std::vector<Shape> AllShapes() const;
    int Depth(uint32_t i) const { return depth_[i]; }
    // Parent element, or the element itself for a root.
    uint32_t Parent(uint32_t i) const {
        return i < numRoots_ ? i : splitElement_[(i - numRoots_) / arity_];
    }
    // Index of _i_ among the Arity()^Depth(i) elements of its depth in its tree, in
    // subdivision order (a segment's position along its root, from its start).
    uint64_t Position(uint32_t i) const;

    // Bytes the trees hold (their arrays' elements, not the address space reserved
    // beyond them, nor the patches).
    size_t Bytes() const {
        return recentShapes_.size() * sizeof(Shape) + hot_.size() * sizeof(ElementType) +
               depth_.size() + splitElement_.size() * sizeof(uint32_t);
    }

    // Counters of the trees: elements per depth, elements without children.
    std::vector<uint64_t> NodesPerDepth() const;
    uint64_t NumLeaves() const;

  private:
    uint32_t Subdivide(uint32_t i);

    size_t numRoots_;
    size_t maxElements_;
    Subdivision mode_;
    int arity_;
    const Patches<Shape> *patches_;  // the roots' shapes
    static inline const Patches<Shape> kNoPatches{};
    ReservedArray<ElementType> hot_;
    ReservedArray<uint8_t> depth_;
    // Per sibling group g (elements numRoots + g * arity onwards, in the order they were
    // made): the element split into it.
    ReservedArray<uint32_t> splitElement_;
    // The shapes of the last kRecent elements made, element e's at e % kRecent (ids are
    // made in order, so none overwrites a younger one): most elements are split soon
    // after they are made, a few hundred elements later in the refinement's order
    // (docs/benchmarks.md), and then need no subdivision to make their shape again.
    static constexpr uint32_t kRecent = 4096;
    std::vector<Shape> recentShapes_;  // kRecent once the forest first splits
    // The shapes down to the element split last, for the others: the next split is
    // mostly near it.
    ShapeCursor<Shape> cursor_;
};

extern template class ShapeCursor<Segment>;
extern template class ShapeCursor<Polygon>;
extern template class Forest<Segment>;
extern template class Forest<Polygon>;

}  // namespace hrbench
