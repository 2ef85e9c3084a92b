// Comparing two refinements in tests: their counters, their stored links and their
// element trees, for either shape.
#pragma once

#include <algorithm>
#include <sstream>
#include <string>

#include "hrbench.h"

namespace hrbench_test {

// Every counter of _a_ and _b_ that differs, one per line, named as CounterTable()
// names it; empty if they agree.
inline std::string CounterDifferences(const hrbench::Counters &a, const hrbench::Counters &b) {
    std::ostringstream out;
    for (const hrbench::CounterInfo &c : hrbench::CounterTable()) {
        if (c.scalar && a.*c.scalar != b.*c.scalar)
            out << c.name << ": " << a.*c.scalar << " vs " << b.*c.scalar << "\n";
        if (c.histogram && a.*c.histogram != b.*c.histogram)
            out << c.name << " differs\n";
    }
    return out.str();
}

// True when _a_ and _b_ hold the same links in the same order.
inline bool SameLinks(const hrbench::LinkBuffer &a, const hrbench::LinkBuffer &b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(),
                      [](const auto &x, const auto &y) { return x.i == y.i && x.j == y.j; });
}

// The first element where the forests _a_ and _b_ differ (in size, centre, root,
// children, parent or depth), or empty if they hold the same elements under the same ids.
template <typename Shape>
std::string ForestDifferences(const hrbench::Forest<Shape> &a, const hrbench::Forest<Shape> &b) {
    std::ostringstream out;
    if (a.Size() != b.Size()) {
        out << "sizes: " << a.Size() << " vs " << b.Size() << "\n";
        return out.str();
    }
    for (uint32_t e = 0; e < a.Size(); ++e) {
        if (a[e].size != b[e].size || a[e].center != b[e].center || a[e].root != b[e].root ||
            a[e].firstChild != b[e].firstChild || a.Parent(e) != b.Parent(e) ||
            a.Depth(e) != b.Depth(e)) {
            out << "element " << e << " differs\n";
            break;
        }
    }
    return out.str();
}

// Everything two refinements of one scene may differ in: counters, links, per root pair
// tallies and the element trees; empty if they are the same refinement.
template <typename Shape>
std::string RefinementDifferences(const hrbench::Refinement<Shape> &a,
                                  const hrbench::Refinement<Shape> &b) {
    std::string out = CounterDifferences(a.record.counters, b.record.counters);
    if (!SameLinks(a.links, b.links))
        out += "links differ\n";
    bool samePairs = a.pairs.size() == b.pairs.size() &&
                     std::equal(a.pairs.begin(), a.pairs.end(), b.pairs.begin(),
                                [](const auto &x, const auto &y) {
                                    return x.p == y.p && x.q == y.q && x.links == y.links &&
                                           x.oracleCalls == y.oracleCalls;
                                });
    if (!samePairs)
        out += "pair tallies differ\n";
    return out + ForestDifferences(a.forest, b.forest);
}

}  // namespace hrbench_test
