// Shared basics: the user-facing error type, notes and progress.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace ink {

// An error a user can cause (bad file, no device, too many points). The message is one line that says
// what is wrong and, where possible, how to fix it; apps print it and exit non-zero.
struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A token or line of a file, for a message: quoted, shortened, bytes outside printable ASCII shown as '?',
// so that binary garbage cannot break the one-line message.
std::string quoted(std::string_view s);

// The whole file, read in chunks (pipes have no size, files can change); more than maxBytes throws
// "PATH: tooLarge". Errors name the file and the system's reason.
std::string readFileCapped(const std::string& path, size_t maxBytes, const std::string& tooLarge);

// A one-line remark to the user ("note: merged 3 duplicate points"), written to stderr unless silenced.
void note(const std::string& line);
void setNotesEnabled(bool enabled);

// Progress of long work ("fit", "refine"): a single self-overwriting line, shown only when stderr is a
// terminal, so piped and scripted runs stay quiet.
struct Progress {
    Progress(const char* what, size_t total);
    ~Progress();
    void update(size_t done);
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

private:
    const char* what_;
    size_t total_;
    int lastPercent_ = -1;
    bool enabled_;
};

}  // namespace ink
