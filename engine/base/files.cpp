// The output layer (files.h): outputs written whole or not at all, never over an input or a non-regular file.
#include "base/files.h"

#include "base/common.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>
#include <cerrno>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>

namespace inkwell {

namespace {

// --- The temporaries a signal removes --------------------------------------------------------------------
// A fixed array the handler reads without locks or allocation: a slot's path is written before its flag is
// set, and the flag cleared before the slot is reused.
constexpr int kSlots = 64;
constexpr size_t kPathMax = 4096;
char gPaths[kSlots][kPathMax];
volatile std::sig_atomic_t gUsed[kSlots];
volatile std::sig_atomic_t gDirectory[kSlots];  // the slot is a directory of temporaries
std::mutex gRegistryMutex;

// Removes the files in `path` and then the directory, with async-signal-safe calls only (open, getdents64,
// unlinkat, lseek, close, rmdir): passes over the entries until one removes nothing.
void removeDirectoryOnSignal(const char* path) {
    int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        struct Entry {
            uint64_t inode;
            int64_t offset;
            unsigned short length;
            unsigned char type;
            char name[1];
        };
        alignas(8) char buffer[4096];
        for (int pass = 0; pass < 64; ++pass) {
            bool removed = false;
            ::lseek(fd, 0, SEEK_SET);
            long n;
            while ((n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer)) > 0)
                for (long at = 0; at < n;) {
                    const Entry* e = reinterpret_cast<const Entry*>(buffer + at);
                    const char* name = buffer + at + offsetof(Entry, name);
                    bool dots = name[0] == '.' && (name[1] == 0 || (name[1] == '.' && name[2] == 0));
                    if (!dots && ::unlinkat(fd, name, 0) == 0) removed = true;
                    at += e->length;
                }
            if (!removed) break;
        }
        ::close(fd);
    }
    ::rmdir(path);
}

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
struct sigaction gPrevious[3];

extern "C" void removeTemporariesAndDie(int sig) {
    for (int i = 0; i < kSlots; ++i)
        if (gUsed[i] && gDirectory[i])
            removeDirectoryOnSignal(gPaths[i]);
        else if (gUsed[i])
            ::unlink(gPaths[i]);  // async-signal-safe
    // The action before ours (the default: end the process; or another's handler, which runs next), raised
    // again: it is delivered once this handler returns.
    for (int i = 0; i < 3; ++i)
        if (kSignals[i] == sig) ::sigaction(sig, &gPrevious[i], nullptr);
    ::raise(sig);
}

}  // namespace

void removeTemporariesOnSignals() {
    for (int i = 0; i < 3; ++i) {
        struct sigaction current {};
        if (::sigaction(kSignals[i], nullptr, &current) != 0 || current.sa_handler == SIG_IGN ||
            current.sa_handler == removeTemporariesAndDie)
            continue;
        gPrevious[i] = current;
        struct sigaction action {};
        action.sa_handler = removeTemporariesAndDie;
        sigemptyset(&action.sa_mask);
        ::sigaction(kSignals[i], &action, nullptr);
    }
}

namespace {

thread_local OutputBatch* gBatch = nullptr;

[[noreturn]] void refuse(const std::string& path, const std::string& reason) {
    throw Error("cannot write '" + path + "': " + reason);
}

std::string kindOf(mode_t mode) {
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

// The file an output replaces: the path itself, or for a symbolic link the file it points to (so that the
// link stays and its target is written, as the shell's `>` does). Refuses what must not be replaced.
struct Target {
    std::string path;
    bool exists = false;
    mode_t mode = 0;
};

Target resolveTarget(const std::string& path) {
    Target t{path};
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
        char* resolved = ::realpath(path.c_str(), nullptr);
        if (!resolved)
            refuse(path, std::string("a symbolic link whose target cannot be resolved: ") + std::strerror(errno));
        t.path = resolved;
        std::free(resolved);
    }
    if (::stat(t.path.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) refuse(path, std::strerror(EISDIR));
        if (!S_ISREG(st.st_mode))
            refuse(path, kindOf(st.st_mode) + ", not a regular file: only regular files are replaced");
        t.exists = true;
        t.mode = st.st_mode & 07777;
    } else if (errno != ENOENT) {
        refuse(path, std::strerror(errno));
    }
    return t;
}

// A new empty file beside the target, `.inkwell-XXXXXX` (a short name: any legal output name works),
// registered for the signal handler, with the target's permissions (or the umask's for a new file).
std::string makeTemporary(const std::string& path, const Target& target, int& slot) {
    std::filesystem::path dir = std::filesystem::path(target.path).parent_path();
    std::string pattern = (dir.empty() ? std::string(".") : dir.string()) + "/.inkwell-XXXXXX";
    int fd = ::mkstemp(pattern.data());
    if (fd < 0) refuse(path, std::strerror(errno));
    slot = registerTemporary(pattern);
    mode_t mode = target.mode;
    if (!target.exists) {
        mode_t mask = ::umask(0);
        ::umask(mask);
        mode = 0666 & ~mask;
    }
    int error = 0;
    if (::fchmod(fd, mode) != 0) error = errno;
    if (::close(fd) != 0 && !error) error = errno;
    if (error) {
        ::unlink(pattern.c_str());
        unregisterTemporary(slot);
        refuse(path, std::strerror(error));
    }
    return pattern;
}

void discard(const std::string& tmp, int slot) {
    ::unlink(tmp.c_str());
    unregisterTemporary(slot);
}

struct stat statOrZero(const std::string& path, bool& exists) {
    struct stat st {};
    exists = ::stat(path.c_str(), &st) == 0;
    return st;
}

std::string normalized(const std::string& path) {
    std::error_code ec;
    std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec), ec);
    return (ec ? std::filesystem::path(path).lexically_normal() : p).string();
}

}  // namespace

namespace {

int registerSlot(const std::string& path, bool directory) {
    static std::once_flag once;
    std::call_once(once, removeTemporariesOnSignals);
    if (path.size() >= kPathMax) return -1;
    std::lock_guard lock(gRegistryMutex);
    for (int i = 0; i < kSlots; ++i)
        if (!gUsed[i]) {
            std::memcpy(gPaths[i], path.c_str(), path.size() + 1);
            gDirectory[i] = directory ? 1 : 0;
            gUsed[i] = 1;
            return i;
        }
    return -1;
}

}  // namespace

int registerTemporary(const std::string& path) { return registerSlot(path, false); }

int registerTemporaryDirectory(const std::string& path) { return registerSlot(path, true); }

void unregisterTemporary(int slot) {
    if (slot < 0 || slot >= kSlots) return;
    std::lock_guard lock(gRegistryMutex);
    gUsed[slot] = 0;
}

size_t registeredTemporaries() {
    std::lock_guard lock(gRegistryMutex);
    size_t n = 0;
    for (int i = 0; i < kSlots; ++i) n += gUsed[i] ? 1 : 0;
    return n;
}

void writeAll(int fd, const void* data, size_t size, const std::string& name, bool close) {
    const char* p = static_cast<const char*>(data);
    int error = 0;
    while (size > 0) {
        ssize_t n = ::write(fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            error = n < 0 ? errno : EIO;
            break;
        }
        p += n;
        size -= size_t(n);
    }
    if (close && ::close(fd) != 0 && !error) error = errno;
    if (error) refuse(name, std::strerror(error));
}

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    Target target = resolveTarget(path);
    int slot = -1;
    std::string tmp = makeTemporary(path, target, slot);
    try {
        write(tmp);
    } catch (...) {
        discard(tmp, slot);
        throw;
    }
    if (gBatch) {
        gBatch->pending_.push_back({tmp, target.path, path, slot});
        return;
    }
    if (::rename(tmp.c_str(), target.path.c_str()) != 0) {
        int e = errno;
        discard(tmp, slot);
        refuse(path, std::strerror(e));
    }
    unregisterTemporary(slot);
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
    writeAtomically(path, [&](const std::string& tmp) {
        int fd = ::open(tmp.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
        if (fd < 0) refuse(path, std::strerror(errno));
        writeAll(fd, bytes.data(), bytes.size(), path, true);
    });
}

OutputBatch::OutputBatch() : outer_(gBatch) { gBatch = this; }

OutputBatch::~OutputBatch() {
    gBatch = outer_;
    for (const Pending& p : pending_) discard(p.tmp, p.slot);
}

void OutputBatch::commit() {
    gBatch = outer_;
    for (size_t i = 0; i < pending_.size(); ++i) {
        const Pending& p = pending_[i];
        if (::rename(p.tmp.c_str(), p.target.c_str()) != 0) {
            int e = errno;
            std::string name = p.name;
            pending_.erase(pending_.begin(), pending_.begin() + std::ptrdiff_t(i));
            refuse(name, std::strerror(e));  // the destructor removes the rest
        }
        unregisterTemporary(p.slot);
    }
    pending_.clear();
}

void checkWritable(const std::string& path) {
    if (path.empty()) return;
    Target target = resolveTarget(path);
    int slot = -1;
    std::string tmp = makeTemporary(path, target, slot);
    discard(tmp, slot);
}

bool sameFile(const std::string& a, const std::string& b) {
    bool aExists = false, bExists = false;
    struct stat sa = statOrZero(a, aExists), sb = statOrZero(b, bExists);
    if (aExists && bExists) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    if (aExists != bExists) return false;
    return normalized(a) == normalized(b);
}

void checkOutputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs) {
    for (size_t i = 0; i < outputs.size(); ++i) {
        const std::string& out = outputs[i];
        if (out.empty()) continue;
        for (const std::string& in : inputs)
            if (!in.empty() && sameFile(out, in))
                refuse(out, "it is also an input of this command (inputs are never modified)");
        for (size_t j = 0; j < i; ++j)
            if (!outputs[j].empty() && sameFile(out, outputs[j])) refuse(out, "it is given as two outputs");
        checkWritable(out);
    }
}

}  // namespace inkwell
