// Writing output so that a failed write (a full disk, a closed pipe, a folder that does
// not exist) is an error, never a silent success.
#pragma once

#include <ostream>
#include <string>

namespace hrbench {

// Flushes _out_ and throws InputError ("cannot write WHAT: reason") if any write to it
// failed.
void CheckOutput(std::ostream &out, const std::string &what);

// Writes _text_ to the file at _path_ (replacing it); _what_ names it in messages.
void WriteOutputFile(const std::string &path, const std::string &what, const std::string &text);

}  // namespace hrbench
