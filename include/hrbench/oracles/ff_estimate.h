// The form-factor estimates that the hanrahan and bf oracles choose from
// (`--ff-estimate`; docs/conventions.md#oracles). The formulas are in oracles/hanrahan.h.
#pragma once

#include <string>
#include <vector>

namespace hrbench {

enum class FfEstimate {
    ClampedCosine,  // RenderPark's (rpkCpp formFactorEstimate): f, |cosines| raised to >= 2f
    CentreCosine,   // point-to-disc factor times both centre cosines clamped at 0
    SolidAngle,     // point-to-disc factor with both cosines 1 (Hanrahan & Salzman 1990)
};

// The default: the one estimate whose source says it follows Hanrahan, Salzman & Aupperle
// ("as in Hanrahan SIGGRAPH'91"), though there it drives a threshold on power, not F <= eps.
constexpr FfEstimate kDefaultFfEstimate = FfEstimate::ClampedCosine;

// How an estimate presents itself to the command line, the JSON and the capability listing.
struct FfEstimateInfo {
    FfEstimate estimate;
    const char *name;       // as on the command line and in JSON
    const char *formula2d;  // F(i<-j) in 2D, in the notation of docs/conventions.md
    const char *formula3d;  // F(i<-j) in 3D
    const char *source;     // where it comes from, and what of the source was verified
    const char *doc;        // one line for --help
};

// Every estimate, the default first.
const std::vector<FfEstimateInfo> &FfEstimates();

// The entry of _estimate_.
const FfEstimateInfo &FfEstimateInfoOf(FfEstimate estimate);

// The name of _estimate_ ("clamped-cosine", ...).
std::string FfEstimateName(FfEstimate estimate);

// Parses an estimate's name; throws InputError listing the names.
FfEstimate ParseFfEstimate(const std::string &name);

}  // namespace hrbench
