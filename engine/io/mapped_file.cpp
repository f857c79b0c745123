#include "engine/io/mapped_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

#include "engine/io/text_input.h"

namespace penumbra {

MappedFile::MappedFile(const std::filesystem::path& path) {
    const auto error = [&](int err) {
        return FileReadError(path.string(), std::generic_category().message(err));
    };
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw error(errno);
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const int err = errno;
        ::close(fd);
        throw error(err);
    }
    if (S_ISDIR(st.st_mode)) {
        ::close(fd);
        throw error(EISDIR);
    }
    size_ = static_cast<size_t>(st.st_size);
    if (size_ > 0) {
        mapping_ = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
        if (mapping_ == MAP_FAILED) {
            const int err = errno;
            ::close(fd);
            mapping_ = nullptr;
            throw error(err);
        }
        // Read front to back, once or twice: read ahead, drop behind.
        ::madvise(mapping_, size_, MADV_SEQUENTIAL);
        data_ = static_cast<const unsigned char*>(mapping_);
    }
    ::close(fd);  // the mapping keeps the file
}

MappedFile::~MappedFile() {
    if (mapping_) ::munmap(mapping_, size_);
}

}  // namespace penumbra
