#include "output.h"

#include <cerrno>
#include <cstring>
#include <fstream>

#include "hrbench/util/error.h"

namespace hrbench {

void CheckOutput(std::ostream &out, const std::string &what) {
    errno = 0;
    if (!out.flush())
        throw InputError("cannot write " + what +
                         (errno ? ": " + std::string(std::strerror(errno)) : ""));
}

void WriteOutputFile(const std::string &path, const std::string &what, const std::string &text) {
    std::string name = what + " '" + path + "'";
    std::ofstream out(path, std::ios::binary);
    if (!out)
        throw InputError("cannot write " + name + ": " + std::strerror(errno));
    out << text;
    CheckOutput(out, name);
    out.close();
    if (!out)
        throw InputError("cannot write " + name + ": " + std::strerror(errno));
}

}  // namespace hrbench
