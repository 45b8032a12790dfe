// The output layer and the text of messages: every file Inkwell writes goes through here, and programs that write
// several files of one result (the command line: an image, its plot and its stats) use it too. The guarantees
// (docs/robustness.md):
//  - an output is complete or absent: it is written to a temporary file in the same directory
//    (`.inkwell-XXXXXX`, so a name of any legal length works), every write and close is checked, and only
//    then is it renamed over the output; on any failure, and on SIGINT/SIGTERM, the temporary is removed;
//  - only regular files are replaced: an existing device, FIFO, socket or directory is refused; a symbolic
//    link is written through (the file it points to is replaced, the link stays), a dangling one refused;
//  - inputs are never modified: checkOutputs refuses an output that is one of the command's inputs;
//  - an OutputBatch commits all of a command's outputs only when all of them were written.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace inkwell {

// A token or line of a file, for a message: quoted, shortened, bytes outside printable ASCII shown as '?',
// so that binary garbage cannot break the one-line message.
std::string quoted(std::string_view s);

// `s` with every byte that is not printable text escaped as \xNN: control characters (a newline too) and
// bytes that are not valid UTF-8; valid UTF-8 (a file name with accents) stays as it is. Every message the
// command line prints goes through it, so a file's stray byte never reaches the terminal raw.
std::string escapeText(std::string_view s);

// The whole file, read in chunks (pipes have no size, files can change); more than maxBytes throws
// "PATH: tooLarge". Errors name the file and the system's reason.
std::string readFileCapped(const std::string& path, size_t maxBytes, const std::string& tooLarge);

// Calls write(tmpPath) and renames tmpPath over path (or, inside an OutputBatch, leaves the rename to its
// commit()); on any failure removes tmpPath and throws inkwell::Error. write must check its own writes.
void writeAtomically(const std::string& path, const std::function<void(const std::string& tmpPath)>& write);

// Writes `bytes` to `path` atomically, checking every write, the flush and the close.
void writeFileAtomically(const std::string& path, const std::string& bytes);

// Writes `size` bytes to an open file descriptor (a temporary of writeAtomically, or /dev/full in a test);
// throws inkwell::Error "cannot write 'NAME': REASON" on a short write, and closes fd (checked) when asked.
void writeAll(int fd, const void* data, size_t size, const std::string& name, bool close);

// Refuses, up front, an output path writeAtomically could not write (a missing or read-only directory, a
// directory, device, FIFO or socket in its place, a dangling symbolic link), with the one-line message the
// write would give: it creates and removes a temporary file beside the target. Does nothing for an empty path.
void checkWritable(const std::string& path);

// checkWritable for each non-empty output, and refuses an output that is one of `inputs` or another output
// (the same file by device and inode when it exists, by normalized absolute path when it does not).
void checkOutputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs);

// True when a and b name the same file (see checkOutputs).
bool sameFile(const std::string& a, const std::string& b);

// While one is alive (on this thread), writeAtomically writes temporaries and defers their renames to
// commit(); destroying it without commit() removes them all. commit() renames them in the order written.
class OutputBatch {
public:
    OutputBatch();
    ~OutputBatch();
    OutputBatch(const OutputBatch&) = delete;
    OutputBatch& operator=(const OutputBatch&) = delete;
    void commit();

private:
    struct Pending {
        std::string tmp, target, name;
        int slot;
    };
    std::vector<Pending> pending_;
    OutputBatch* outer_;
    friend void writeAtomically(const std::string&, const std::function<void(const std::string&)>&);
};

// Installs the SIGINT/SIGTERM/SIGHUP handler that unlinks the registered temporaries and then raises the
// signal again with the action it replaced (not over an ignored signal). Done by the first registration;
// call again after someone else replaced the handler.
void removeTemporariesOnSignals();

// The registry of temporaries the SIGINT/SIGTERM handler removes (unlink only, on a fixed array), exposed
// for tests. registerTemporary returns a slot (or -1 when full: the file is then not protected).
int registerTemporary(const std::string& path);
// A directory of temporaries (capture's staging directory): the handler removes the files in it, then it.
int registerTemporaryDirectory(const std::string& path);
void unregisterTemporary(int slot);
size_t registeredTemporaries();

}  // namespace inkwell
