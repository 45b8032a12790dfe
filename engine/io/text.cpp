// Strict text scanning and one-line errors for the point readers.
#include "io/text.h"

#include "base/common.h"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <system_error>

namespace ink::io {

void fail(const std::string& name, const std::string& what) { throw Error(name + ": " + what); }

std::string str(const Eigen::Vector3d& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%g, %g, %g)", v.x(), v.y(), v.z());
    return buf;
}

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.15g", v);
    return buf;
}

std::string lineName(size_t line) { return "line " + std::to_string(line); }

namespace {
bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
}  // namespace

void splitFields(std::string_view line, std::vector<std::string_view>& out) {
    out.clear();
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && isBlank(line[i])) ++i;
        size_t start = i;
        while (i < line.size() && !isBlank(line[i])) ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
}

bool toDouble(std::string_view s, double& out) {
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    if (end != s.data() + s.size() || s.empty()) return false;
    if (ec == std::errc::result_out_of_range) {
        // from_chars reports both overflow and underflow this way; strtod tells them apart (+-HUGE_VAL
        // or a tiny value), and the token is known to be a well-formed number by now.
        out = std::strtod(std::string(s).c_str(), nullptr);
        return true;
    }
    return ec == std::errc();
}

bool toInt(std::string_view s, int64_t& out) {
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && !s.empty() && end == s.data() + s.size();
}

void rejectBinary(std::string_view text, const std::string& name, size_t firstLine) {
    size_t nul = text.find('\0');
    if (nul == std::string_view::npos) return;
    Lines lines(text.substr(0, nul + 1), 0, firstLine);
    for (std::string_view line; lines.next(line);) {}
    fail(name, "line " + std::to_string(lines.number()) + ": binary data (a NUL byte) in a text file");
}

}  // namespace ink::io
