// The estimate made before a refinement (refine/estimate.h; docs/limits.md#estimates).
#include <catch2/catch.hpp>

#include "generators.h"
#include "hrbench/hrbench.h"
#include "refine/estimate.h"

using namespace hrbench;

TEST_CASE("A scene whose root elements outgrow a pilot is estimated without a pilot",
          "[estimate]") {
    // 8 * 230^2 = 423,200 triangles: their root elements alone take more than a pilot's
    // 16 MiB, so every pilot would fail after building them; none is tried.
    Scene scene = MakeScene("sphere", {{"n", 230}});
    RefineOptions o;
    o.eps = 0.5, o.minArea = 1e-6, o.clusters = true;
    RunEstimate e = EstimateRun(scene, o, "run", "enumerate", 100000000000ull);
    CHECK_THAT(e.basis, Catch::StartsWith("none: the patches' root elements alone outgrow"));
    CHECK(e.pilotEps == 0);
    CHECK(!e.exact);
    // A scene of few patches is estimated from a pilot.
    RunEstimate small =
        EstimateRun(MakeScene("sphere", {{"n", 4}}), o, "run", "enumerate", 100000000000ull);
    CHECK(small.pilotEps > 0);
    CHECK_THAT(small.basis, !Catch::StartsWith("none"));
}
