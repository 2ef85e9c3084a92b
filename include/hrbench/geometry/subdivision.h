// How an element is split into children: the subdivision rule every shape follows.
#pragma once

#include <string>

namespace hrbench {

enum class Subdivision {
    Binary,    // two halves (the default; docs/conventions.md)
    Quadtree,  // four children (HSA91); polygons only
};

// Name used on the command line and in JSON ("binary", "quadtree").
std::string SubdivisionName(Subdivision mode);

// Parses a subdivision name; throws InputError listing the valid names.
Subdivision ParseSubdivision(const std::string &name);

// Throws InputError unless _mode_ applies to scenes of _dimension_ (segments are only
// halved): the one check of run, solve, check-links and dump-paths.
void CheckSubdivision(Subdivision mode, int dimension);

// Number of children an element gets under _mode_.
constexpr int SubdivisionArity(Subdivision mode) { return mode == Subdivision::Binary ? 2 : 4; }

}  // namespace hrbench
