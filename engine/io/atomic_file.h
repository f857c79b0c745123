// The one way the project writes a file: atomically. The bytes go to a temporary file in the
// target's directory (a unique name, created exclusively), are written in full (short writes and
// EINTR retried), flushed to disk (fsync), and the temporary is renamed over the target; the
// directory is then synced (best effort) so that the rename survives a crash. A reader sees the
// old file or the whole new one, never a part. On failure the temporary is removed, the target is
// left as it was, and AtomicWriteError is thrown.
#pragma once

#include <cstddef>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string_view>

namespace penumbra {

// "cannot write 'PATH': REASON" (REASON names the step: create, write, fsync, close, rename).
struct AtomicWriteError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct AtomicWriteOptions {
    // Test hook: the write fails once this many bytes are written (simulates a full disk).
    size_t failAfterBytes = std::numeric_limits<size_t>::max();
};

void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes,
                         const AtomicWriteOptions& options = {});

// The same for a file too large to hold in memory (the merge of visibility files): append() the
// bytes as they come, then commit() (fsync, rename, directory fsync). Destroyed without a commit
// (an error, an exception), the temporary is removed and the target left as it was.
class AtomicFileWriter {
  public:
    explicit AtomicFileWriter(const std::filesystem::path& path,
                              const AtomicWriteOptions& options = {});  // creates the temporary
    ~AtomicFileWriter();
    AtomicFileWriter(const AtomicFileWriter&) = delete;
    AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

    void append(std::string_view bytes);
    void commit();
    size_t written() const { return written_; }

  private:
    [[noreturn]] void fail(const std::string& why);
    std::filesystem::path path_, temp_;
    AtomicWriteOptions options_;
    int fd_ = -1;
    size_t written_ = 0;
    bool committed_ = false;
};

}  // namespace penumbra
