// Numbers, counts, colours and points in the words of a mesh or material file; each
// fails at the current line of its Lines with a one-line message.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "hrbench/scene.h"
#include "text_reader.h"

namespace hrbench::meshio {

// Whether _word_ is one or more decimal digits and nothing else.
bool AllDigits(std::string_view word);

// Parses _word_ as a number into _value_; returns "" or why it is not a finite number.
// As everywhere in hrbench (util/args.h), a number beyond the doubles overflows and one
// that would lose precision as a subnormal (or 0) underflows.
std::string NumberProblem(std::string_view word, double &value);

// Reads _word_ as a finite number, or fails at the current line of _lines_ saying what
// (_what_) is wrong: "coordinate '1e400' overflows".
double Finite(const Lines &lines, std::string_view word, const std::string &what);

// Reads _word_ into _value_ when it is a non-negative integer written in digits that fits
// 64 bits: the common case, checked without making a message.
bool ParseCount(std::string_view word, uint64_t &value);

// Reads _word_ as a non-negative integer written in digits, or fails saying why not.
uint64_t Count(const Lines &lines, std::string_view word, const std::string &what);

// Reads the _count_ (3 or 4) components r g b [a] of a colour: integers in 0..255, or,
// when any is written otherwise (0.5, 1e-1), numbers in [0, 1]. Returns r, g, b and their
// mean, scaled to [0, 1].
struct Colour {
    Rgb rgb;
    double mean;
};
Colour ReadColour(const Lines &lines, Words &words, size_t count, const std::string &what);

// Reads the coordinates x y z of a vertex, each multiplied by _scale_.
Vec3 ReadPoint(const Lines &lines, Words &words, double scale);

}  // namespace hrbench::meshio
