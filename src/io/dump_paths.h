// Link dumps whose elements are named by their corners, converted to hrbench's element
// paths (docs/dump-paths.md): for kernels that do not follow hrbench's child order.
#pragma once

#include <istream>
#include <ostream>
#include <string>

#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

// The default matching tolerance: a corner matches within this fraction of the diameter
// of its root patch (room for a kernel computing in float, 2^-24 = 6e-8 relative).
constexpr double kDefaultPathTolerance = 1e-5;

// Copies the link dump read from _in_ (named _source_ in messages) to _out_, replacing
// every element token named by corners (`@x,y;x,y` in 2D, `@x,y,z;x,y,z;x,y,z[;x,y,z]`
// in 3D, optionally after its root index `R@...` and after `KEY=`) by the path of the
// element of _scene_'s subdivision tree under _subdivision_ with those corners (in any
// cyclic order and either orientation), each within _tolerance_ times the diameter of
// the root patch. Every other word and line is copied unchanged; comment lines are not
// read. Throws InputError "SOURCE:LINE: ..." for a token that is malformed or matches no
// element, or more than one.
void ConvertDumpPaths(const Scene &scene, Subdivision subdivision, double tolerance,
                      std::istream &in, const std::string &source, std::ostream &out);

}  // namespace hrbench
