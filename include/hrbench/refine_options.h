// The options of one refinement run, as plain typed values (the CLI parses strings).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "hrbench/geometry/subdivision.h"
#include "hrbench/oracles/ff_estimate.h"

namespace hrbench {

struct RefineProgress;  // refine.h
struct Scene;           // scene.h
struct Segment;         // geometry/segment.h
struct Polygon;         // geometry/polygon.h
template <typename Shape>
class RadiosityEstimate;  // radiosity_estimate.h

// The radiosity estimate of a run, or none (std::monostate): one field for either shape;
// the oracle refuses an estimate of the other shape than the scene's.
using AnyEstimate = std::variant<std::monostate, const RadiosityEstimate<Segment> *,
                                 const RadiosityEstimate<Polygon> *>;

// What a link above the input patches may join under --clusters (`--cluster-bound`;
// docs/conventions.md#clusters): which node pairs the cluster oracle bounds.
enum class ClusterBound {
    Cluster,  // any two nodes, the transfer bounded from both ends' balls and measures
    Patch,    // a patch and a node: one end of every such link is an input patch
};

struct ClusterBoundInfo {
    const char *name;  // "cluster" or "patch"
    const char *doc;   // one line
    ClusterBound bound;
};

// Every cluster bound, the default first: the CLI's choices and capabilities read it.
const std::vector<ClusterBoundInfo> &ClusterBounds();

// The bound named _name_; throws InputError listing the names.
ClusterBound ParseClusterBound(const std::string &name);
std::string ClusterBoundName(ClusterBound bound);

// How refinement treats occlusion (`--visibility`; docs/3d.md).
enum class VisibilityMode {
    None,      // ignore occlusion (the setting of the papers; the default)
    Fraction,  // weight the oracle's error by the visible fraction V of the pair
    Refine,    // refine every partially visible pair down to the recursion limit
};

// Name used on the command line and in JSON ("none", "fraction", "refine").
std::string VisibilityName(VisibilityMode mode);

// Parses a visibility mode; throws InputError listing the valid names.
VisibilityMode ParseVisibility(const std::string &name);

// Depth beyond which no element is split without a user limit: deeper elements lose
// their midpoints to double rounding, and a pair that gets there would not terminate
// on its own (touching patches). Reaching it is an error.
constexpr int kSafetyDepth = 48;

// Throws the LimitError of a rejected pair of the trees of root patches _p_ and _q_
// whose preferred element has reached kSafetyDepth without a user limit.
[[noreturn]] void ThrowSafetyDepth(uint64_t p, uint64_t q);

struct RefineOptions {
    std::string oracle = "garmann";  // a name of the oracle registry (oracles/registry.h)
    double eps = 0;                  // oracle threshold, > 0
    double minArea = 0;              // link a pair whose preferred element is smaller; 0 = off
    int maxDepth = -1;               // link a pair whose preferred element has this depth; -1 = off
    bool storeLinks = false;         // keep every link (store mode) or only count (count-only)
    size_t memoryBudget = 0;         // bytes for elements and links; 0 = what the machine has free
    int threads = 1;                 // worker threads; counts never depend on it
    Subdivision subdivision = Subdivision::Binary;     // 3D: two halves or four quarters
    VisibilityMode visibility = VisibilityMode::None;  // how occlusion counts (docs/3d.md)
    int raysPerSide = 3;  // k: sample points per element side for visibility, 1..16
    // The form-factor estimate of the oracles that read one (hanrahan, bf); the others
    // ignore it (`--ff-estimate`, oracles/ff_estimate.h).
    FfEstimate ffEstimate = kDefaultFfEstimate;
    // Refine through the cluster hierarchy (clusters.h) instead of every root pair.
    bool clusters = false;
    ClusterBound clusterBound = ClusterBound::Cluster;  // with clusters: which pairs link
    // Where the run reports its progress (refine.h), if anywhere: not a setting of the run.
    RefineProgress *progress = nullptr;
    // The radiosity the bf oracle reads, not owned: not a setting of the run either.
    // None: the emission of the root patches (the first pass of refine-solve-refine).
    AnyEstimate estimate;

    bool HasRecursionLimit() const { return minArea > 0 || maxDepth >= 0; }
};

// Throws InputError naming the option when _options_ are out of range or do not apply
// to a scene of dimension _dimension_ (2 or 3).
void ValidateOptions(const RefineOptions &options, int dimension);

// Below this fraction of the largest root patch's measure, --min-area draws a warning.
constexpr double kMinAreaWarnFraction = 1e-8;

// A warning (one line, "" for none) when the scene's size and --min-area disagree by
// orders of magnitude, as when a scene is in other units than intended: --min-area
// larger than the largest root patch's measure (length in 2D, area in 3D), so that no
// element is ever split, or below kMinAreaWarnFraction of it, so that elements may be
// halved some 27 times or more before it applies.
std::string MinAreaWarning(const Scene &scene, const RefineOptions &options);

// The memory budget of a run in bytes: the option, or 90% of the free memory.
size_t EffectiveBudget(const RefineOptions &options);

// Bytes a stored link takes: its two element ids, and with visibility (anything but
// --visibility none) its visible fraction (Refinement::visible).
size_t StoredLinkBytes(const RefineOptions &options);

// Free memory reported by the operating system (MemAvailable), in bytes.
size_t AvailableMemoryBytes();

}  // namespace hrbench
