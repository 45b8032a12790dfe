// What the point readers share: their limits, one-line errors, and strict text scanning (lines, fields,
// numbers) for the text formats and the PLY ascii body.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ink::io {

// Header counts above this are refused outright, whatever the file size: no real input is that big, and
// it keeps a hostile header from turning into a huge allocation or loop.
constexpr uint64_t kMaxElements = 100'000'000;
constexpr uint64_t kMaxFileBytes = uint64_t(2) << 30;  // 2 GiB

// Throws ink::Error("NAME: WHAT").
[[noreturn]] void fail(const std::string& name, const std::string& what);

// "(x, y, z)", for messages.
std::string str(const Eigen::Vector3d& v);

// A number read from a file, for messages; it may be huge or negative when the file is corrupt.
std::string num(double v);

// "line N", for messages.
std::string lineName(size_t line);

// Splits on blanks; `out` is reused across calls to avoid reallocating per line.
void splitFields(std::string_view line, std::vector<std::string_view>& out);

// Locale-independent, whole-token number parsing (strtod would accept "1.5abc" prefixes and obey the
// locale's decimal point). "nan" and "inf" parse; the finiteness checks reject them with a location.
bool toDouble(std::string_view s, double& out);
bool toInt(std::string_view s, int64_t& out);

// Text lines ending in "\n", "\r\n" or "\r".
class Lines {
public:
    explicit Lines(std::string_view text, size_t start = 0, size_t firstNumber = 1)
        : text_(text), pos_(start), number_(firstNumber - 1) {}

    bool next(std::string_view& line) {
        if (pos_ >= text_.size()) return false;
        size_t end = std::min(text_.find_first_of("\r\n", pos_), text_.size());
        line = text_.substr(pos_, end - pos_);
        pos_ = end + 1;
        if (end < text_.size() && text_[end] == '\r' && pos_ < text_.size() && text_[pos_] == '\n') ++pos_;
        ++number_;
        return true;
    }
    size_t number() const { return number_; }
    size_t remaining() const { return text_.size() - std::min(pos_, text_.size()); }

private:
    std::string_view text_;
    size_t pos_;
    size_t number_;
};

// Text formats never contain NUL; finding one means the file is binary, and saying so is clearer than
// whatever parse error the garbage would cause next. `firstLine` is the number of the text's first line.
void rejectBinary(std::string_view text, const std::string& name, size_t firstLine = 1);

}  // namespace ink::io
