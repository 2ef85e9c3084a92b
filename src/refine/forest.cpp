#include "hrbench/forest.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "hrbench/util/error.h"

namespace hrbench {

double SquaredSizeBound(double size) {
    if (!(size > 0))
        return 0;
    // Bisect on the bit patterns of the doubles in [0, +inf], which are ordered as the
    // values: find the first whose square root reaches _size_.
    uint64_t lo = 0, hi = 0x7ff0000000000000;  // sqrt(+0) = 0 < size; sqrt(+inf) = +inf
    while (hi - lo > 1) {
        uint64_t mid = lo + (hi - lo) / 2;
        double s;
        std::memcpy(&s, &mid, sizeof s);
        (std::sqrt(s) >= size ? hi : lo) = mid;
    }
    double bound;
    std::memcpy(&bound, &hi, sizeof bound);
    return bound;
}

template <typename Shape>
Forest<Shape>::Forest(const Patches<Shape> &patches, size_t maxElements, Subdivision mode)
    : numRoots_(patches.size()), maxElements_(maxElements), mode_(mode),
      arity_(SubdivisionArity(mode)), patches_(&patches) {
    if (numRoots_ >= (size_t(1) << 31))
        throw InputError("scene has too many patches");
    if (maxElements < SIZE_MAX) {
        size_t n = std::min<size_t>(maxElements, UINT32_MAX);
        hot_.ReserveUpFront(n), depth_.ReserveUpFront(n);
        splitElement_.ReserveUpFront(n / arity_ + 1);
    }
    for (const Patch<Shape> &patch : patches) {
        const Shape &s = patch.shape;
        hot_.push_back({s.Centroid(), s.SquaredMeasure(), kNoChildren, uint32_t(hot_.size())});
        depth_.push_back(0);
    }
}

template <typename Shape>
const Shape &ShapeCursor<Shape>::ShapeOf(const Forest<Shape> &forest, uint32_t e) {
    if (&forest != forest_)
        forest_ = &forest, Clear();
    // The path in _e_'s tree, else the one used less recently.
    uint32_t root = forest[e].root;
    int p = !paths_[last_].ids.empty() && paths_[last_].ids[0] == root ? last_ : 1 - last_;
    Path &path = paths_[p];
    last_ = p;
    // Up from _e_ to the deepest element the path holds, or to the root.
    below_.clear();
    for (uint32_t a = e;; a = forest.Parent(a)) {
        size_t depth = size_t(forest.Depth(a));
        if (depth < path.ids.size() && path.ids[depth] == a) {
            path.ids.resize(depth + 1), path.shapes.resize(depth + 1);
            break;
        }
        if (depth == 0) {
            path.ids.assign(1, a), path.shapes.assign(1, forest.RootShape(a));
            break;
        }
        below_.push_back(a);
    }
    // Down to _e_ again, one subdivision per level.
    std::array<Shape, 4> children;
    for (; !below_.empty(); below_.pop_back()) {
        uint32_t child = below_.back();
        path.shapes.back().Subdivide(forest.Mode(), children);
        path.ids.push_back(child);
        path.shapes.push_back(children[(child - forest.NumRoots()) % size_t(forest.Arity())]);
    }
    return path.shapes.back();
}

template <typename Shape>
Shape Forest<Shape>::ShapeOf(uint32_t i) const {
    if (i < numRoots_)
        return RootShape(i);
    return ShapeCursor<Shape>().ShapeOf(*this, i);
}

template <typename Shape>
std::vector<Shape> Forest<Shape>::AllShapes() const {
    std::vector<Shape> shapes(Size());
    for (uint32_t root = 0; root < numRoots_; ++root)
        shapes[root] = RootShape(root);
    std::array<Shape, 4> children;
    for (size_t g = 0; g < splitElement_.size(); ++g) {
        shapes[splitElement_[g]].Subdivide(mode_, children);
        std::copy_n(children.begin(), arity_, shapes.begin() + ptrdiff_t(numRoots_ + g * arity_));
    }
    return shapes;
}

template <typename Shape>
uint32_t Forest<Shape>::Subdivide(uint32_t i) {
    // Refuse to grow past the budget or past 32-bit indices.
    if (hot_.size() + arity_ > maxElements_ || hot_.size() + arity_ > UINT32_MAX)
        throw LimitError("element trees would exceed the memory budget (" +
                         std::to_string(hot_.size()) + " elements); raise --max-memory or eps");

    // Split element _i_ and check that double precision still resolves its children.
    uint32_t first = uint32_t(hot_.size());
    bool recent = first - i <= kRecent;
    const Shape &shape = i < numRoots_ ? RootShape(i)
                         : recent      ? recentShapes_[i % kRecent]
                                       : cursor_.ShapeOf(*this, i);
    std::array<Shape, 4> children;
    int n = shape.Subdivide(mode_, children);  // == arity
    std::array<double, 4> squares{}, sizes{};
    for (int c = 0; c < n; ++c) {
        squares[c] = children[c].SquaredMeasure();
        sizes[c] = std::sqrt(squares[c]);  // == children[c].Measure()
    }
    if (!Shape::Resolves(hot_[i].Size(), sizes, n))
        throw LimitError("element " + std::to_string(i) + " of patch " +
                         std::to_string(hot_[i].root) +
                         " is too small for double precision at depth " +
                         std::to_string(depth_[i]) + "; use --min-area or --max-depth");

    // Append the children, first child first, and their parent.
    uint32_t root = hot_[i].root;
    uint8_t depth = uint8_t(depth_[i] + 1);
    recentShapes_.resize(kRecent);
    for (int c = 0; c < n; ++c) {
        hot_.push_back({children[c].Centroid(), squares[c], kNoChildren, root});
        depth_.push_back(depth);
        recentShapes_[(first + c) % kRecent] = children[c];
    }
    splitElement_.push_back(i);
    hot_[i].firstChild = first;
    return first;
}

template <typename Shape>
uint64_t Forest<Shape>::Position(uint32_t i) const {
    uint64_t position = 0, weight = 1;
    for (; i >= numRoots_; i = Parent(i), weight *= uint64_t(arity_))
        position += (i - numRoots_) % arity_ * weight;
    return position;
}

template <typename Shape>
std::vector<uint64_t> Forest<Shape>::NodesPerDepth() const {
    std::vector<uint64_t> histogram;
    for (uint8_t d : depth_) {
        if (d >= histogram.size())
            histogram.resize(d + 1, 0);
        ++histogram[d];
    }
    return histogram;
}

template <typename Shape>
uint64_t Forest<Shape>::NumLeaves() const {
    uint64_t leaves = 0;
    for (const ElementType &e : hot_)
        leaves += e.firstChild == kNoChildren;
    return leaves;
}

template class ShapeCursor<Segment>;
template class ShapeCursor<Polygon>;
template class Forest<Segment>;
template class Forest<Polygon>;

}  // namespace hrbench
