#include "run_report.h"

#include <chrono>
#include <ctime>
#include <iomanip>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "util/args.h"

#ifndef HRBENCH_VERSION
#define HRBENCH_VERSION "unknown"
#endif
#ifndef HRBENCH_BUILD_TYPE
#define HRBENCH_BUILD_TYPE "unknown"
#endif

namespace hrbench {

using nlohmann::json;

std::string EngineVersion() { return HRBENCH_VERSION; }

static json Context() {
    char host[256] = "unknown";
    gethostname(host, sizeof host - 1);
    std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    return {{"version", EngineVersion()},
            {"build_type", HRBENCH_BUILD_TYPE},
            {"date", date},
            {"host", host}};
}

json RunToJson(const Scene &scene, const RefineOptions &options, const Refinement &refinement) {
    json record;
    record["schema_version"] = kRunSchemaVersion;
    record["version"] = EngineVersion();
    record["context"] = Context();
    record["scene"] = scene.family;
    record["params"] = scene.params;
    record["patches"] = scene.NumPatches();
    record["eps"] = options.eps;
    record["oracle"] = OracleName(options.oracle);
    record["mode"] = options.storeLinks ? "store" : "count-only";
    record["min_area"] = options.minArea > 0 ? json(options.minArea) : json(nullptr);
    record["max_depth_limit"] = options.maxDepth >= 0 ? json(options.maxDepth) : json(nullptr);
    record["threads"] = options.threads;
    record["dimension"] = scene.dimension;
    record["subdivision"] = SubdivisionName(options.subdivision);
    record["visibility"] = VisibilityName(options.visibility);
    record["rays_per_side"] =
        options.visibility == VisibilityMode::None ? json(nullptr) : json(options.raysPerSide);
    AddCountersToJson(refinement.counters, record);
    record["seconds"] = refinement.seconds;
    return record;
}

void PrintRunTable(const json &record, std::ostream &out) {
    out << "scene     " << record["scene"].get<std::string>();
    for (const auto &[key, value] : record["params"].items())
        out << " " << key << "=" << FormatDouble(value.get<double>());
    out << "\noracle    " << record["oracle"].get<std::string>() << "  eps "
        << FormatDouble(record["eps"].get<double>()) << "  mode "
        << record["mode"].get<std::string>() << "\n\n";
    for (const char *key : {"nodes", "leaves", "links", "oracle_calls", "max_depth",
                            "forced_links", "culled_pairs", "root_pairs", "rays", "visibility_queries",
                            "occluded_pairs"})
        out << std::left << std::setw(19) << key << std::right << std::setw(15)
            << record[key].dump() << "\n";
    out << std::left << std::setw(19) << "seconds" << std::right << std::setw(15)
        << std::setprecision(6) << record["seconds"].get<double>() << "\n";
    for (const char *key : {"nodes_per_depth", "links_per_depth"})
        out << std::left << std::setw(14) << key << " " << record[key].dump() << "\n";
}

// The 3D form of the links CSV: roots, element ids, areas, centroids and depths.
static void WriteLinksCsv3D(const Refinement &refinement, std::ostream &out) {
    const PolygonForest &forest = refinement.forest3d;
    out << "root_i,elem_i,area_i,cx_i,cy_i,cz_i,depth_i,root_j,elem_j,area_j,cx_j,cy_j,cz_j,"
           "depth_j\n";
    for (const Link &link : refinement.links) {
        for (uint32_t e : {link.i, link.j}) {
            const Vec3 &c = forest[e].center;
            out << forest[e].root << "," << e << "," << FormatDouble(forest[e].size) << ","
                << FormatDouble(c.x()) << "," << FormatDouble(c.y()) << "," << FormatDouble(c.z())
                << "," << forest.Depth(e) << (e == link.i ? "," : "\n");
        }
    }
}

void WriteLinksCsv(const Refinement &refinement, std::ostream &out) {
    if (refinement.forest3d.Size() > 0)
        return WriteLinksCsv3D(refinement, out);
    const SegmentForest &forest = refinement.forest;
    out << "root_i,elem_i,t0_i,t1_i,depth_i,root_j,elem_j,t0_j,t1_j,depth_j\n";
    for (const Link &link : refinement.links) {
        for (uint32_t e : {link.i, link.j}) {
            out << forest[e].root << "," << e << "," << FormatDouble(forest.T0(e)) << ","
                << FormatDouble(forest.T1(e)) << "," << forest.Depth(e)
                << (e == link.i ? "," : "\n");
        }
    }
}

}  // namespace hrbench
