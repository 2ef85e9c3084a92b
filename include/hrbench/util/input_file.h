// Reading an input file whole, within a size limit checked before and while reading, so
// that no input (a device such as /dev/zero, a huge or growing file) can read forever or
// exhaust memory.
#pragma once

#include <cstddef>
#include <string>

namespace hrbench {

// Default limit on the size of one input file (scene, mesh, material library): 256 MiB.
// Overridden by `--max-input MIB`.
constexpr size_t kDefaultMaxInputBytes = size_t(256) << 20;

// Returns the contents of the file at _path_. _what_ names it in messages ("scene file").
// Throws InputError with one line when the path does not exist, is a directory, cannot be
// read, or holds more than _maxBytes_ bytes.
std::string ReadInputFile(const std::string &path, const std::string &what,
                          size_t maxBytes = kDefaultMaxInputBytes);

// The same for an input that must be a regular file (a link dump): a FIFO, a device or
// a socket is refused with InputError before anything is read, and never waited on.
std::string ReadRegularFile(const std::string &path, const std::string &what,
                            size_t maxBytes = kDefaultMaxInputBytes);

}  // namespace hrbench
