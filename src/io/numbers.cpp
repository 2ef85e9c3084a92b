// Numbers, counts, colours and points of mesh and material files.
#include "numbers.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include "util/format.h"

namespace hrbench::meshio {

bool AllDigits(std::string_view word) {
    return !word.empty() &&
           std::all_of(word.begin(), word.end(), [](unsigned char c) { return std::isdigit(c); });
}

// Parses _word_ as a number into _value_; returns "" or why it is not a finite number.
// As everywhere in hrbench (util/args.h), a number beyond the doubles overflows and one
// that would lose precision as a subnormal (or 0) underflows.
std::string NumberProblem(std::string_view word, double &value) {
    std::string_view text = word;
    if (text.size() > 1 && text[0] == '+' && text[1] != '+' && text[1] != '-')
        text.remove_prefix(1);  // files and strtod take a leading '+', from_chars does not
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec == std::errc::invalid_argument || end != text.data() + text.size())
        return "is not a number";
    const char *overflows = "overflows double precision (largest 1.8e308)";
    const char *underflows = "underflows double precision (smallest normal 2.2e-308)";
    if (ec == std::errc::result_out_of_range) {
        // from_chars reports underflow and overflow alike; strtod tells them apart.
        return std::isinf(std::strtod(std::string(text).c_str(), nullptr)) ? overflows : underflows;
    }
    if (!std::isfinite(value))
        return "is not finite";
    return value == 0 || std::isnormal(value) ? "" : underflows;
}

// Reads _word_ as a finite number, or fails at the current line of _lines_ saying what
// (_what_) is wrong: "coordinate '1e400' overflows".
double Finite(const Lines &lines, std::string_view word, const std::string &what) {
    double value = 0;
    std::string problem = NumberProblem(word, value);
    if (!problem.empty())
        lines.Fail(what + " " + Quoted(word) + " " + problem);
    return value;
}

// Reads _word_ as a non-negative integer written in digits, or fails saying why not.
bool ParseCount(std::string_view word, uint64_t &value) {
    return AllDigits(word) &&
           std::from_chars(word.data(), word.data() + word.size(), value).ec == std::errc();
}

uint64_t Count(const Lines &lines, std::string_view word, const std::string &what) {
    uint64_t value = 0;
    if (ParseCount(word, value))
        return value;
    if (AllDigits(word))
        lines.Fail(what + " " + Quoted(word) + " is too large");
    double number = 0;
    std::string problem = NumberProblem(word, number);
    if (problem.empty())
        problem = number < 0 ? "is negative" : "is not an integer";
    lines.Fail(what + " " + Quoted(word) + " " + problem);
}

Colour ReadColour(const Lines &lines, Words &words, size_t count, const std::string &what) {
    std::array<std::string_view, 4> components;
    bool integers = true;
    for (size_t k = 0; k < count; ++k) {
        words.Next(components[k]);
        integers = integers && AllDigits(components[k]);
    }
    Rgb rgb{};
    double sum = 0;
    for (size_t k = 0; k < count; ++k) {
        std::string_view word = components[k];
        double value = 0;
        if (integers) {
            uint64_t byte = 256;
            std::from_chars(word.data(), word.data() + word.size(), byte);
            if (byte > 255)
                lines.Fail(what + " " + Quoted(word) + " is outside 0..255");
            value = double(byte);
        } else {
            value = Finite(lines, word, what);
            if (!(value >= 0 && value <= 1))
                lines.Fail(what + " " + Quoted(word) +
                           " is outside [0, 1] (a colour written with fractions is read in 0..1)");
        }
        if (k < 3) {  // the alpha is checked, not used
            rgb[k] = integers ? value / 255 : value;
            sum += value;
        }
    }
    return {rgb, integers ? sum / (3 * 255.0) : sum / 3};
}

// Reads the coordinates x y z of a vertex, each multiplied by _scale_.
Vec3 ReadPoint(const Lines &lines, Words &words, double scale) {
    std::array<double, 3> xyz;
    std::string_view word;
    for (double &c : xyz) {
        words.Next(word);
        c = Finite(lines, word, "coordinate") * scale;
        if (scale != 1 && (!std::isfinite(c) || (c != 0 && !std::isnormal(c))))
            lines.Fail("coordinate " + Quoted(word) + " times the scale " + FormatDouble(scale) +
                       (std::isfinite(c) ? " underflows double precision (smallest normal 2.2e-308)"
                                         : " overflows double precision (largest 1.8e308)"));
    }
    return Vec3(xyz[0], xyz[1], xyz[2]);
}
}  // namespace hrbench::meshio
