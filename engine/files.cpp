// Output files written whole or not at all (files.h).
#include "files.h"

#include "common.h"

#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace ink {

namespace {

std::string temporaryPath(const std::string& path) { return path + ".tmp" + std::to_string(getpid()); }

}  // namespace

void checkWritable(const std::string& path) {
    if (path.empty()) return;
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error("cannot write '" + path + "': " + std::strerror(EISDIR));
    std::string tmp = temporaryPath(path);
    std::FILE* file = std::fopen(tmp.c_str(), "wb");
    if (!file) throw Error("cannot write '" + path + "': " + std::strerror(errno));
    std::fclose(file);
    std::remove(tmp.c_str());
}

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    std::string tmp = temporaryPath(path);
    try {
        write(tmp);
    } catch (...) {
        std::remove(tmp.c_str());
        throw;
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        int e = errno;
        std::remove(tmp.c_str());
        throw Error("cannot write '" + path + "': " + std::strerror(e));
    }
}

}  // namespace ink
