#include "hrbench/forest.h"

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
    : numRoots_(patches.size()), maxElements_(maxElements), mode_(mode) {
    if (numRoots_ >= (size_t(1) << 31))
        throw InputError("scene has too many patches");
    for (const Patch<Shape> &patch : patches) {
        const Shape &s = patch.shape;
        hot_.push_back({s.Centroid(), s.SquaredMeasure(), kNoChildren, uint32_t(hot_.size())});
        shapes_.push_back(s);
        depth_.push_back(0);
        parent_.push_back(uint32_t(parent_.size()));
    }
}

template <typename Shape>
uint32_t Forest<Shape>::Subdivide(uint32_t i) {
    // Refuse to grow past the budget or past 32-bit indices.
    int arity = Arity();
    if (hot_.size() + arity > maxElements_ || hot_.size() + arity > UINT32_MAX)
        throw LimitError("element trees would exceed the memory budget (" +
                         std::to_string(hot_.size()) + " elements); raise --max-memory or eps");

    // Split element _i_ and check that double precision still resolves its children.
    std::array<Shape, 4> children;
    int n = shapes_[i].Subdivide(mode_, children);  // == arity
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

    // Append the children, first child first.
    uint32_t first = uint32_t(hot_.size());
    uint32_t root = hot_[i].root;
    uint8_t depth = uint8_t(depth_[i] + 1);
    for (int c = 0; c < n; ++c) {
        hot_.push_back({children[c].Centroid(), squares[c], kNoChildren, root});
        shapes_.push_back(children[c]);
        depth_.push_back(depth);
        parent_.push_back(i);
    }
    hot_[i].firstChild = first;
    return first;
}

template <typename Shape>
std::vector<uint32_t> Forest<Shape>::Canonicalize() {
    // The new id of every element: the preorder walk of the union (ForestUnion in
    // refine.cpp), numbering each sibling group when its parent is reached.
    std::vector<uint32_t> id(Size());
    uint32_t next = uint32_t(numRoots_);
    std::vector<uint32_t> stack;
    for (uint32_t root = uint32_t(numRoots_); root-- > 0;) {
        id[root] = root;
        stack.push_back(root);
    }
    const int arity = Arity();
    while (!stack.empty()) {
        uint32_t e = stack.back();
        stack.pop_back();
        uint32_t first = hot_[e].firstChild;
        if (first == kNoChildren)
            continue;
        for (int c = 0; c < arity; ++c)
            id[first + c] = next + c;
        next += arity;
        for (int c = arity; c-- > 0;)
            stack.push_back(first + c);
    }

    // Point the links between elements at the new ids, then move every element to its
    // new place, cycle by cycle.
    for (uint32_t e = 0; e < Size(); ++e) {
        if (hot_[e].firstChild != kNoChildren)
            hot_[e].firstChild = id[hot_[e].firstChild];
        parent_[e] = id[parent_[e]];
    }
    std::vector<bool> placed(Size());
    for (uint32_t start = 0; start < Size(); ++start) {
        if (placed[start] || id[start] == start)
            continue;
        ElementType hot = hot_[start];
        Shape shape = shapes_[start];
        uint8_t depth = depth_[start];
        uint32_t parent = parent_[start];
        for (uint32_t to = id[start]; !placed[start]; to = id[to]) {
            std::swap(hot, hot_[to]), std::swap(shape, shapes_[to]);
            std::swap(depth, depth_[to]), std::swap(parent, parent_[to]);
            placed[to] = true;
        }
    }
    maxElements_ = SIZE_MAX;
    return id;
}

template <typename Shape>
uint64_t Forest<Shape>::Position(uint32_t i) const {
    uint64_t position = 0, weight = 1;
    for (; parent_[i] != i; i = parent_[i], weight *= uint64_t(Arity()))
        position += (i - hot_[parent_[i]].firstChild) * weight;
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

template class Forest<Segment>;
template class Forest<Polygon>;

}  // namespace hrbench
