// The 2D (flatland) scene families.
#pragma once

#include <vector>

#include "generators.h"

namespace hrbench {

std::vector<Family> FlatlandFamilies();

}  // namespace hrbench
