// Number formatting shared by every writer (JSON, tables, CSV, messages).
#pragma once

#include <string>

namespace hrbench {

// Formats a double with the shortest representation that reads back exactly.
std::string FormatDouble(double value);

}  // namespace hrbench
