// Number and list formatting shared by every writer (JSON, tables, CSV, messages).
#pragma once

#include <string>
#include <vector>

namespace hrbench {

// Formats a double with the shortest representation that reads back exactly.
std::string FormatDouble(double value);

// "a, b and c", for messages.
std::string JoinedNames(const std::vector<std::string> &names);

}  // namespace hrbench
