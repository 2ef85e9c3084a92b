// The run record: the exact counters of one run, the one table that names them, and
// the writers that present a run (JSON, human table). Every method of counting (the
// enumerating kernel, the translation method) produces a RunRecord.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

// Schema version of `hrbench run --json` records.
constexpr int kRunSchemaVersion = 1;

// The exact counters of one run (docs/conventions.md); all identical on every run,
// build type and thread count. CounterTable() names each for output.
struct Counters {
    uint64_t nodes = 0;              // elements of every tree, roots included
    uint64_t leaves = 0;             // elements without children
    uint64_t links = 0;              // element pairs linked (each stands for both directions)
    uint64_t oracleCalls = 0;        // evaluations of the oracle
    uint64_t maxDepth = 0;           // depth of the deepest element (roots have depth 0)
    uint64_t forcedLinks = 0;        // links made by the recursion limit, not the oracle
    uint64_t culledPairs = 0;        // root pairs that cannot exchange light, never refined
    uint64_t rootPairs = 0;          // unordered root pairs considered, culled ones included
    uint64_t rays = 0;               // visibility segments cast (0 with --visibility none)
    uint64_t visibilityQueries = 0;  // element pairs whose visible fraction was estimated
    uint64_t occludedPairs = 0;      // element pairs found fully occluded, never linked
    // --clusters only (0 without; docs/conventions.md#clusters):
    uint64_t clusterNodes = 0;        // clusters in the hierarchy
    uint64_t clusterLinks = 0;        // links with a cluster at one end at least
    uint64_t elementLinks = 0;        // links between elements (links = these + clusterLinks)
    uint64_t clusterOracleCalls = 0;  // cluster oracle calls (oracleCalls includes them)
    uint64_t openedClusters = 0;      // distinct clusters opened by a refused cluster pair
    // The initial linking, everything decided above the input patches (with or without
    // --clusters; docs/conventions.md#initial-linking), set by CountInitialLinking:
    uint64_t linkingLinks = 0;            // cluster_links + root_pairs - culled_pairs
    uint64_t linkingCalls = 0;            // cluster_oracle_calls + root_pairs
    std::vector<uint64_t> nodesPerDepth;  // elements per element depth
    std::vector<uint64_t> linksPerDepth;  // links per link depth depth_i + depth_j
};

// Sets the initial linking's counters of _c_ from its cluster and root-pair counters.
void CountInitialLinking(Counters &c);

// Drops a histogram's trailing zero bins: every counted histogram ends at its last
// nonzero one, whichever method counted it.
void DropTrailingZeros(std::vector<uint64_t> &histogram);

// One counter as output names it. Exactly one of _scalar_ and _histogram_ is set.
struct CounterInfo {
    const char *name;      // JSON key, benchmark counter and table row, e.g. "oracle_calls"
    const char *category;  // "tree", "refine" or "visibility"
    const char *unit;      // what one count is, e.g. "elements"
    const char *doc;       // one line
    uint64_t Counters::*scalar;
    std::vector<uint64_t> Counters::*histogram;
};

// Every counter, in output order: the scalars, then the histograms.
const std::vector<CounterInfo> &CounterTable();

// What one run measured, whichever method produced it.
struct RunRecord {
    std::string method;  // "enumerate" or "translation"
    Counters counters;
    double seconds = 0;  // wall time of the count, in seconds
    // The eps or --min-area the record was counted at where one count made records of
    // several (run --sweep); unset: the run's options say it. RunToJson reads them.
    std::optional<double> sweptEps, sweptMinArea;
    double cpuSeconds = 0;  // CPU time of the count, every thread's, in seconds
    // The initial linking (Counters::linkingLinks): its wall time, the refinement of the
    // root pairs it hands down left out (unset where the method does not time it apart:
    // translation, run --sweep), and the bytes of what it builds and keeps (the cluster
    // hierarchy, its nodes' balls, its links in store mode; 0 without clusters).
    std::optional<double> linkingSeconds;
    uint64_t linkingBytes = 0;
};

// The JSON record of one run: schema version, context, scene and its provenance, the
// options, every counter of CounterTable() as a top-level key, method and seconds.
nlohmann::json RunToJson(const Scene &scene, const RefineOptions &options, const RunRecord &record);

// The `context` of every JSON output: engine version, build (type, compiler, flags, git
// commit) and machine (host, CPU model), and the date.
nlohmann::json RunContext();

// The oracle of a JSON run record as the tables show it: its name, and its form-factor
// estimate where it reads one, "hanrahan (clamped-cosine)".
std::string OracleLabel(const nlohmann::json &record);

// Prints a JSON run record as an aligned two-column table.
void PrintRunTable(const nlohmann::json &record, std::ostream &out);

// Version of the engine; results of different versions are never mixed.
std::string EngineVersion();

}  // namespace hrbench
