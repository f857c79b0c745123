// A whole file mapped read-only into memory (mmap): its bytes without copying them, paged in by the
// operating system as they are read and dropped under memory pressure. For inputs larger than the
// memory a process should hold, read once or twice in order: the merge of visibility files
// (engine/io/visibility_merge.h) and the keys of the cluster's shards.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>

namespace penumbra {

class MappedFile {
  public:
    // Throws FileReadError (engine/io/text_input.h): "FILE: cannot read file: REASON".
    explicit MappedFile(const std::filesystem::path& path);
    ~MappedFile();
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;

    std::span<const unsigned char> bytes() const { return {data_, size_}; }

  private:
    const unsigned char* data_ = nullptr;
    size_t size_ = 0;
    void* mapping_ = nullptr;  // what munmap gets (none for an empty file)
};

}  // namespace penumbra
