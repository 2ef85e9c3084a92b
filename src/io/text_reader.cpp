// How the words of a file are shown in messages.
#include "text_reader.h"

#include <cstdio>

namespace hrbench::meshio {

// _word_ for a message: at most 40 bytes, every byte outside printable ASCII escaped, so
// that a message stays one short line whatever the file holds.
std::string Shown(std::string_view word) {
    constexpr size_t kMaxShown = 40;
    std::string out;
    for (unsigned char c : word.substr(0, kMaxShown)) {
        if (c >= 0x20 && c < 0x7f) {
            out += char(c);
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", unsigned(c));
            out += hex;
        }
    }
    return word.size() > kMaxShown ? out + "..." : out;
}

std::string Quoted(std::string_view word) { return "'" + Shown(word) + "'"; }

// _value_ with 3 significant digits, for measures in messages.
std::string ThreeDigits(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
}

}  // namespace hrbench::meshio
