// A small ProjectKernel of its own, independent of hrbench's engine: two parallel plates
// in flatland, P (0,0)->(l,0) and Q (l,d)->(0,d), refined with the garmann oracle as
// docs/conventions.md states it. It includes only hrbench/probe.h, which counts as
// hrbench counts and writes the link dump that `hrbench check-links` validates:
//
//   tiny_kernel 64 1 0.25 plates.dump
//   hrbench check-links parallel l=64 d=1 --eps 0.25 --links plates.dump
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <hrbench/probe.h>

namespace {

// Every element of both trees, in flat arrays indexed by element; 0 and 1 are the roots.
struct Elements {
    std::vector<double> ax, ay, bx, by;  // the segment a -> b
    std::vector<uint32_t> parent;        // the element itself for a root
    std::vector<uint32_t> firstChild;    // 0 until the element is split
    std::vector<int> depth;

    uint32_t Add(double x0, double y0, double x1, double y1, uint32_t up, int d) {
        ax.push_back(x0), ay.push_back(y0), bx.push_back(x1), by.push_back(y1);
        uint32_t id = uint32_t(parent.size());
        parent.push_back(up == UINT32_MAX ? id : up);
        firstChild.push_back(0);
        depth.push_back(d);
        return id;
    }
    // A^2 = dx*dx + dy*dy, in that order: the size that picks the element to split.
    double SizeSquared(uint32_t e) const {
        double dx = bx[e] - ax[e], dy = by[e] - ay[e];
        return dx * dx + dy * dy;
    }
    double MidX(uint32_t e) const { return 0.5 * (ax[e] + bx[e]); }
    double MidY(uint32_t e) const { return 0.5 * (ay[e] + by[e]); }
};

class TinyKernel {
  public:
    TinyKernel(double l, double d, double eps, hrbench::probe::Probe &probe)
        : eps_(eps), probe_(probe) {
        e_.Add(0, 0, l, 0, UINT32_MAX, 0);  // P, facing +y
        e_.Add(l, d, 0, d, UINT32_MAX, 0);  // Q, facing -y
        probe_.ElementCreated(0);
        probe_.ElementCreated(0);
    }

    void Run() { Project(0, 1); }

  private:
    // garmann: max(A_i, A_j) <= eps * r, r the distance of the midpoints, equality
    // accepted; max(A_i, A_j) taken as the root of the larger A^2.
    bool Acceptable(uint32_t i, uint32_t j) const {
        double s = std::max(e_.SizeSquared(i), e_.SizeSquared(j));
        double dx = e_.MidX(i) - e_.MidX(j), dy = e_.MidY(i) - e_.MidY(j);
        return std::sqrt(s) <= eps_ * std::sqrt(dx * dx + dy * dy);
    }

    // The first child of _e_, halving it at its midpoint the first time.
    uint32_t Children(uint32_t e) {
        if (e_.firstChild[e] == 0) {
            double mx = e_.MidX(e), my = e_.MidY(e);
            double ax = e_.ax[e], ay = e_.ay[e], bx = e_.bx[e], by = e_.by[e];
            int d = e_.depth[e] + 1;
            e_.firstChild[e] = e_.Add(ax, ay, mx, my, e, d);
            e_.Add(mx, my, bx, by, e, d);
            probe_.ElementCreated(d);
            probe_.ElementCreated(d);
        }
        return e_.firstChild[e];
    }

    // The element's name for the dump: its root and its child indices from the root.
    hrbench::probe::ElementPath PathOf(uint32_t e) const {
        std::string digits;
        for (; e_.parent[e] != e; e = e_.parent[e])
            digits.insert(digits.begin(), char('0' + (e - e_.firstChild[e_.parent[e]])));
        return {e, digits};  // e is now the root, whose id is its index in scene order
    }

    void Project(uint32_t i, uint32_t j) {
        probe_.OracleCall();
        if (Acceptable(i, j))
            return probe_.Link(PathOf(i), PathOf(j));
        bool splitI = e_.SizeSquared(i) >= e_.SizeSquared(j);  // the larger; ties the first
        if (e_.depth[splitI ? i : j] >= 48) {
            std::fprintf(stderr, "tiny_kernel: the recursion reached depth 48\n");
            std::exit(3);
        }
        uint32_t child = Children(splitI ? i : j);
        for (uint32_t c = child; c < child + 2; ++c)
            splitI ? Project(c, j) : Project(i, c);
    }

    Elements e_;
    double eps_;
    hrbench::probe::Probe &probe_;
};

bool Positive(const char *text, double &value) {
    char *end = nullptr;
    value = std::strtod(text, &end);
    return *text && !*end && std::isfinite(value) && value > 0;
}

}  // namespace

int main(int argc, char **argv) {
    double l, d, eps;
    if (argc != 5 || !Positive(argv[1], l) || !Positive(argv[2], d) || !Positive(argv[3], eps)) {
        std::fprintf(stderr, "usage: tiny_kernel L D EPS DUMP (L, D, EPS numbers > 0)\n");
        return 2;
    }
    std::ofstream dump(argv[4]);
    if (!dump) {
        std::fprintf(stderr, "tiny_kernel: cannot write %s\n", argv[4]);
        return 2;
    }
    hrbench::probe::Probe probe(&dump);
    TinyKernel(l, d, eps, probe).Run();
    probe.Finish();
    dump.close();
    if (!dump) {
        std::fprintf(stderr, "tiny_kernel: cannot write %s\n", argv[4]);
        return 2;
    }
    const hrbench::probe::Counters &c = probe.Counts();
    std::printf("links %llu\noracle_calls %llu\nnodes %llu\nmax_depth %llu\n",
                (unsigned long long)c.links, (unsigned long long)c.oracleCalls,
                (unsigned long long)c.nodes, (unsigned long long)c.maxDepth);
    return 0;
}
