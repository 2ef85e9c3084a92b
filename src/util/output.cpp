#include "output.h"

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <random>
#include <streambuf>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hrbench/util/error.h"

namespace hrbench {

void CheckOutput(std::ostream &out, const std::string &what) {
    errno = 0;
    if (!out.flush())
        throw InputError("cannot write " + what +
                         (errno ? ": " + std::string(std::strerror(errno)) : ""));
}

namespace {

// A stream buffer over a file descriptor that keeps the errno of its first failed write,
// so that the message gives the system's reason however late the failure shows.
class FdBuffer : public std::streambuf {
  public:
    explicit FdBuffer(int fd) : fd_(fd) { setp(buffer_, buffer_ + sizeof buffer_); }
    int Error() const { return error_; }

  protected:
    int_type overflow(int_type c) override {
        if (!Drain())
            return traits_type::eof();
        if (!traits_type::eq_int_type(c, traits_type::eof()))
            sputc(traits_type::to_char_type(c));
        return traits_type::not_eof(c);
    }
    int sync() override { return Drain() ? 0 : -1; }

  private:
    bool Drain() {
        for (char *p = pbase(); p < pptr();) {
            ssize_t n = ::write(fd_, p, size_t(pptr() - p));
            if (n < 0 && errno == EINTR)
                continue;
            if (n < 0) {
                error_ = error_ ? error_ : errno;
                return false;
            }
            p += n;
        }
        setp(buffer_, buffer_ + sizeof buffer_);
        return error_ == 0;
    }

    int fd_;
    int error_ = 0;
    char buffer_[1 << 16];
};

std::string Reason(int error) { return std::strerror(error); }

// The folder part of _path_ ("." for a bare name) and its last component.
std::pair<std::string, std::string> SplitPath(const std::string &path) {
    size_t slash = path.find_last_of('/');
    if (slash == std::string::npos)
        return {".", path};
    return {slash == 0 ? "/" : path.substr(0, slash), path.substr(slash + 1)};
}

// The file a write to _path_ reaches: symbolic links followed (a dangling one to the
// name it points at), in a folder given by its real path. _exists_ and _mode_ describe
// it where it exists.
struct Target {
    std::string folder, name;  // real folder, last component
    bool exists = false;
    mode_t mode = 0;
    std::string Path() const { return (folder == "/" ? "" : folder) + "/" + name; }
};

Target Resolve(const std::string &path, const std::string &label) {
    // Follow the links by hand: realpath() refuses a link to a name not taken yet.
    std::string p = path;
    struct stat info;
    Target t;
    for (int hops = 0;; ++hops) {
        if (lstat(p.c_str(), &info) != 0) {
            if (errno != ENOENT)
                throw InputError("cannot write " + label + ": " + Reason(errno));
            break;
        }
        if (!S_ISLNK(info.st_mode)) {
            t.exists = true;
            t.mode = info.st_mode;
            break;
        }
        if (hops == 40)
            throw InputError("cannot write " + label + ": " + Reason(ELOOP));
        char link[PATH_MAX];
        ssize_t n = readlink(p.c_str(), link, sizeof link - 1);
        if (n < 0)
            throw InputError("cannot write " + label + ": " + Reason(errno));
        std::string to(link, size_t(n));
        p = to[0] == '/' ? to : SplitPath(p).first + "/" + to;
    }
    if (t.exists && S_ISDIR(t.mode))
        throw InputError("cannot write " + label + ": it is a folder; give a file to write");
    auto [folder, name] = SplitPath(p);
    if (name.empty() || name == "." || name == "..")
        throw InputError("cannot write " + label + ": it names a folder; give a file to write");
    char real[PATH_MAX];
    if (!realpath(folder.c_str(), real))
        throw InputError("cannot write " + label + ": folder '" + folder + "': " + Reason(errno));
    t.folder = real;
    t.name = name;
    return t;
}

// Syncs the folder's entries (a rename); a file system that cannot (EINVAL) has nothing
// to do.
void SyncFolder(const std::string &folder, const std::string &label) {
    int fd = open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0)
        return;
    int failed = fsync(fd) != 0 && errno != EINVAL ? errno : 0;
    close(fd);
    if (failed)
        throw InputError("cannot write " + label + ": " + Reason(failed));
}

}  // namespace

struct OutputFile::State {
    std::string label;  // "link dump 'PATH'"
    Target target;
    bool through = false;   // a device or FIFO, written in place
    std::string temporary;  // the file written, when not through
    int fd = -1;
    FdBuffer *buffer = nullptr;
    std::unique_ptr<FdBuffer> owned;
    std::ostream stream{nullptr};
    bool finished = false, committed = false;

    [[noreturn]] void Fail(int error) const {
        throw InputError("cannot write " + label + ": " + Reason(error) +
                         (!through && target.exists ? "; the previous file is kept" : ""));
    }
};

OutputFile::OutputFile(const std::string &path, const std::string &what)
    : state_(std::make_unique<State>()) {
    State &s = *state_;
    s.label = what + " '" + path + "'";
    s.target = Resolve(path, s.label);
    const Target &t = s.target;
    s.through = t.exists && (S_ISCHR(t.mode) || S_ISBLK(t.mode) || S_ISFIFO(t.mode));
    if (t.exists && !s.through && !S_ISREG(t.mode))
        throw InputError("cannot write " + s.label + ": it is not a file, device or FIFO");
    if (s.through) {
        s.fd = open(t.Path().c_str(), O_WRONLY | O_CLOEXEC);
        if (s.fd < 0)
            s.Fail(errno);
    } else {
        // A new name beside the target, cut to stay within NAME_MAX; hidden by its dot.
        std::random_device random;
        for (int tries = 0; s.fd < 0; ++tries) {
            char suffix[16];
            std::snprintf(suffix, sizeof suffix, ".%08x.tmp", unsigned(random()));
            s.temporary = t.folder + "/." + t.name.substr(0, 100) + suffix;
            s.fd = open(s.temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
            if (s.fd < 0 && (errno != EEXIST || tries == 100)) {
                s.temporary.clear();
                s.Fail(errno);
            }
        }
        if (t.exists && fchmod(s.fd, t.mode & 07777) != 0)
            s.Fail(errno);
    }
    s.owned = std::make_unique<FdBuffer>(s.fd);
    s.buffer = s.owned.get();
    s.stream.rdbuf(s.buffer);
}

OutputFile::~OutputFile() {
    State &s = *state_;
    if (s.fd >= 0)
        close(s.fd);
    if (!s.committed && !s.temporary.empty())
        unlink(s.temporary.c_str());
}

std::ostream &OutputFile::Stream() { return state_->stream; }

void OutputFile::Finish() {
    State &s = *state_;
    if (s.finished)
        return;
    s.stream.flush();
    if (s.buffer->Error())
        s.Fail(s.buffer->Error());
    if (!s.stream)
        s.Fail(EIO);
    // A device or FIFO cannot be synced (EINVAL): what it does with the bytes is its own.
    if (fsync(s.fd) != 0 && !(s.through && (errno == EINVAL || errno == EROFS)))
        s.Fail(errno);
    int fd = s.fd;
    s.fd = -1;
    if (close(fd) != 0)
        s.Fail(errno);
    s.finished = true;
}

void OutputFile::Commit() {
    State &s = *state_;
    Finish();
    if (s.committed)
        return;
    if (!s.through) {
        if (rename(s.temporary.c_str(), s.target.Path().c_str()) != 0)
            s.Fail(errno);
        s.committed = true;
        SyncFolder(s.target.folder, s.label);
    }
    s.committed = true;
}

std::string OutputTarget(const std::string &path, const std::string &what) {
    return Resolve(path, what + " '" + path + "'").Path();
}

void WriteOutputFile(const std::string &path, const std::string &what, const std::string &text) {
    WriteOutputFiles({{path, what, text}});
}

void WriteOutputFiles(const std::vector<OutputText> &files) {
    std::vector<std::unique_ptr<OutputFile>> staged;
    for (const OutputText &file : files) {
        staged.push_back(std::make_unique<OutputFile>(file.path, file.what));
        staged.back()->Stream() << file.text;
        staged.back()->Finish();
    }
    for (auto &file : staged)
        file->Commit();
}

void RefuseOutputOverInput(const std::string &output, const std::string &outputFlag,
                           const std::string &input, const std::string &inputFlag) {
    struct stat out, in;
    if (output.empty() || input.empty() || stat(output.c_str(), &out) != 0 ||
        stat(input.c_str(), &in) != 0)
        return;
    if (out.st_dev == in.st_dev && out.st_ino == in.st_ino)
        throw InputError(outputFlag + " '" + output + "' is the file " + inputFlag + " '" + input +
                         "' reads; write the output to another file");
}

}  // namespace hrbench
