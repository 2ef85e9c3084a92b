#include "hrbench/links_csv.h"

#include <cmath>

#include "util/format.h"

namespace hrbench {

namespace {

void WriteHeader(const Forest<Segment> &, std::ostream &out) {
    out << "root_i,elem_i,t0_i,t1_i,depth_i,root_j,elem_j,t0_j,t1_j,depth_j\n";
}

void WriteHeader(const Forest<Polygon> &, std::ostream &out) {
    out << "root_i,elem_i,area_i,cx_i,cy_i,cz_i,depth_i,root_j,elem_j,area_j,cx_j,cy_j,cz_j,"
           "depth_j\n";
}

// The interval of a segment element along its root, exact for dyadic positions.
void WriteGeometry(const Forest<Segment> &forest, uint32_t e, std::ostream &out) {
    double rootLength = forest[forest[e].root].Size();
    double position = double(forest.Position(e));
    int depth = forest.Depth(e);
    out << FormatDouble(rootLength * std::ldexp(position, -depth)) << ","
        << FormatDouble(rootLength * std::ldexp(position + 1, -depth));
}

void WriteGeometry(const Forest<Polygon> &forest, uint32_t e, std::ostream &out) {
    const Vec3 &c = forest[e].center;
    out << FormatDouble(forest[e].Size()) << "," << FormatDouble(c.x()) << ","
        << FormatDouble(c.y()) << "," << FormatDouble(c.z());
}

}  // namespace

void WriteLinksCsv(const AnyRefinement &refinement, std::ostream &out) {
    std::visit(
        [&](const auto &r) {
            WriteHeader(r.forest, out);
            for (const Link &link : r.links) {
                for (uint32_t e : {link.i, link.j}) {
                    out << r.forest[e].root << "," << e << ",";
                    WriteGeometry(r.forest, e, out);
                    out << "," << r.forest.Depth(e) << (e == link.i ? "," : "\n");
                }
            }
            // Cluster links (--clusters) after them: a cluster end is C<index> with its
            // other columns empty, a patch end its root element.
            const size_t emptyColumns = r.forest[0].center.size() == 2 ? 4 : 6;
            for (const ClusterLink &link : r.clusterLinks) {
                for (uint32_t node : {link.a, link.b}) {
                    if (IsCluster(node)) {
                        out << "C" << ClusterIndex(node) << std::string(emptyColumns, ',');
                    } else {
                        out << node << "," << node << ",";
                        WriteGeometry(r.forest, node, out);
                        out << ",0";
                    }
                    out << (node == link.a ? "," : "\n");
                }
            }
        },
        refinement);
}

}  // namespace hrbench
