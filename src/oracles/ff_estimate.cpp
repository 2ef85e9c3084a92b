#include "hrbench/oracles/ff_estimate.h"

#include <stdexcept>

#include "hrbench/util/error.h"
#include "util/named.h"

namespace hrbench {

const std::vector<FfEstimateInfo> &FfEstimates() {
    // cos_i = n_i . (c_j - c_i) / r and cos_j = -n_j . (c_j - c_i) / r, unclamped.
    static const std::vector<FfEstimateInfo> table = {
        {FfEstimate::ClampedCosine, "clamped-cosine",
         "f max(|cos_i|, 2f) max(|cos_j|, 2f), f = A_j / sqrt(4 r^2 + A_j^2)",
         "f max(|cos_i|, 2f) max(|cos_j|, 2f), f = A_j / (pi r^2 + A_j)",
         "RenderPark (Bekaert et al.) as its C++ port has it (OscarChavarro/rpkCpp, "
         "src/raycasting/stochasticRaytracing/hierarchyRefine.cpp, formFactorEstimate, "
         "'Cheap form factor estimate to drive hierarchical refinement as in Hanrahan "
         "SIGGRAPH'91', in floats), read there only by the stochastic Jacobi method's "
         "refinement, which compares a power (receiver area x estimate x reflectance x B) "
         "with a threshold; hrbench uses it under its own threshold F <= eps. RenderPark is "
         "3D only: the 2D form is hrbench's analogue with the flatland f",
         "RenderPark's: the point-to-disc factor f times\nboth |cosines|, each raised to at "
         "least 2f"},
        {FfEstimate::CentreCosine, "centre-cosine",
         "A_j max(0, cos_i) max(0, cos_j) / sqrt(4 r^2 + A_j^2)",
         "A_j max(0, cos_i) max(0, cos_j) / (pi r^2 + A_j)",
         "hrbench's reading of Hanrahan, Salzman & Aupperle (SIGGRAPH 1991): the form factor "
         "from the receiver's centre to a disc (2D: a segment) of the source's area centred "
         "at the source's centre, both cosines at the centres clamped at 0; the body of "
         "that paper's estimate was not verified",
         "the point-to-disc factor times both centre\ncosines clamped at 0 (the only "
         "estimate before 0.5.0)"},
        {FfEstimate::SolidAngle, "solid-angle", "A_j / sqrt(4 r^2 + A_j^2)", "A_j / (pi r^2 + A_j)",
         "Hanrahan & Salzman, A Rapid Hierarchical Radiosity Algorithm for Unoccluded "
         "Environments, Eurographics Workshop on Photosimulation 1990 (Princeton "
         "TR-281-90): the abstract's bound on the maximum solid angle F_eps, expressed in "
         "form-factor units as the point-to-centred-disc factor with both cosines 1, its "
         "largest value; the abstract was verified, the body not",
         "the point-to-disc factor, cosines 1: the\nsubtended solid angle as a form factor"},
    };
    return table;
}

const FfEstimateInfo &FfEstimateInfoOf(FfEstimate estimate) {
    for (const FfEstimateInfo &info : FfEstimates())
        if (info.estimate == estimate)
            return info;
    throw std::logic_error("a form-factor estimate without an entry in FfEstimates()");
}

std::string FfEstimateName(FfEstimate estimate) { return FfEstimateInfoOf(estimate).name; }

FfEstimate ParseFfEstimate(const std::string &name) {
    return FindNamed(FfEstimates(), name, "form-factor estimate").estimate;
}

}  // namespace hrbench
