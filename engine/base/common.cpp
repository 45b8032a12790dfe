#include "base/common.h"

#include <sys/stat.h>
#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace inkwell {

std::string readFileCapped(const std::string& path, size_t maxBytes, const std::string& tooLarge) {
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) throw Error("cannot open '" + path + "': " + std::strerror(errno));
    // Before reading: a device (a symlink to /dev/zero) would be read up to the cap, 2 GiB, before it is
    // refused. Regular files and FIFOs (a pipe, read up to the same cap) are read.
    struct stat info {};
    if (fstat(fileno(file), &info) != 0 || !(S_ISREG(info.st_mode) || S_ISFIFO(info.st_mode))) {
        std::fclose(file);
        if (S_ISDIR(info.st_mode)) throw Error("cannot open '" + path + "': " + std::strerror(EISDIR));
        throw Error("cannot read '" + path + "': not a regular file (" +
                    (S_ISCHR(info.st_mode)   ? "a character device"
                     : S_ISBLK(info.st_mode) ? "a block device"
                                             : "a socket or other special file") +
                    ")");
    }
    // A regular file larger than the cap is refused unread (a FIFO has no size: read up to the cap).
    if (S_ISREG(info.st_mode) && uint64_t(info.st_size) > uint64_t(maxBytes)) {
        std::fclose(file);
        throw Error(path + ": " + tooLarge);
    }
    std::string bytes;
    if (S_ISREG(info.st_mode)) {  // read in place: a 250 MB model appended in chunks was copied three times
        bytes.resize(size_t(info.st_size));
        bytes.resize(std::fread(bytes.data(), 1, bytes.size(), file));
    }
    char chunk[1 << 16];
    size_t n;
    while ((n = std::fread(chunk, 1, sizeof chunk, file)) > 0) {  // a FIFO, or a file that grew
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

std::string escapeText(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    auto escape = [&out](unsigned char c) {
        static const char* kHex = "0123456789abcdef";
        out += "\\x";
        out += kHex[c >> 4];
        out += kHex[c & 15];
    };
    for (size_t i = 0; i < s.size();) {
        unsigned char c = static_cast<unsigned char>(s[i]);
        if (c < 0x80) {
            if (c < 0x20 || c == 0x7f)
                escape(c);
            else
                out += char(c);
            ++i;
            continue;
        }
        // The length of a well-formed UTF-8 sequence starting with c (RFC 3629: no overlong forms, no
        // surrogates, nothing above U+10FFFF), or 0.
        size_t n = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3 : c >= 0xf0 && c <= 0xf4 ? 4 : 0;
        bool ok = n > 0 && i + n <= s.size();
        for (size_t k = 1; ok && k < n; ++k) {
            unsigned char d = static_cast<unsigned char>(s[i + k]);
            ok = (d & 0xc0) == 0x80;
            if (k == 1 && ok) {
                if (c == 0xe0) ok = d >= 0xa0;
                if (c == 0xed) ok = d < 0xa0;
                if (c == 0xf0) ok = d >= 0x90;
                if (c == 0xf4) ok = d < 0x90;
            }
        }
        if (!ok) {
            escape(c);
            ++i;
            continue;
        }
        out.append(s.substr(i, n));
        i += n;
    }
    return out;
}

}  // namespace inkwell

namespace ink {

namespace {
thread_local const Reporter* t_reporter = nullptr;
}

ScopedReporter::ScopedReporter(const Reporter& reporter) : previous_(t_reporter) { t_reporter = &reporter; }
ScopedReporter::~ScopedReporter() { t_reporter = previous_; }

void note(const std::string& line) {
    if (t_reporter && t_reporter->note) t_reporter->note(line);
}

Progress::Progress(const char* what, size_t total) : what_(what), total_(total) {}

Progress::~Progress() {
    if (lastPercent_ >= 0 && t_reporter && t_reporter->progress) t_reporter->progress(what_, total_, total_);
}

void Progress::update(size_t done) {
    if (!t_reporter || !t_reporter->progress || total_ == 0) return;
    int percent = int(100.0 * double(done) / double(total_));
    if (percent == lastPercent_) return;
    lastPercent_ = percent;
    t_reporter->progress(what_, done, total_);
}

}  // namespace ink
