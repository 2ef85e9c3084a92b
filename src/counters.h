// The exact counters of one refinement run, named as in DESIGN section 2.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace hrbench {

struct Counters {
    uint64_t nodes = 0;         // elements of every tree, roots included
    uint64_t leaves = 0;        // elements without children
    uint64_t links = 0;         // element pairs linked (each stands for both directions)
    uint64_t oracleCalls = 0;   // evaluations of the oracle
    int maxDepth = 0;           // depth of the deepest element (roots have depth 0)
    uint64_t forcedLinks = 0;   // links made by the recursion limit, not the oracle
    uint64_t culledPairs = 0;   // root pairs that cannot exchange light, never refined
    uint64_t rootPairs = 0;     // unordered root pairs considered, culled ones included
    uint64_t rays = 0;               // visibility segments cast (0 with --visibility none)
    uint64_t visibilityQueries = 0;  // element pairs whose visible fraction was estimated
    uint64_t occludedPairs = 0;      // element pairs found fully occluded, never linked
    std::vector<uint64_t> nodesPerDepth;  // elements per element depth
    std::vector<uint64_t> linksPerDepth;  // links per link depth depth_i + depth_j
};

// Adds every counter to _out_ as a top-level key (`oracle_calls`, `nodes_per_depth`, ...).
void AddCountersToJson(const Counters &counters, nlohmann::json &out);

}  // namespace hrbench
