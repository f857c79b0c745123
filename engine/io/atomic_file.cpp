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

void writeFileAtomically(const fs::path& path, std::string_view bytes,
                         const AtomicWriteOptions& options) {
    const auto error = [&](const std::string& why) {
        return AtomicWriteError("cannot write '" + path.string() + "': " + why);
    };
    if (path.filename().empty() || path.filename() == "." || path.filename() == "..")
        throw error("not a file name");
    const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    std::random_device random;
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, ".tmp-%08x%08x", random(), random());
    const fs::path temp = dir / ("." + path.filename().string() + suffix);
    FileDescriptor file{::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644)};
    if (file.fd < 0) throw error("create " + temp.string() + ": " + errnoText(errno));
    try {
        writeAll(file.fd, bytes, options.failAfterBytes);
        if (::fsync(file.fd) != 0) throw StepFailed("fsync: " + errnoText(errno));
        if (::close(file.release()) != 0) throw StepFailed("close: " + errnoText(errno));
        std::error_code ec;
        fs::rename(temp, path, ec);
        if (ec) throw StepFailed("rename " + temp.string() + ": " + ec.message());
    } catch (const StepFailed& e) {
        if (file.fd >= 0) ::close(file.release());
        std::error_code ignored;
        fs::remove(temp, ignored);
        throw error(e.what());
    }
    // Make the rename itself durable (best effort: some file systems refuse to fsync a directory).
    FileDescriptor dirFd{::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)};
    if (dirFd.fd >= 0) ::fsync(dirFd.fd);
}

}  // namespace penumbra
