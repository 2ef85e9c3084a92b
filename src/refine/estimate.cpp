#include "refine/estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "hrbench/forest.h"
#include "hrbench/refine.h"
#include "hrbench/scene.h"
#include "hrbench/util/error.h"

namespace hrbench {

namespace {

// The pilots' memory budget: it ends a pilot after a few million links (well under a
// second), so that estimating never costs more than a sliver of a run it lets through.
constexpr size_t kPilotBytes = size_t(16) << 20;
// Bytes per link of a solve's coefficients and arrays, and per element (docs/limits.md).
constexpr double kSolveLinkBytes = 48, kSolveElementBytes = 172;
// Bytes of a pair state of the translation method (translation_count*.cpp), and how
// many copies the growing array holds at once.
constexpr double kStateBytes2d = 24, kStateBytes3d = 16, kStateCopies = 2;

// One pilot refinement: its eps and counts.
struct Pilot {
    double eps, nodes, links;
};

std::string Shown(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
}

// The most elements a recursion limit allows: with --max-depth D each root's tree
// holds at most (a^(D+1) - 1) / (a - 1) elements (a = 2 or 4 children); with
// --min-area A a root of measure m has at most a m / A leaves (an element is split only
// while its measure is at least A), so at most twice as many elements. Infinity without.
double RecursionCap(const Scene &scene, const RefineOptions &options) {
    double arity = SubdivisionArity(options.subdivision);
    double cap = INFINITY;
    if (options.maxDepth >= 0)
        cap =
            double(scene.NumPatches()) * (std::pow(arity, options.maxDepth + 1) - 1) / (arity - 1);
    if (options.minArea > 0) {
        double leaves = std::visit(
            [&](const auto &patches) {
                double sum = 0;
                for (const auto &patch : patches)
                    sum += std::max(1.0, arity * patch.shape.Measure() / options.minArea);
                return sum;
            },
            scene.patches);
        cap = std::min(cap, 2 * leaves);
    }
    return cap;
}

// Bytes per element of the run's trees.
double ElementBytes(const Scene &scene) {
    return scene.Dimension() == 2 ? double(Forest<Segment>::kBytesPerElement)
                                  : double(Forest<Polygon>::kBytesPerElement);
}

// Fills in the memory of _e_ from its elements and links.
void AddBytes(RunEstimate &e, const Scene &scene, const RefineOptions &options,
              const std::string &command) {
    double forests = options.threads == 1 ? 1 : options.threads + 1;
    e.bytes = e.elements * ElementBytes(scene) * (options.storeLinks ? 1 : forests);
    if (options.storeLinks)
        e.bytes += e.links * double(StoredLinkBytes(options));
    if (command == "solve")
        e.bytes += e.links * kSolveLinkBytes + e.elements * kSolveElementBytes;
}

// Scales the last pilot to _options_.eps (see EstimateRun).
RunEstimate Scale(const Scene &scene, const RefineOptions &options, const std::string &command,
                  const Pilot &last, const std::optional<Pilot> &previous) {
    double slopeN = 1, slopeL = 2;  // the laws: N ~ eps^-1, L ~ eps^-2 at fixed geometry
    if (previous && last.nodes > previous->nodes) {
        double step = std::log(previous->eps / last.eps);
        slopeN = std::max(slopeN, std::log(last.nodes / previous->nodes) / step);
        slopeL = std::max(slopeL, std::log(last.links / previous->links) / step);
    }
    double ratio = last.eps / options.eps;
    RunEstimate e;
    e.pilotEps = last.eps;
    e.elements = last.nodes * std::pow(ratio, slopeN);
    e.links = last.links * std::pow(ratio, slopeL);
    double cap = RecursionCap(scene, options);
    if (e.elements > cap) {
        // The limit stops the elements' growth; the links grow as N^2 at most (C4).
        e.links = std::min(e.links, last.links * std::pow(cap / last.nodes, 2));
        e.elements = cap;
    }
    e.basis = "scaled from a refinement at eps " + Shown(last.eps) + " (N ~ eps^-" + Shown(slopeN) +
              ", L ~ eps^-" + Shown(slopeL) + ")";
    AddBytes(e, scene, options, command);
    return e;
}

// A scaled estimate counts as passing the caps only this far below them, since the
// exponents of a pre-asymptotic range may exceed the laws' (2.1 where 2 is the law, for
// parallel l=64 d=1 near eps 1e-3): a run near a cap is scaled from a finer pilot.
constexpr double kMargin = 16;

// Whether _e_ passes the caps with _margin_ to spare.
bool Passes(const RunEstimate &e, const RefineOptions &options, uint64_t maxLinks, double margin) {
    return e.bytes * margin <= double(EffectiveBudget(options)) &&
           (maxLinks == 0 || e.links * margin <= double(maxLinks));
}

// The translation method keeps, per level, the states of the offsets whose pairs the
// oracle rejects: garmann rejects a pair closer than size / eps (2D) or size / sqrt(eps)
// (3D), and the offsets step by half an element, so a level holds at most 4 / eps states
// in 2D, (4 / sqrt(eps))^2 = 16 / eps in 3D.
RunEstimate EstimateTranslation(const Scene &scene, const RefineOptions &options) {
    RunEstimate e;
    const bool flat = scene.Dimension() == 2;
    double states = (flat ? 4 : 16) / options.eps;
    e.bytes = kStateCopies * (flat ? kStateBytes2d : kStateBytes3d) * states;
    e.basis = "its pair states, " + Shown(states) + " on a level at most (" + (flat ? "4" : "16") +
              "/eps)";
    return e;
}

}  // namespace

RunEstimate EstimateRun(const Scene &scene, const RefineOptions &options,
                        const std::string &command, const std::string &method, uint64_t maxLinks) {
    if (method == "translation")
        return EstimateTranslation(scene, options);
    // Start at the coarsest pilot whose scaled links could pass the caps with the margin:
    // a pilot has at least one link per root pair, up to P (P + 1) / 2 of them, and
    // scaling by 4^k in eps multiplies links by 16^k.
    double linkCap = maxLinks ? double(maxLinks) : INFINITY;
    if (options.storeLinks)
        linkCap = std::min(linkCap, double(EffectiveBudget(options)) / StoredLinkBytes(options));
    double pairs = double(scene.NumPatches()) * (scene.NumPatches() + 1) / 2;
    int k =
        std::isfinite(linkCap) && linkCap > kMargin * pairs
            ? std::min(16, int(std::floor(std::log(linkCap / kMargin / pairs) / std::log(16.0))))
            : 0;
    RefineOptions pilot = options;
    pilot.storeLinks = true;  // bounded by its budget; the counts are count-only's
    pilot.memoryBudget = std::min(kPilotBytes, EffectiveBudget(options));
    pilot.progress = nullptr;
    if (double(scene.NumPatches()) * ElementBytes(scene) >= double(pilot.memoryBudget)) {
        // The root elements alone outgrow every pilot (a mesh of millions of patches):
        // no estimate, without trying; the run's own budget still stops it in time.
        RunEstimate e;
        e.basis = "none: the patches' root elements alone outgrow a pilot's " +
                  Shown(double(kPilotBytes) / (1 << 20)) + " MiB";
        return e;
    }
    std::optional<Pilot> last, previous;
    // Go finer while a pilot fits and its scaled estimate fails the caps; where the first
    // pilot outgrows its budget, coarser until one fits (up to eps 4^kMaxCoarser times
    // the first's).
    constexpr int kMaxCoarser = 12;
    const int first = k;
    for (; k >= 0 && k <= first + kMaxCoarser;) {
        pilot.eps = std::ldexp(options.eps, 2 * k);
        Counters c;
        try {
            c = std::visit([](auto &&r) { return r.record.counters; }, Refine(scene, pilot));
        } catch (const LimitError &) {
            if (last || k < first)
                break;  // past the pilot's budget: scale the last one that fitted
            ++k;
            continue;
        } catch (const Error &) {
            // Input the run itself refuses, with its own message (the bf oracle without an
            // emitter, before solve gives the emission): no estimate.
            RunEstimate e;
            e.basis = "none";
            return e;
        }
        previous = last;
        last = Pilot{pilot.eps, double(c.nodes), double(c.links)};
        if (k == 0) {
            RunEstimate e;
            e.exact = true;
            e.pilotEps = options.eps;
            e.elements = last->nodes;
            e.links = last->links;
            e.basis = "counted at eps " + Shown(options.eps);
            AddBytes(e, scene, options, command);
            return e;
        }
        if (k > first ||
            Passes(Scale(scene, options, command, *last, previous), options, maxLinks, kMargin))
            break;  // a coarser pilot than the first fitted: the next finer one did not
        --k;
    }
    if (!last) {
        // Even the coarsest pilot outgrew its budget (a mesh of many patches): no
        // estimate, and no refusal; the run's own budget still stops it in time.
        RunEstimate e;
        e.basis = "none: no pilot fitted in " + Shown(double(kPilotBytes) / (1 << 20)) + " MiB";
        return e;
    }
    return Scale(scene, options, command, *last, previous);
}

void CheckEstimate(const RunEstimate &estimate, const RefineOptions &options,
                   const std::string &method, uint64_t maxLinks) {
    const double budget = double(EffectiveBudget(options));
    const double mib = 1 << 20;
    std::string counts = method == "translation" ? ""
                                                 : Shown(estimate.elements) + " elements, " +
                                                       Shown(estimate.links) + " links, ";
    std::string what = "this run would take about " + counts + Shown(estimate.bytes / mib) +
                       " MiB of memory (estimated: " + estimate.basis + ")";
    if (estimate.bytes > budget)
        throw LimitError(what + ", more than its memory budget of " + Shown(budget / mib) +
                         " MiB (--max-memory MIB raises it, up to the memory free; or raise eps)");
    if (method != "translation" && maxLinks != 0 && estimate.links > double(maxLinks))
        throw LimitError(what + ", more than --max-links " + Shown(double(maxLinks)) +
                         " (--max-links N raises the cap, 0 lifts it; or raise eps)");
}

}  // namespace hrbench
