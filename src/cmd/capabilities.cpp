#include "cmd/capabilities.h"

#include <cmath>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cmd/options.h"
#include "generators.h"
#include "hrbench/count.h"
#include "hrbench/oracles/registry.h"
#include "hrbench/record.h"
#include "hrbench/refine.h"
#include "hrbench/solve.h"

namespace hrbench {

using nlohmann::json;

namespace {

// A range bound, or null when the parameter is unbounded on that side.
json Bound(double value) { return std::isinf(value) ? json(nullptr) : json(value); }

json FamilyJson(const Family &f) {
    json params = json::array();
    for (const ParamSpec &p : f.params)
        params.push_back(
            {{"name", p.name},
             {"default", p.defaultFrom.empty() ? json(p.defaultValue) : json(nullptr)},
             {"default_from", p.defaultFrom.empty() ? json(nullptr) : json(p.defaultFrom)},
             {"low", Bound(p.low)},
             {"high", Bound(p.high)},
             {"low_open", p.lowOpen},
             {"high_open", p.highOpen},
             {"integer", p.integer},
             {"doc", p.help}});
    return {{"name", f.name}, {"dimension", f.dimension}, {"doc", f.help}, {"params", params}};
}

json OracleJson(const OracleInfo &info) {
    json dimensions = json::array();
    for (int d : {2, 3})
        if (info.Supports(d))
            dimensions.push_back(d);
    json parameters = json::array();
    std::istringstream words(info.parameters);
    for (std::string word; words >> word;)
        parameters.push_back(word);
    return {{"name", info.name},
            {"dimensions", dimensions},
            {"parameters", parameters},
            {"doc", info.doc}};
}

// A form-factor estimate: its formulas of F(i<-j), its source, the oracles that read it.
json FfEstimateJson(const FfEstimateInfo &info) {
    return {{"name", info.name},
            {"formula_2d", info.formula2d},
            {"formula_3d", info.formula3d},
            {"source", info.source},
            {"oracles", OraclesReading("ff_estimate")},
            {"default", info.estimate == kDefaultFfEstimate}};
}

json OptionJson(const OptionSpec &o) {
    json excludes = json::array();
    for (const OptionExclusion &x : o.excludes)
        excludes.push_back(x.option);
    return {{"name", o.name},
            {"flag", o.flag},
            {"value", o.value.empty() ? json(nullptr) : json(o.value)},
            {"choices", o.choices.empty() ? json(nullptr) : json(o.choices)},
            {"commands", o.commands},
            {"excludes", excludes},
            {"doc", o.doc}};
}

}  // namespace

json Capabilities() {
    json doc;
    doc["schema_version"] = kCapabilitiesSchemaVersion;
    doc["engine"] = "hrbench";
    doc["version"] = EngineVersion();
    doc["run_schema_version"] = kRunSchemaVersion;
    doc["context"] = RunContext();
    for (const CommandSpec &c : Commands())
        doc["commands"].push_back({{"name", c.name}, {"doc", c.doc}});
    for (const Family &f : Families())
        doc["families"].push_back(FamilyJson(f));
    for (const OracleInfo &info : OracleInfos())
        doc["oracles"].push_back(OracleJson(info));
    for (const FfEstimateInfo &info : FfEstimates())
        doc["ff_estimates"].push_back(FfEstimateJson(info));
    for (const MethodInfo &m : Methods())
        doc["methods"].push_back({{"name", m.name}, {"doc", m.doc}});
    for (const SolveMethodInfo &m : SolveMethods())
        doc["solvers"].push_back({{"name", m.name}, {"doc", m.doc}});
    for (const ClusterBoundInfo &b : ClusterBounds())
        doc["cluster_bounds"].push_back({{"name", b.name}, {"doc", b.doc}});
    for (const ClusterTransferInfo &t : ClusterTransfers())
        doc["cluster_transfers"].push_back({{"name", t.name}, {"doc", t.doc}});
    for (const OptionSpec &o : OptionTable())
        doc["options"].push_back(OptionJson(o));
    for (const CounterInfo &c : CounterTable())
        doc["counters"].push_back({{"name", c.name},
                                   {"kind", c.scalar ? "scalar" : "histogram"},
                                   {"category", c.category},
                                   {"unit", c.unit},
                                   {"doc", c.doc}});
    return doc;
}

}  // namespace hrbench
