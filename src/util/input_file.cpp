#include "hrbench/util/input_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>

#include <sys/stat.h>

#include "hrbench/util/error.h"

namespace hrbench {

std::string ReadInputFile(const std::string &path, const std::string &what, size_t maxBytes) {
    std::string name = what + " '" + path + "'";
    std::string limit = " the input limit of " + std::to_string(maxBytes >> 20) +
                        " MiB; raise it with --max-input MIB";

    // Refuse what cannot be a file before opening it, and a regular file that is too big.
    struct stat info;
    if (stat(path.c_str(), &info) != 0)
        throw InputError("cannot read " + name + ": " + std::strerror(errno));
    if (S_ISDIR(info.st_mode))
        throw InputError("cannot read " + name + ": it is a directory");
    if (S_ISREG(info.st_mode) && size_t(info.st_size) > maxBytes)
        throw InputError(name + " has " + std::to_string(info.st_size) + " bytes, more than" +
                         limit);

    // Read in chunks, never past the limit (devices and pipes have no size to check).
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw InputError("cannot read " + name + ": " + std::strerror(errno));
    std::string text;
    char chunk[1 << 16];
    while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
        if (text.size() + size_t(in.gcount()) > maxBytes)
            throw InputError(name + " is larger than" + limit);
        text.append(chunk, size_t(in.gcount()));
    }
    if (in.bad())
        throw InputError("cannot read " + name + ": read error");
    return text;
}

}  // namespace hrbench
