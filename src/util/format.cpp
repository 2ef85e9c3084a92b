#include "util/format.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace hrbench {

std::string FormatDouble(double value) {
    char buffer[32];
    if (std::isfinite(value)) {
        // The same text as the printf loop below (to_chars with a precision is specified
        // as %.*g), several times faster: writing a mesh formats millions of coordinates.
        for (int precision = 6; precision <= 17; ++precision) {
            auto end = std::to_chars(buffer, buffer + sizeof buffer, value,
                                     std::chars_format::general, precision)
                           .ptr;
            double back = 0;
            std::from_chars(buffer, end, back);
            if (back == value || precision == 17)
                return std::string(buffer, end);
        }
    }
    for (int precision = 6; precision <= 17; ++precision) {
        std::snprintf(buffer, sizeof buffer, "%.*g", precision, value);
        if (std::strtod(buffer, nullptr) == value)
            break;
    }
    return buffer;
}

std::string JoinedNames(const std::vector<std::string> &names) {
    std::string text;
    for (size_t k = 0; k < names.size(); ++k)
        text += (k == 0 ? "" : k + 1 == names.size() ? " and " : ", ") + names[k];
    return text;
}

}  // namespace hrbench
