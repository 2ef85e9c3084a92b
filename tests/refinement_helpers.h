// Comparing two refinements in tests: their counters and their stored links.
#pragma once

#include <algorithm>
#include <sstream>
#include <string>

#include "hrbench.h"

namespace hrbench_test {

// Every counter of _a_ and _b_ that differs, one per line; empty if they agree.
inline std::string CounterDifferences(const hrbench::Counters &a, const hrbench::Counters &b) {
    std::ostringstream out;
    auto field = [&](const char *name, auto x, auto y) {
        if (x != y)
            out << name << ": " << x << " vs " << y << "\n";
    };
    field("nodes", a.nodes, b.nodes);
    field("leaves", a.leaves, b.leaves);
    field("links", a.links, b.links);
    field("oracle_calls", a.oracleCalls, b.oracleCalls);
    field("max_depth", a.maxDepth, b.maxDepth);
    field("forced_links", a.forcedLinks, b.forcedLinks);
    field("culled_pairs", a.culledPairs, b.culledPairs);
    field("root_pairs", a.rootPairs, b.rootPairs);
    field("rays", a.rays, b.rays);
    field("visibility_queries", a.visibilityQueries, b.visibilityQueries);
    field("occluded_pairs", a.occludedPairs, b.occludedPairs);
    if (a.nodesPerDepth != b.nodesPerDepth)
        out << "nodes_per_depth differs\n";
    if (a.linksPerDepth != b.linksPerDepth)
        out << "links_per_depth differs\n";
    return out.str();
}

// True when _a_ and _b_ hold the same links in the same order.
inline bool SameLinks(const hrbench::LinkBuffer &a, const hrbench::LinkBuffer &b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(), [](const auto &x, const auto &y) {
               return x.i == y.i && x.j == y.j;
           });
}

}  // namespace hrbench_test
