#include "counters.h"

#include <nlohmann/json.hpp>

namespace hrbench {

void AddCountersToJson(const Counters &c, nlohmann::json &out) {
    out["nodes"] = c.nodes;
    out["leaves"] = c.leaves;
    out["links"] = c.links;
    out["oracle_calls"] = c.oracleCalls;
    out["max_depth"] = c.maxDepth;
    out["forced_links"] = c.forcedLinks;
    out["culled_pairs"] = c.culledPairs;
    out["root_pairs"] = c.rootPairs;
    out["rays"] = c.rays;
    out["visibility_queries"] = c.visibilityQueries;
    out["occluded_pairs"] = c.occludedPairs;
    out["nodes_per_depth"] = c.nodesPerDepth;
    out["links_per_depth"] = c.linksPerDepth;
}

}  // namespace hrbench
