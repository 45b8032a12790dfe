// The output layer (engine/base/files.h, docs/robustness.md): an output is complete or absent, only regular files
// are replaced (a symbolic link is written through), inputs are never modified, a command's outputs are
// committed together, and a signal leaves no temporary file.
#include "base/common.h"
#include "base/files.h"
#include "base/image.h"
#include "run_command.h"
#include "skip.h"
#include "temp_dir.h"

#include <doctest/doctest.h>

#include <fcntl.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// No temporary of the output layer (nor of the old NAME.tmpPID scheme) anywhere under dir.
bool noTemporaries(const fs::path& dir) {
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
        std::string name = entry.path().filename().string();
        if (name.rfind(".inkwell-", 0) == 0 || name.find(".tmp") != std::string::npos) {
            MESSAGE("left behind: " << entry.path());
            return false;
        }
    }
    return true;
}

int lines(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

const std::string kBunny = INKWELL_SOURCE_DIR "/assets/bunny.obj";
const std::string kFit = " --control-points 50 ";
const std::string kSmall = " --levels 1 --size 64 64 ";

// A tmpfs of `kib` KiB at dir/name, filled to the last byte (for root only; false where it cannot be made).
struct FullDisk {
    std::string path;
    bool mounted = false;
    FullDisk(const TempDir& dir, const std::string& name) : path(dir / name) {
        fs::create_directories(path);
        if (geteuid() != 0 || ::mount("tmpfs", path.c_str(), "tmpfs", 0, "size=64k") != 0) return;
        mounted = true;
        std::string filler = path + "/filler";
        int fd = ::open(filler.c_str(), O_WRONLY | O_CREAT, 0644);
        std::string block(4096, 'x');
        while (::write(fd, block.data(), block.size()) > 0) {}
        ::close(fd);
    }
    ~FullDisk() {
        if (mounted) ::umount(path.c_str());
    }
};

}  // namespace

TEST_CASE("outputs: a failed write or close says why, and /dev/full is a full disk" * doctest::test_suite("unit")) {
    int fd = ::open("/dev/full", O_WRONLY);
    REQUIRE(fd >= 0);
    std::string bytes(100000, 'x');
    CHECK_THROWS_WITH_AS(ink::writeAll(fd, bytes.data(), bytes.size(), "out.png", true),
                         "cannot write 'out.png': No space left on device", ink::Error);
}

TEST_CASE("outputs: only regular files are replaced; a symbolic link is written through" *
          doctest::test_suite("unit")) {
    TempDir dir;
    std::string fifo = dir / "fifo.png";
    REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
    ink::RgbaImage image{2, 2, std::vector<uint8_t>(16, 255)};
    CHECK_THROWS_WITH_AS(ink::writePng(fifo, image), doctest::Contains("a FIFO, not a regular file"), ink::Error);
    CHECK_THROWS_WITH_AS(ink::checkWritable(fifo), doctest::Contains("a FIFO"), ink::Error);
    CHECK(fs::is_fifo(fifo));

    std::string target = dir.write("target.json", "old");
    fs::create_symlink("target.json", dir.path / "link.json");
    ink::writeFileAtomically(dir / "link.json", "new");
    CHECK(fs::is_symlink(dir.path / "link.json"));
    CHECK(slurp(target) == "new");

    fs::create_symlink("missing/x.json", dir.path / "dangling.json");
    CHECK_THROWS_WITH_AS(ink::writeFileAtomically(dir / "dangling.json", "x"), doctest::Contains("symbolic link"),
                         ink::Error);
    CHECK(fs::is_symlink(dir.path / "dangling.json"));
    CHECK(noTemporaries(dir.path));
}

TEST_CASE("outputs: a 250-character file name is written (the temporary name is short)" * doctest::test_suite("unit")) {
    TempDir dir;
    std::string name = std::string(245, 'n') + ".json";
    REQUIRE(name.size() == 250);
    ink::writeFileAtomically(dir / name, "{}\n");
    CHECK(slurp(dir / name) == "{}\n");
    CHECK(noTemporaries(dir.path));
}

TEST_CASE("outputs: a batch commits all of its outputs or none" * doctest::test_suite("unit")) {
    TempDir dir;
    std::string a = dir.write("a.txt", "old a");
    {
        ink::OutputBatch batch;
        ink::writeFileAtomically(a, "new a");
        CHECK(slurp(a) == "old a");  // not yet
        CHECK_THROWS_AS(ink::writeAtomically(dir / "b.txt", [](const std::string&) { throw ink::Error("failed"); }),
                        ink::Error);
    }  // not committed
    CHECK(slurp(a) == "old a");
    CHECK(!fs::exists(dir / "b.txt"));
    CHECK(noTemporaries(dir.path));
    CHECK(ink::registeredTemporaries() == 0);
    {
        ink::OutputBatch batch;
        ink::writeFileAtomically(a, "new a");
        ink::writeFileAtomically(dir / "b.txt", "b");
        batch.commit();
    }
    CHECK(slurp(a) == "new a");
    CHECK(slurp(dir / "b.txt") == "b");
    CHECK(noTemporaries(dir.path));
}

TEST_CASE("outputs: SIGTERM and SIGINT during a write remove the registered temporaries" *
          doctest::test_suite("unit")) {
    for (int sig : {SIGTERM, SIGINT}) {
        TempDir dir;
        pid_t child = ::fork();
        REQUIRE(child >= 0);
        if (child == 0) {
            // Interrupted in the middle of the write: the temporary exists and is registered. (doctest has its own
            // handlers; the child takes the program's: the default action, then the output layer's.)
            std::signal(sig, SIG_DFL);
            ink::removeTemporariesOnSignals();
            try {
                ink::writeAtomically(dir / "out.png", [&](const std::string& tmp) {
                    std::ofstream(tmp) << "half";
                    ::raise(sig);
                });
            } catch (...) {}
            ::_exit(0);  // not reached when the signal ends the process
        }
        int status = 0;
        REQUIRE(::waitpid(child, &status, 0) == child);
        CHECK(WIFSIGNALED(status));
        CHECK(WTERMSIG(status) == sig);
        CHECK(!fs::exists(dir / "out.png"));
        CHECK(noTemporaries(dir.path));
    }
}

TEST_CASE("outputs: SIGTERM removes a registered directory of temporaries with the files in it (issue 29)" *
          doctest::test_suite("unit")) {
    TempDir dir;
    pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        // capture's staging directory: frames already drawn, one being written.
        std::signal(SIGTERM, SIG_DFL);
        ink::removeTemporariesOnSignals();
        std::string staging = dir / ".inkwell-capture-test";
        fs::create_directory(staging);
        ink::registerTemporaryDirectory(staging);
        for (int i = 0; i < 300; ++i) std::ofstream(staging + "/frame_" + std::to_string(i) + ".png") << "frame";
        try {
            ink::writeAtomically(staging + "/frame_300.png", [&](const std::string& tmp) {
                std::ofstream(tmp) << "half";
                ::raise(SIGTERM);
            });
        } catch (...) {}
        ::_exit(0);
    }
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    CHECK(WIFSIGNALED(status));
    CHECK(!fs::exists(dir / ".inkwell-capture-test"));
    CHECK(fs::is_empty(dir.path));
}

TEST_CASE("outputs: a FIFO or a symbolic link given to a command" * doctest::test_suite("cli")) {
    TempDir dir;
    std::string fifo = dir / "out.hrbf";
    REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
    Run r = runInkwell("fit " + kBunny + kFit + "-o " + fifo);
    CHECK(r.status == 1);
    CHECK(lines(r.output) == 1);
    CHECK(r.output.find("a FIFO, not a regular file") != std::string::npos);
    CHECK(fs::is_fifo(fifo));

    std::string target = dir.write("real.hrbf", "old");
    fs::create_symlink("real.hrbf", dir.path / "link.hrbf");
    r = runInkwell("fit " + kBunny + kFit + "-o " + (dir / "link.hrbf"));
    CHECK(r.status == 0);
    CHECK(fs::is_symlink(dir.path / "link.hrbf"));
    CHECK(slurp(target).rfind("\x89HRBF", 0) == 0);
    CHECK(noTemporaries(dir.path));
}

TEST_CASE("outputs: an output that is an input is refused before any work" * doctest::test_suite("cli")) {
    TempDir dir;
    std::string model = dir.write("x.obj", slurp(kBunny));
    Run r = runInkwell("render " + model + kSmall + "-o " + model);
    CHECK(r.status == 1);
    CHECK(lines(r.output) == 1);
    CHECK(r.output.find("is also an input") != std::string::npos);
    CHECK(slurp(model) == slurp(kBunny));

    // The same file by another name.
    r = runInkwell("fit " + model + kFit + "-o " + dir.path.string() + "/./x.obj");
    CHECK(r.status == 1);
    CHECK(slurp(model) == slurp(kBunny));

    r = runInkwell("bench --model " + model + " --json " + model);
    CHECK(r.status == 1);
    CHECK(r.output.find("is also an input") != std::string::npos);
    CHECK(slurp(model) == slurp(kBunny));

    r = runInkwell("render " + model + kSmall + "-o " + (dir / "o.png") + " --stats " + (dir / "o.png"));
    CHECK(r.status == 1);
    CHECK(r.output.find("given as two outputs") != std::string::npos);
    CHECK(!fs::exists(dir / "o.png"));

    ink::writePng(dir / "a.png", {2, 2, std::vector<uint8_t>(16, 255)});
    ink::writePng(dir / "b.png", {2, 2, std::vector<uint8_t>(16, 0)});
    std::string a = slurp(dir / "a.png");
    r = runInkwell("compare " + (dir / "a.png") + " " + (dir / "b.png") + " --diff " + (dir / "a.png"));
    CHECK(r.status == 1);
    CHECK(r.output.find("is also an input") != std::string::npos);
    CHECK(slurp(dir / "a.png") == a);
    CHECK(noTemporaries(dir.path));
}

TEST_CASE("outputs: a 250-character output name works for a command" * doctest::test_suite("cli")) {
    TempDir dir;
    std::string name = dir / (std::string(245, 'h') + ".hrbf");
    Run r = runInkwell("fit " + kBunny + kFit + "-o " + name + " --stats " + (dir / (std::string(245, 's') + ".json")));
    CHECK(r.status == 0);
    CHECK(fs::exists(name));
    CHECK(noTemporaries(dir.path));
}

TEST_CASE("outputs: a full disk is exit 1 with the reason, and leaves no output, not even the first of two" *
          doctest::test_suite("cli")) {
    TempDir dir;
    FullDisk full(dir, "full");
    if (!full.mounted) {
        skipTest("needs root to mount a small tmpfs");
        return;
    }
    Run r = runInkwell("render -q " + kBunny + kFit + kSmall + "-o " + full.path + "/out.png");
    CHECK(r.status == 1);
    CHECK(lines(r.output) == 1);
    CHECK(r.output.find("No space left on device") != std::string::npos);
    CHECK(!fs::exists(full.path + "/out.png"));

    // The model fits, the stats do not: neither is left.
    r = runInkwell("fit " + kBunny + kFit + "-o " + (dir / "ok.hrbf") + " --stats " + full.path + "/s.json");
    CHECK(r.status == 1);
    CHECK(r.output.find("No space left on device") != std::string::npos);
    CHECK(!fs::exists(dir / "ok.hrbf"));
    CHECK(!fs::exists(full.path + "/s.json"));

    // A re-capture that fails (its stats do not fit) leaves the old capture as it was, its manifest included
    // (the new frames are swapped in only once everything is written), and no new manifest.
    fs::create_directories(dir.path / "cap");
    dir.write("cap/manifest.json", "{\"frames\": [\"old\"]}\n");
    r = runInkwell("capture " + kBunny + kFit + kSmall + "--frames 2 -o " + (dir / "cap") + " --stats " + full.path +
                   "/s.json");
    CHECK(r.status == 1);
    CHECK(r.output.find("No space left on device") != std::string::npos);
    std::ifstream old(dir / "cap/manifest.json");
    CHECK(std::string(std::istreambuf_iterator<char>(old), {}) == "{\"frames\": [\"old\"]}\n");
    CHECK(!fs::exists(dir / "cap/frame_0000.png"));
    CHECK(noTemporaries(dir.path));
}
