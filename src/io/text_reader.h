// Lines and words of a mesh or material file's text, and how its words are shown in
// messages (docs/3d.md, "Mesh input").
#pragma once

#include <algorithm>
#include <string>
#include <string_view>
#include <utility>

#include "hrbench/util/error.h"

namespace hrbench::meshio {

// _word_ for a message: at most 40 bytes, every byte outside printable ASCII escaped, so
// that a message stays one short line whatever the file holds.
std::string Shown(std::string_view word);

std::string Quoted(std::string_view word);

inline bool IsBlank(char c) { return c == ' ' || c == '\t'; }

// _value_ with 3 significant digits, for measures in messages.
std::string ThreeDigits(double value);

// The statements of one file's text, line by line, numbered from 1; errors name the file
// and the line. A statement line is one that is neither blank nor only a comment.
class Lines {
  public:
    // _file_ names the file in messages: "mesh file 'PATH'".
    Lines(std::string_view text, std::string file) : text_(text), file_(std::move(file)) {
        // Skip a UTF-8 byte order mark, which some editors write before the first line.
        if (text_.substr(0, 3) == "\xEF\xBB\xBF")
            pos_ = 3;
    }

    // Moves to the next statement line, without its line ending and its `#` comment;
    // false at the end of the text.
    bool Next() {
        while (pos_ < text_.size()) {
            size_t end = std::min(text_.find('\n', pos_), text_.size());
            std::string_view line = text_.substr(pos_, end - pos_);
            pos_ = std::min(end + 1, text_.size());
            ++number_;
            if (!line.empty() && line.back() == '\r')
                line.remove_suffix(1);
            if (line.find('\r') != std::string_view::npos)
                Fail("carriage return inside a line (line endings must be \\n or \\r\\n)");
            line = line.substr(0, line.find('#'));
            if (!std::all_of(line.begin(), line.end(), IsBlank)) {
                line_ = line;
                return true;
            }
        }
        return false;
    }

    std::string_view Line() const { return line_; }
    size_t Number() const { return number_; }
    // The bytes after the current line.
    size_t BytesLeft() const { return text_.size() - pos_; }

    [[noreturn]] void Fail(const std::string &what) const { FailAt(number_, what); }
    [[noreturn]] void FailAt(size_t line, const std::string &what) const {
        throw InputError(At(line, what));
    }
    // A warning about the current line, worded as an error is.
    std::string Warning(const std::string &what) const { return At(number_, what); }
    std::string At(size_t line, const std::string &what) const {
        return file_ + ", line " + std::to_string(line) + ": " + what;
    }
    // Fails at the line after the last one (line 1 of an empty file): where a truncated
    // file ends. Call once Next() has returned false.
    [[noreturn]] void FailAtEnd(const std::string &what) const { FailAt(number_ + 1, what); }

  private:
    std::string_view text_;
    std::string file_;
    size_t pos_ = 0;
    size_t number_ = 0;
    std::string_view line_;
};

// The words of a line, separated by spaces and tabs.
class Words {
  public:
    explicit Words(std::string_view line) : rest_(line) {}

    // Reads the next word into _word_; false when none is left.
    bool Next(std::string_view &word) {
        // Plain loops: find_first_of with a set costs a memchr per character.
        size_t start = 0, size = rest_.size();
        while (start < size && IsBlank(rest_[start]))
            ++start;
        size_t end = start;
        while (end < size && !IsBlank(rest_[end]))
            ++end;
        word = rest_.substr(start, end - start);
        rest_.remove_prefix(end);
        return !word.empty();
    }

    // The number of words not read yet.
    size_t Left() const {
        Words copy = *this;
        std::string_view word;
        size_t n = 0;
        while (copy.Next(word))
            ++n;
        return n;
    }

  private:
    std::string_view rest_;
};

}  // namespace hrbench::meshio
