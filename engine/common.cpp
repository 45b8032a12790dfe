#include "common.h"

#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace ink {

static bool g_notes = true;

std::string readFileCapped(const std::string& path, size_t maxBytes, const std::string& tooLarge) {
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) throw Error("cannot open '" + path + "': " + std::strerror(errno));
    std::string bytes;
    char chunk[1 << 16];
    size_t n;
    while ((n = std::fread(chunk, 1, sizeof chunk, file)) > 0) {
        bytes.append(chunk, n);
        if (bytes.size() > maxBytes) {
            std::fclose(file);
            throw Error(path + ": " + tooLarge);
        }
    }
    bool bad = std::ferror(file);
    int error = errno;
    std::fclose(file);
    if (bad) throw Error("cannot read '" + path + "': " + std::strerror(error));
    return bytes;
}

std::string quoted(std::string_view s) {
    constexpr size_t kMax = 40;
    std::string out = "'";
    for (size_t i = 0; i < s.size() && i < kMax; ++i) {
        unsigned char c = static_cast<unsigned char>(s[i]);
        out += (c >= 0x20 && c < 0x7f) ? char(c) : '?';
    }
    if (s.size() > kMax) out += "...";
    return out + "'";
}

void note(const std::string& line) {
    if (g_notes) std::fprintf(stderr, "note: %s\n", line.c_str());
}

void setNotesEnabled(bool enabled) { g_notes = enabled; }

Progress::Progress(const char* what, size_t total) : what_(what), total_(total), enabled_(isatty(STDERR_FILENO) != 0) {}

Progress::~Progress() {
    if (enabled_ && lastPercent_ >= 0) std::fprintf(stderr, "\r%s: done%-10s\n", what_, "");
}

void Progress::update(size_t done) {
    if (!enabled_ || total_ == 0) return;
    int percent = int(100.0 * double(done) / double(total_));
    if (percent == lastPercent_) return;
    lastPercent_ = percent;
    std::fprintf(stderr, "\r%s: %3d%%", what_, percent);
    std::fflush(stderr);
}

}  // namespace ink
