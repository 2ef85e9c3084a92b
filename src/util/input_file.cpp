#include "hrbench/util/input_file.h"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hrbench/util/error.h"

namespace hrbench {

namespace {

// What a file that is not a regular file is, for a message.
const char *KindOf(mode_t mode) {
    return S_ISFIFO(mode)   ? "a FIFO"
           : S_ISCHR(mode)  ? "a character device"
           : S_ISBLK(mode)  ? "a block device"
           : S_ISSOCK(mode) ? "a socket"
                            : "not a regular file";
}

// Closes a descriptor on every way out.
struct FileDescriptor {
    int fd;
    ~FileDescriptor() {
        if (fd >= 0)
            close(fd);
    }
};

std::string Read(const std::string &path, const std::string &what, size_t maxBytes,
                 bool regularOnly) {
    std::string name = what + " '" + path + "'";
    std::string limit = " the input limit of " + std::to_string(maxBytes >> 20) +
                        " MiB; raise it with --max-input MIB";

    // Refuse what cannot be a file before opening it: opening a FIFO without a writer
    // would wait for one.
    struct stat info;
    auto checkKind = [&] {
        if (S_ISDIR(info.st_mode))
            throw InputError("cannot read " + name + ": it is a directory");
        if (regularOnly && !S_ISREG(info.st_mode))
            throw InputError("cannot read " + name + ": it is " + KindOf(info.st_mode) +
                             ", not a regular file");
    };
    if (stat(path.c_str(), &info) != 0)
        throw InputError("cannot read " + name + ": " + std::strerror(errno));
    checkKind();

    // Without blocking where only a regular file will do: the path may have become a FIFO
    // since; what was opened is checked again, and its size, before reading.
    FileDescriptor file{open(path.c_str(), O_RDONLY | O_CLOEXEC | (regularOnly ? O_NONBLOCK : 0))};
    if (file.fd < 0 || fstat(file.fd, &info) != 0)
        throw InputError("cannot read " + name + ": " + std::strerror(errno));
    checkKind();
    if (S_ISREG(info.st_mode) && size_t(info.st_size) > maxBytes)
        throw InputError(name + " has " + std::to_string(info.st_size) + " bytes, more than" +
                         limit);

    // Read in chunks, never past the limit (devices and pipes have no size to check, and
    // a regular file may grow).
    std::string text;
    char chunk[1 << 16];
    for (;;) {
        ssize_t n = read(file.fd, chunk, sizeof chunk);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            throw InputError("cannot read " + name + ": " + std::strerror(errno));
        if (n == 0)
            return text;
        if (text.size() + size_t(n) > maxBytes)
            throw InputError(name + " is larger than" + limit);
        text.append(chunk, size_t(n));
    }
}

}  // namespace

std::string ReadInputFile(const std::string &path, const std::string &what, size_t maxBytes) {
    return Read(path, what, maxBytes, false);
}

std::string ReadRegularFile(const std::string &path, const std::string &what, size_t maxBytes) {
    return Read(path, what, maxBytes, true);
}

}  // namespace hrbench
