// A scene: the ordered list of root patches that refinement starts from.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "polygon.h"
#include "util/args.h"

namespace hrbench {

using Vec2 = Eigen::Vector2d;

// Surface properties of a root patch, inherited by all of its elements.
struct Material {
    double reflectance = 0.5;  // rho, in [0, 1)
    double emission = 0.0;     // emitted radiosity E, >= 0
};

// An oriented flatland patch from _a_ to _b_; its front side is on the left
// (the direction rotated by +90 degrees), as DESIGN section 2 defines.
struct Segment {
    Vec2 a, b;
    Material material;

    double Length() const { return (b - a).norm(); }
    Vec2 Midpoint() const { return 0.5 * (a + b); }
    // Unit normal on the front (left) side.
    Vec2 Normal() const {
        Vec2 dir = (b - a).normalized();
        return Vec2(-dir.y(), dir.x());
    }
};

// A 3D patch: a planar convex triangle or quad, counter-clockwise seen from its
// front (DESIGN section 2), with its surface properties.
struct Face {
    Polygon polygon;
    Material material;
};

// Scene with its provenance (family and parameters) so that results explain themselves.
struct Scene {
    int dimension = 2;
    std::string family;       // generator family, or "file" for a loaded scene
    ParamMap params;          // parameters after defaults
    std::vector<Segment> segments;  // 2D root patches in scene order
    std::vector<Face> faces;        // 3D root patches in scene order

    size_t NumPatches() const { return dimension == 3 ? faces.size() : segments.size(); }
};

// Checks what refinement relies on: at least one patch, finite coordinates,
// non-degenerate segments, planar convex non-degenerate polygons, materials in range.
// Throws InputError naming the patch.
void ValidateScene(const Scene &scene);

}  // namespace hrbench
