// The output of a solve: its JSON, the human table and the CSV of its leaves
// (docs/solve.md, The solve command).
#include <algorithm>
#include <cmath>
#include <iomanip>

#include <nlohmann/json.hpp>

#include "hrbench/solve.h"
#include "solve_internal.h"
#include "util/format.h"

namespace hrbench {

using nlohmann::json;

void AddLinkFormFactors(const LinkFormFactors &formFactors, json &record) {
    record["link_form_factor_max"] = formFactors.max;
    record["link_form_factor_above_eps"] = formFactors.aboveEps;
}

json SolveToJson(const Scene &scene, const RefineOptions &refine, const SolveOptions &options,
                 const SolveResult &result) {
    json out = RunToJson(scene, refine, result.record);
    auto optional = [](const std::optional<double> &v) { return v ? json(*v) : json(nullptr); };
    out["solver"] = SolveMethodName(options.method);
    // "consistent": leaves scaled to their exact form factor sums; "plain": HSA91's gather
    // as published, asked for or forced by visibility (ConsistencyScales); "reciprocal":
    // with cluster links, the rows scaled both ways (SolveResult::gather).
    out["gather"] = !result.gather.empty() ? result.gather
                    : options.plainGather || refine.visibility != VisibilityMode::None
                        ? "plain"
                        : "consistent";
    if (result.gather == "reciprocal") {
        out["reciprocal_steps"] = result.reciprocalSteps;
        out["reciprocal_error"] = result.reciprocalError;
    }
    out["tolerance"] = options.tolerance;
    out["max_iterations"] = options.maxIterations;
    out["emission"] = optional(options.emission);
    out["reflectance"] = optional(options.reflectance);
    out["passes"] = result.passes;
    out["pass_links"] = result.passLinks;
    out["pass_nodes"] = result.passNodes;
    out["iterations"] = result.iterations;
    out["residual"] = result.residual;
    out["emitted_power"] = result.emittedPower;
    out["absorbed_power"] = result.absorbedPower;
    out["energy_balance_warning"] =
        result.energyWarning.empty() ? json(nullptr) : json(result.energyWarning);
    AddLinkFormFactors(result.linkFormFactors, out);
    if (result.clusters) {  // the record holds clusters, cluster_nodes and cluster_links
        out["cluster_transfer"] = ClusterTransferName(options.clusterTransfer);
        out["cluster_transfer_share"] = result.clusters->transferShare;
        out["cluster_rays"] = result.clusters->rays;
        out["occluded_cluster_links"] = result.clusters->occludedLinks;
    }
    json radiosity = json::array();
    for (const ElementRadiosity &leaf : result.leaves)
        radiosity.push_back(leaf.radiosity);
    out["radiosity"] = std::move(radiosity);
    auto times = [&](const std::string &stage, const StageTime &t) {
        out["seconds_" + stage] = t.wall;
        out["cpu_seconds_" + stage] = t.cpu;
    };
    times("refine", result.refine);
    times("coefficients", result.coefficients);
    times("solve", result.solve);
    if (result.reference) {
        const UniformSolution &ref = *result.reference;
        json values = json::array();
        for (const ElementRadiosity &e : ref.elements)
            values.push_back(e.radiosity);
        out["reference_depth"] = ref.depth;
        out["reference_radiosity"] = std::move(values);
        out["reference_emitted_power"] = ref.emittedPower;
        out["reference_absorbed_power"] = ref.absorbedPower;
        const ReferenceComparison &c = *result.comparison;
        for (const auto &[name, norms] :
             {std::pair<std::string, const ErrorNorms &>{"reference", c},
              {"projection", c.projection},
              {"hierarchy", c.hierarchy}}) {
            out[name + "_error_max"] = norms.maxError;
            out[name + "_error_mean"] = norms.meanError;
            out[name + "_error_l2"] = norms.l2Error;
        }
        if (ref.change)
            out["reference_change"] = *ref.change;
        times("reference", ref.time);
    }
    return out;
}

void PrintSolveTable(const json &solve, std::ostream &out) {
    double low = INFINITY, high = -INFINITY;
    for (const json &b : solve["radiosity"]) {
        low = std::min(low, b.get<double>());
        high = std::max(high, b.get<double>());
    }
    out << "scene     " << solve["scene"].get<std::string>();
    for (const auto &[key, value] : solve["params"].items())
        out << " " << key << "=" << FormatDouble(value.get<double>());
    out << "\noracle    " << OracleLabel(solve) << "  eps "
        << FormatDouble(solve["eps"].get<double>()) << "  visibility "
        << solve["visibility"].get<std::string>() << "\nsolver    "
        << solve["solver"].get<std::string>() << "  tolerance "
        << FormatDouble(solve["tolerance"].get<double>()) << "  gather "
        << solve["gather"].get<std::string>() << "\n\n";
    auto row = [&](const std::string &name, const std::string &value) {
        out << std::left << std::setw(27) << name << std::right << std::setw(12) << value << "\n";
    };
    for (const char *counter : {"leaves", "links", "passes"})
        row(counter, solve[counter].dump());
    for (const char *list : {"pass_links", "pass_nodes"}) {
        std::string values;
        for (const json &v : solve[list])
            values += (values.empty() ? "" : " ") + v.dump();
        row(list, values);
    }
    row("iterations", solve["iterations"].dump());
    for (const char *value : {"residual", "emitted_power", "absorbed_power"})
        row(value, Short(solve[value].get<double>()));
    row("radiosity_min", Short(low));
    row("radiosity_max", Short(high));
    for (const char *key : {"link_form_factor_max", "link_form_factor_above_eps"})
        row(key, Short(solve[key].get<double>()));
    if (solve.contains("cluster_transfer")) {
        row("cluster_transfer", solve["cluster_transfer"].get<std::string>());
        row("cluster_nodes", solve["cluster_nodes"].dump());
        row("cluster_links", solve["cluster_links"].dump());
        row("cluster_transfer_share", Short(solve["cluster_transfer_share"].get<double>()));
        row("cluster_rays", solve["cluster_rays"].dump());
        row("occluded_cluster_links", solve["occluded_cluster_links"].dump());
    }
    for (const char *stage : {"refine", "coefficients", "solve", "reference"}) {
        std::string key = std::string("seconds_") + stage;
        if (solve.contains(key))
            row(key, Short(solve[key].get<double>()) + " (cpu " +
                         Short(solve["cpu_" + key].get<double>()) + ")");
    }
    if (solve.contains("reference_depth")) {
        row("reference_depth", solve["reference_depth"].dump());
        row("reference_elements", std::to_string(solve["reference_radiosity"].size()));
        for (const char *part : {"reference", "projection", "hierarchy"})
            for (const char *norm : {"max", "mean", "l2"}) {
                std::string key = std::string(part) + "_error_" + norm;
                row(key, Short(solve[key].get<double>()));
            }
        if (solve.contains("reference_change"))
            row("reference_change", Short(solve["reference_change"].get<double>()));
    }
}

namespace {

// The CSV's header: the columns of docs/solve.md.
const char *SolveCsvHeader(int dimension) {
    return dimension == 2
               ? "element,root,depth,position,x,y,measure,radiosity,irradiance,reflectance,"
                 "emission,red,green,blue,x0,y0,x1,y1"
               : "element,root,depth,position,x,y,z,measure,radiosity,irradiance,reflectance,"
                 "emission,red,green,blue,corners,x0,y0,z0,x1,y1,z1,x2,y2,z2,x3,y3,z3";
}

// The leaf's outline: 2D its end points x0,y0,x1,y1; 3D the number of corners and four
// corners' x,y,z, those of a triangle's missing fourth corner empty.
void WriteOutline(const ElementRadiosity &leaf, int dimension, std::ostream &out) {
    if (dimension == 3)
        out << ',' << leaf.numCorners;
    for (int k = 0; k < (dimension == 2 ? 2 : 4); ++k)
        for (int d = 0; d < dimension; ++d) {
            out << ',';
            if (k < leaf.numCorners)
                out << FormatDouble(leaf.corners[size_t(k)][d]);
        }
}

}  // namespace

void WriteSolveCsv(const SolveResult &result, int dimension, std::ostream &out) {
    out << SolveCsvHeader(dimension) << '\n';
    for (const ElementRadiosity &leaf : result.leaves) {
        out << leaf.element << ',' << leaf.root << ',' << leaf.depth << ',' << leaf.position;
        for (int d = 0; d < dimension; ++d)
            out << ',' << FormatDouble(leaf.centroid[d]);
        out << ',' << FormatDouble(leaf.measure) << ',' << FormatDouble(leaf.radiosity) << ','
            << FormatDouble(leaf.irradiance);
        // The colour is for display: the solve used the scalar reflectance.
        const Material &material = result.materials[leaf.root];
        out << ',' << FormatDouble(material.reflectance) << ',' << FormatDouble(material.emission);
        for (double c : material.DisplayColour())
            out << ',' << FormatDouble(c);
        WriteOutline(leaf, dimension, out);
        out << '\n';
    }
}

}  // namespace hrbench
