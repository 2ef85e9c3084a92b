// Comparing two refinements in tests: their counters, their stored links and their
// element trees, for either shape; and the invariants a refinement satisfies per root pair.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <string>
#include <utility>

#include "hrbench/hrbench.h"

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
        if (a[e].sizeSquared != b[e].sizeSquared || a[e].center != b[e].center ||
            a[e].root != b[e].root || a[e].firstChild != b[e].firstChild ||
            a.Parent(e) != b.Parent(e) || a.Depth(e) != b.Depth(e)) {
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

// The invariants of docs/conventions.md that every stored refinement without visibility
// satisfies, one line for each that fails; empty if all hold:
//  - per root pair, the oracle calls follow from its links: 2L - 1 (binary) or
//    (4L - 1) / 3 (quadtree);
//  - per root pair, its links tile the pair's parameter domain P x Q: the sum of
//    A_i A_j is A_P A_Q, to _relTolerance_;
//  - the per pair links add up to the links counter and the stored links; the histograms
//    add up to the nodes and links counters; nodes is the size of the forest.
template <typename Shape>
std::string TilingViolations(const hrbench::Scene &scene, const hrbench::Refinement<Shape> &r,
                             double relTolerance = 1e-12) {
    std::ostringstream out;
    out.precision(17);
    const hrbench::Forest<Shape> &f = r.forest;
    const hrbench::Patches<Shape> &roots = scene.Get<Shape>();
    std::map<std::pair<uint32_t, uint32_t>, double> area;
    for (const hrbench::Link &link : r.links)
        area[{f[link.i].root, f[link.j].root}] += f[link.i].Size() * f[link.j].Size();
    uint64_t linksSeen = 0;
    for (const hrbench::PairTally &pair : r.pairs) {
        bool callsFollow = f.Mode() == hrbench::Subdivision::Binary
                               ? pair.oracleCalls == 2 * pair.links - 1
                               : 3 * pair.oracleCalls == 4 * pair.links - 1;
        if (!callsFollow)
            out << "pair " << pair.p << "," << pair.q << ": " << pair.oracleCalls
                << " oracle calls for " << pair.links << " links\n";
        double expected = roots[pair.p].shape.Measure() * roots[pair.q].shape.Measure();
        double tiled = area[std::make_pair(pair.p, pair.q)];
        if (!(std::abs(tiled - expected) <=
              relTolerance * std::max(std::abs(tiled), std::abs(expected))))
            out << "pair " << pair.p << "," << pair.q << ": links tile " << tiled << ", not "
                << expected << "\n";
        linksSeen += pair.links;
    }
    const hrbench::Counters &c = r.record.counters;
    if (linksSeen != c.links || r.links.size() != c.links)
        out << "links: " << linksSeen << " over the pairs, " << r.links.size() << " stored, "
            << c.links << " counted\n";
    uint64_t nodes = 0, links = 0;
    for (uint64_t n : c.nodesPerDepth)
        nodes += n;
    for (uint64_t n : c.linksPerDepth)
        links += n;
    if (nodes != c.nodes || c.nodes != f.Size())
        out << "nodes: " << nodes << " per depth, " << c.nodes << " counted, " << f.Size()
            << " in the forest\n";
    if (links != c.links)
        out << "links per depth: " << links << " for " << c.links << " links\n";
    return out.str();
}

}  // namespace hrbench_test
