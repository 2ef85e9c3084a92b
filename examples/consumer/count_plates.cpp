// Refines two parallel plates with the engine of an installed hrbench and prints the
// counters, as the CLI's `hrbench run parallel l=64 d=1 --eps 0.25` would.
#include <cstdio>

#include <generators.h>
#include <hrbench/hrbench.h>

int main() {
    hrbench::Scene scene = hrbench::MakeScene("parallel", {{"l", 64.0}, {"d", 1.0}});
    hrbench::RefineOptions options;
    options.oracle = "garmann";
    options.eps = 0.25;
    const hrbench::Counters c = hrbench::Refine<hrbench::Segment>(scene, options).record.counters;
    std::printf("nodes %llu\nlinks %llu\noracle_calls %llu\n", (unsigned long long)c.nodes,
                (unsigned long long)c.links, (unsigned long long)c.oracleCalls);
    return 0;
}
