#include "engine/io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <random>
#include <string>
#include <system_error>
#include <utility>

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// Closes a POSIX file descriptor on scope exit.
struct FileDescriptor {
    int fd = -1;
    ~FileDescriptor() {
        if (fd >= 0) ::close(fd);
    }
    int release() { return std::exchange(fd, -1); }
};

std::string errnoText(int err) { return std::generic_category().message(err); }

// Thrown by the steps below; becomes AtomicWriteError with the target's name in front.
struct StepFailed : std::runtime_error {
    using std::runtime_error::runtime_error;
};

void writeAll(int fd, std::string_view bytes, size_t failAfter) {
    size_t written = 0;
    while (written < bytes.size()) {
        size_t chunk = std::min<size_t>(bytes.size() - written, size_t{1} << 20);
        if (written + chunk > failAfter) chunk = failAfter - written;
        if (chunk == 0) throw StepFailed("write: simulated write failure");
        const ssize_t n = ::write(fd, bytes.data() + written, chunk);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw StepFailed("write: " + errnoText(errno));
        }
        written += static_cast<size_t>(n);
    }
}

}  // namespace

AtomicFileWriter::AtomicFileWriter(const fs::path& path, const AtomicWriteOptions& options)
    : path_(path), options_(options) {
    if (path.filename().empty() || path.filename() == "." || path.filename() == "..")
        throw AtomicWriteError("cannot write '" + path.string() + "': not a file name");
    const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    std::random_device random;
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, ".tmp-%08x%08x", random(), random());
    temp_ = dir / ("." + path.filename().string() + suffix);
    fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd_ < 0)
        throw AtomicWriteError("cannot write '" + path.string() + "': create " + temp_.string() +
                               ": " + errnoText(errno));
}

AtomicFileWriter::~AtomicFileWriter() {
    if (committed_) return;
    if (fd_ >= 0) ::close(fd_);
    std::error_code ignored;
    fs::remove(temp_, ignored);
}

void AtomicFileWriter::fail(const std::string& why) {
    if (fd_ >= 0) ::close(std::exchange(fd_, -1));
    std::error_code ignored;
    fs::remove(temp_, ignored);
    throw AtomicWriteError("cannot write '" + path_.string() + "': " + why);
}

void AtomicFileWriter::append(std::string_view bytes) {
    if (fd_ < 0 || committed_) fail("write: the file is closed");
    const size_t failAfter =
        options_.failAfterBytes > written_ ? options_.failAfterBytes - written_ : 0;
    try {
        writeAll(fd_, bytes, failAfter);
    } catch (const StepFailed& e) {
        fail(e.what());
    }
    written_ += bytes.size();
}

void AtomicFileWriter::commit() {
    if (fd_ < 0 || committed_) fail("commit: the file is closed");
    if (::fsync(fd_) != 0) fail("fsync: " + errnoText(errno));
    if (::close(std::exchange(fd_, -1)) != 0) fail("close: " + errnoText(errno));
    std::error_code ec;
    fs::rename(temp_, path_, ec);
    if (ec) fail("rename " + temp_.string() + ": " + ec.message());
    committed_ = true;
    // Make the rename itself durable (best effort: some file systems refuse to fsync a directory).
    const fs::path dir = path_.parent_path().empty() ? fs::path(".") : path_.parent_path();
    FileDescriptor dirFd{::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)};
    if (dirFd.fd >= 0) ::fsync(dirFd.fd);
}

void writeFileAtomically(const fs::path& path, std::string_view bytes,
                         const AtomicWriteOptions& options) {
    AtomicFileWriter writer(path, options);
    writer.append(bytes);
    writer.commit();
}

}  // namespace penumbra
