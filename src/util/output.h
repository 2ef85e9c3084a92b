// Writing output so that a failed write (a full disk, a closed pipe, a folder that does
// not exist) is an error, never a silent success, and so that an output file is written
// whole or not at all: the one way every command writes a file (docs/limits.md#output).
#pragma once

#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace hrbench {

// Flushes _out_ and throws InputError ("cannot write WHAT: reason") if any write to it
// failed.
void CheckOutput(std::ostream &out, const std::string &what);

// One output file, named _path_ by the user; _what_ names it in messages ("link dump").
// What happens depends on what the name is:
// - a regular file or a name not taken yet: the text goes to a temporary file in the
//   same folder (".NAME.XXXXXXXX.tmp"), which Commit() syncs to the disk and renames over
//   the name; a file that existed keeps its permission bits. Until then the previous
//   file is untouched, and an OutputFile destroyed without Commit() removes its
//   temporary file, so a failed write (a full disk) leaves the previous file as it was.
// - a symbolic link: its real target is written as above; the link stays a link.
// - a device or a FIFO (/dev/stdout, a named pipe): written through, never replaced; a
//   FIFO waits for its reader as a shell redirection does.
// - a folder, a name in a folder that does not exist: InputError before anything is
//   written.
// Every failure is an InputError naming the file and the system's reason.
class OutputFile {
  public:
    OutputFile(const std::string &path, const std::string &what);
    ~OutputFile();
    OutputFile(const OutputFile &) = delete;
    OutputFile &operator=(const OutputFile &) = delete;

    // The stream to write the whole content to.
    std::ostream &Stream();
    // Flushes and syncs the content; a temporary file stays under its own name.
    void Finish();
    // Finishes and puts the file in place (the rename); the output is then complete.
    void Commit();

  private:
    struct State;
    std::unique_ptr<State> state_;
};

// The file an OutputFile at _path_ writes: symbolic links followed, in its real folder
// (InputError as OutputFile's where it names a folder or a folder that does not exist).
// A file that others name beside it (an OBJ's MTL) belongs beside this one.
std::string OutputTarget(const std::string &path, const std::string &what);

// Writes _text_ to _path_ as one OutputFile.
void WriteOutputFile(const std::string &path, const std::string &what, const std::string &text);

// One file of an output made of several (an OBJ and its MTL library).
struct OutputText {
    std::string path, what, text;
};

// Writes several files of one output: every one is written and synced first, then they
// are renamed in the order given, so list a file that another refers to before it. A
// failed write (a full disk) therefore leaves every previous file intact.
void WriteOutputFiles(const std::vector<OutputText> &files);

// Throws InputError, before anything is written, when the output at _output_ (given by
// _outputFlag_) is the file the input _input_ (_inputFlag_) reads: the same device and
// inode, whatever links or names lead to them. Nothing to check where either is empty
// or the output does not exist yet.
void RefuseOutputOverInput(const std::string &output, const std::string &outputFlag,
                           const std::string &input, const std::string &inputFlag);

}  // namespace hrbench
