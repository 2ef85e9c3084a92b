#include "hrbench/check_links.h"

#include <memory>
#include <optional>
#include <string>

#include "check_links/checker.h"
#include "check_links/internal.h"
#include "cluster/cluster_oracles.h"

namespace hrbench {

namespace {

// The checks of a dump of _Shape_ elements, with the oracle of the run.
template <typename Shape>
LinkCheck CheckShape(const Scene &scene, const RefineOptions &options, const LinkConventions &conv,
                     const LinkDump &dump, Violations &violations) {
    const Patches<Shape> &patches = scene.Get<Shape>();
    LinkCheck check;
    // oracle=own judges nothing: any oracle type will do, garmann's costs nothing to make.
    const std::string name = conv.ownOracle ? "garmann" : options.oracle;
    AllOracles::ForEach([&](auto tag) {
        using Oracle = typename decltype(tag)::template Type<Shape>;
        if constexpr (Oracle::kInfo.Supports(Shape::kDimension)) {
            if (name == Oracle::kInfo.name) {
                if constexpr (!ClusterForm<Oracle>::kExists)
                    if (options.clusters && !conv.ownOracle)
                        throw InputError("--clusters: the oracle " + std::string(name) +
                                         " has no cluster form");
                RefineOptions at = options;
                if (conv.ownOracle)
                    at.oracle = name;
                Oracle oracle = MakeOracle<Oracle>(at, patches);
                std::optional<Oracle> below;
                if (conv.acceptLt && !conv.ownOracle) {
                    RefineOptions lower = at;
                    lower.eps = std::nextafter(at.eps, 0.0);
                    below.emplace(MakeOracle<Oracle>(lower, patches));
                }
                check = Checker<Shape, Oracle>(patches, oracle, below ? &*below : nullptr, at, conv,
                                               dump, violations)
                            .Run();
            }
        }
    });
    return check;
}

}  // namespace

LinkCheck CheckLinks(const Scene &scene, const RefineOptions &given, const LinkDump &dump,
                     const CheckLinksOptions &extra) {
    if (given.visibility != VisibilityMode::None)
        throw InputError("check-links checks refinement without visibility: the links of a "
                         "root pair tile it only when no pair is occluded");
    if (!given.clusters && !dump.clusterLinks.empty()) {
        const DumpClusterLink &l = dump.clusterLinks.front();
        throw InputError(dump.name + ":" + std::to_string(l.line) + ": " + LinkDump::NodeName(l.a) +
                         " " + LinkDump::NodeName(l.b) +
                         " is a cluster link: add --clusters to check a clustered refinement");
    }
    RefineOptions options = given;
    const LinkConventions conv = ResolveConventions(dump, extra, options);
    if (options.clusters && conv.directed)
        throw InputError("--clusters checks undirected links: a cluster link stands for both "
                         "directions, and links=directed has one per direction");
    RefineOptions counting = options;
    counting.storeLinks = false;
    counting.threads = 1;
    // Reflectance is read by no oracle: check-links takes any (docs/probe.md).
    ValidateScene(scene, false);
    ValidateOptions(counting, scene.Dimension());
    const Scene &checked = scene;
    Violations violations(dump.name, extra.every);
    // A version 1 dump is read ordered and has no unlinks: checked as it is, uncopied.
    std::optional<LinkDump> copy;
    if (dump.version >= 2)
        copy = Resolve(dump, conv, violations);
    const LinkDump &resolved = copy ? *copy : dump;
    // The dump first: that check's work and memory grow with the dump (Checker::Run). A
    // dump that passes it is ProjectKernel's refinement link for link, so hrbench's own
    // refinement, run after it, makes as many links as the dump holds: a tiny dump
    // before a refinement too large to finish fails quickly instead of waiting on it.
    LinkCheck check = checked.Dimension() == 2
                          ? CheckShape<Segment>(checked, options, conv, resolved, violations)
                          : CheckShape<Polygon>(checked, options, conv, resolved, violations);
    check.conventions = conv;
    check.oracle = conv.ownOracle ? "own" : options.oracle;
    check.treeComplete = violations.Total() == 0;
    check.oracleCallsFromRecord = !resolved.decisions.empty();
    check.fromLinks.links = resolved.links.size() + resolved.clusterLinks.size();
    if (check.clusters) {
        check.fromLinks.elementLinks = resolved.links.size();
        check.fromLinks.clusterLinks = resolved.clusterLinks.size();
    }
    CountInitialLinking(check.fromLinks);
    // Named pairs, not structured bindings: C++17 lambdas cannot capture those.
    for (const auto &counter : dump.counters) {
        const std::string &key = counter.first;
        uint64_t value = counter.second;
        std::optional<uint64_t> record = FromRecord(check, key);
        if (record && *record != value)
            violations.Add("counter-mismatch", dump.countersLine, false, 0, 0, [&] {
                return "the counters line says " + key + "=" + std::to_string(value) +
                       (resolved.decisions.empty() ? ", the links give " : ", the record gives ") +
                       std::to_string(*record);
            });
    }
    check.engineCompared = violations.Total() == 0 && conv.IsHrbench() && check.passes == 1;
    if (check.engineCompared) {
        // Refine() validates every material: hand it the scene with the reflectance
        // that no count reads put in range.
        Scene inRange = scene;
        std::visit(
            [](auto &patches) {
                for (auto &patch : patches)
                    if (!(patch.material.reflectance >= 0 && patch.material.reflectance < 1))
                        patch.material.reflectance = 0;
            },
            inRange.patches);
        check.engine = std::visit([&](auto &&r) { return std::move(r.record.counters); },
                                  Refine(inRange, counting));
        for (const auto &compared : ComparedCounters(check.clusters)) {
            const std::string &name = compared.first;
            uint64_t Counters::*field = compared.second;
            if (check.engine.*field != check.fromLinks.*field &&
                FromRecord(check, name).has_value())
                violations.Add("counter-mismatch", 0, false, 0, 0, [&] {
                    return "the links give " + name + " " + std::to_string(check.fromLinks.*field) +
                           ", hrbench's refinement " + std::to_string(check.engine.*field);
                });
        }
    }
    if (violations.Total()) {
        auto summary = std::make_shared<LinkSummary>(violations.Take());
        std::string message = summary->firstMessage;
        if (summary->total > 1)
            message += " (the first of " + std::to_string(summary->total) +
                       " violations; --summary or --json lists them, --all every one)";
        throw LinkViolation(message, summary, std::make_shared<LinkCheck>(check));
    }
    return check;
}

}  // namespace hrbench
