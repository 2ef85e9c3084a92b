// Form factors between two elements, ignoring occlusion: the fraction of the energy that
// leaves _from_ (diffusely, from its front side) and arrives at _to_ (on its front side).
// Reciprocity: Measure(from) * F(from, to) = Measure(to) * F(to, from).
#pragma once

#include "hrbench/geometry/polygon.h"
#include "hrbench/geometry/segment.h"

namespace hrbench {

// Flatland, exact: Hottel's crossed-strings rule, F = (crossed - uncrossed) / (2 L_from),
// applied to the parts of each segment in front of the other's line (the parts behind
// it exchange nothing). 0 for collinear segments or segments facing away.
double FormFactor(const Segment &from, const Segment &to);

// 3D: the closed form of a differential area to a polygon (Lambert's contour formula),
// integrated over _from_ by an adaptive tensor Gauss-Legendre rule (docs/solve.md states
// it), to a relative accuracy of about 1e-10 for separated polygons and better than
// 2e-8 (measured) for polygons sharing an edge or a corner. 0 where the polygons face
// away or are coplanar.
double FormFactor(const Polygon &from, const Polygon &to);

// The form factor from a differential area at _point_ with unit normal _normal_ to the
// front of _polygon_, by Lambert's formula; the part of the polygon behind the point's
// tangent plane is clipped away first. 0 unless the point is strictly in front of the
// polygon's plane.
double PointToPolygonFormFactor(const Vec3 &point, const Vec3 &normal, const Polygon &polygon);

}  // namespace hrbench
