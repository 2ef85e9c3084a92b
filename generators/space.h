// The 3D scene families (docs/3d.md).
#pragma once

#include <vector>

#include "generators.h"

namespace hrbench {

std::vector<Family> SpaceFamilies();

}  // namespace hrbench
