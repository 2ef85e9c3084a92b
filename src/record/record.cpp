#include "hrbench/record.h"

#include <ctime>
#include <fstream>
#include <iomanip>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "build_info.h"
#include "hrbench/oracles/registry.h"
#include "util/format.h"

namespace hrbench {

void CountInitialLinking(Counters &c) {
    c.linkingLinks = c.clusterLinks + c.rootPairs - c.culledPairs;
    c.linkingCalls = c.clusterOracleCalls + c.rootPairs;
}

void DropTrailingZeros(std::vector<uint64_t> &histogram) {
    while (!histogram.empty() && histogram.back() == 0)
        histogram.pop_back();
}

using nlohmann::json;

const std::vector<CounterInfo> &CounterTable() {
    using C = Counters;
    static const std::vector<CounterInfo> table = {
        {"nodes", "tree", "elements", "elements of every tree, roots included", &C::nodes, nullptr},
        {"leaves", "tree", "elements", "elements without children", &C::leaves, nullptr},
        {"links", "refine", "links", "element pairs linked; each stands for both directions",
         &C::links, nullptr},
        {"oracle_calls", "refine", "calls", "evaluations of the oracle", &C::oracleCalls, nullptr},
        {"max_depth", "tree", "levels", "depth of the deepest element (roots have depth 0)",
         &C::maxDepth, nullptr},
        {"forced_links", "refine", "links", "links made by a recursion limit, not the oracle",
         &C::forcedLinks, nullptr},
        {"culled_pairs", "refine", "root pairs", "root pairs that cannot exchange light",
         &C::culledPairs, nullptr},
        {"root_pairs", "refine", "root pairs", "unordered root pairs, culled ones included",
         &C::rootPairs, nullptr},
        {"rays", "visibility", "rays", "visibility segments cast", &C::rays, nullptr},
        {"visibility_queries", "visibility", "element pairs",
         "element pairs whose visible fraction was estimated", &C::visibilityQueries, nullptr},
        {"occluded_pairs", "visibility", "element pairs",
         "element pairs found fully occluded, never linked", &C::occludedPairs, nullptr},
        {"cluster_nodes", "tree", "clusters", "clusters in the hierarchy (--clusters)",
         &C::clusterNodes, nullptr},
        {"cluster_links", "refine", "links", "links with a cluster at one end at least",
         &C::clusterLinks, nullptr},
        {"element_links", "refine", "links",
         "links between elements (--clusters; links = element_links + cluster_links)",
         &C::elementLinks, nullptr},
        {"cluster_oracle_calls", "refine", "calls",
         "cluster oracle calls (oracle_calls includes them)", &C::clusterOracleCalls, nullptr},
        {"opened_clusters", "refine", "clusters",
         "distinct clusters opened by a refused cluster pair", &C::openedClusters, nullptr},
        {"linking_links", "refine", "links",
         "links of the initial linking: cluster_links + root_pairs - culled_pairs",
         &C::linkingLinks, nullptr},
        {"linking_calls", "refine", "calls",
         "node pairs the initial linking decides: cluster_oracle_calls + root_pairs",
         &C::linkingCalls, nullptr},
        {"nodes_per_depth", "tree", "elements", "elements per element depth", nullptr,
         &C::nodesPerDepth},
        {"links_per_depth", "refine", "links", "links per link depth depth_i + depth_j", nullptr,
         &C::linksPerDepth},
    };
    return table;
}

std::string EngineVersion() { return HRBENCH_VERSION; }

// The first "model name" of /proc/cpuinfo, or "unknown".
static std::string CpuModel() {
    std::ifstream cpuinfo("/proc/cpuinfo");
    for (std::string line; std::getline(cpuinfo, line);) {
        if (line.rfind("model name", 0) != 0)
            continue;
        size_t colon = line.find(':');
        if (colon != std::string::npos && colon + 2 <= line.size())
            return line.substr(colon + 2);
    }
    return "unknown";
}

json RunContext() {
    char host[256] = "unknown";
    gethostname(host, sizeof host - 1);
    std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    return {{"version", EngineVersion()},
            {"build_type", HRBENCH_BUILD_TYPE},
            {"compiler", HRBENCH_COMPILER},
            {"build_flags", HRBENCH_BUILD_FLAGS},
            {"git_commit", HRBENCH_GIT_COMMIT},
            {"cpu_model", CpuModel()},
            {"date", date},
            {"host", host}};
}

json RunToJson(const Scene &scene, const RefineOptions &options, const RunRecord &record) {
    json out;
    out["schema_version"] = kRunSchemaVersion;
    out["version"] = EngineVersion();
    out["context"] = RunContext();
    out["scene"] = scene.family;
    out["params"] = scene.params;
    if (!scene.file.empty())
        out[scene.family == "mesh" ? "mesh_file" : "scene_file"] = scene.file;
    out["patches"] = scene.NumPatches();
    out["dimension"] = scene.Dimension();
    out["scene_sha256"] = SceneSha256(scene);  // the geometry refined (docs/scene-format.md)
    out["eps"] = record.sweptEps.value_or(options.eps);
    out["oracle"] = options.oracle;
    // The form-factor estimate, for an oracle that reads one (null: does not apply).
    out["ff_estimate"] = FindOracle(options.oracle).Reads("ff_estimate")
                             ? json(FfEstimateName(options.ffEstimate))
                             : json(nullptr);
    out["method"] = record.method;
    out["mode"] = options.storeLinks ? "store" : "count-only";
    double minArea = record.sweptMinArea.value_or(options.minArea);
    out["min_area"] = minArea > 0 ? json(minArea) : json(nullptr);
    out["max_depth_limit"] = options.maxDepth >= 0 ? json(options.maxDepth) : json(nullptr);
    out["threads"] = options.threads;
    out["subdivision"] = SubdivisionName(options.subdivision);
    out["visibility"] = VisibilityName(options.visibility);
    out["clusters"] = options.clusters;
    out["cluster_bound"] =
        options.clusters ? json(ClusterBoundName(options.clusterBound)) : json(nullptr);
    out["rays_per_side"] =
        options.visibility == VisibilityMode::None ? json(nullptr) : json(options.raysPerSide);
    for (const CounterInfo &c : CounterTable()) {
        if (c.scalar)
            out[c.name] = record.counters.*c.scalar;
        else
            out[c.name] = record.counters.*c.histogram;
    }
    out["seconds"] = record.seconds;
    out["cpu_seconds"] = record.cpuSeconds;
    out["linking_seconds"] = record.linkingSeconds ? json(*record.linkingSeconds) : json(nullptr);
    out["linking_bytes"] = record.linkingBytes;
    return out;
}

std::string OracleLabel(const json &record) {
    std::string label = record["oracle"].get<std::string>();
    auto estimate = record.find("ff_estimate");
    if (estimate != record.end() && estimate->is_string())
        label += " (" + estimate->get<std::string>() + ")";
    return label;
}

void PrintRunTable(const json &record, std::ostream &out) {
    out << "scene     " << record["scene"].get<std::string>();
    for (const auto &[key, value] : record["params"].items())
        out << " " << key << "=" << FormatDouble(value.get<double>());
    out << "\noracle    " << OracleLabel(record) << "  eps "
        << FormatDouble(record["eps"].get<double>()) << "  mode "
        << record["mode"].get<std::string>() << "\n\n";
    for (const CounterInfo &c : CounterTable())
        if (c.scalar)
            out << std::left << std::setw(19) << c.name << std::right << std::setw(15)
                << record[c.name].dump() << "\n";
    // Only where asked for (run --link-form-factors): the default table stays as it was.
    for (const char *key : {"link_form_factor_max", "link_form_factor_above_eps"})
        if (record.contains(key))
            out << std::left << std::setw(27) << key << FormatDouble(record[key].get<double>())
                << "\n";
    out << std::left << std::setw(19) << "seconds" << std::right << std::setw(15)
        << std::setprecision(6) << record["seconds"].get<double>() << "\n";
    for (const CounterInfo &c : CounterTable())
        if (c.histogram)
            out << std::left << std::setw(14) << c.name << " " << record[c.name].dump() << "\n";
}

}  // namespace hrbench
