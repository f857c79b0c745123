#include "engine/io/visibility_merge.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <memory>
#include <queue>
#include <string>
#include <vector>

#include "engine/io/atomic_file.h"
#include "engine/io/mapped_file.h"
#include "engine/io/text_input.h"
#include "engine/io/visibility_file.h"
#include "engine/scene/hash64.h"

namespace penumbra {
namespace detail_merge {

namespace fs = std::filesystem;
using Bytes = std::span<const unsigned char>;

std::string hex(uint64_t v) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "0x%016llx", static_cast<unsigned long long>(v));
    return buf;
}

std::string pairName(const PairKey& k) {
    return "pair (receiver " + std::to_string(k.receiver) + ", patch " + std::to_string(k.patch) +
           ", light " + std::to_string(k.lightFace) + ")";
}

struct Input {
    std::string name;
    std::unique_ptr<MappedFile> file;
    VisibilityFileHeader header;
};

// Walks one input's records in order, each checked (treeRecordAt) and keys strictly increasing.
class Cursor {
  public:
    explicit Cursor(const Input& in) : in_(&in), at_(in.header.payloadBegin) { advance(); }
    bool done() const { return done_; }
    const PairKey& key() const { return current_.key; }
    Bytes record() const { return in_->file->bytes().subspan(at_, current_.size); }
    const Input& input() const { return *in_; }
    void next() {
        at_ += current_.size;
        ++index_;
        advance();
    }

  private:
    void advance() {
        const VisibilityFileHeader& h = in_->header;
        const auto corrupt = [&](const std::string& what) {
            return VisibilityFileError(VisibilityFileStatus::Corrupt, in_->name + ": " + what);
        };
        if (index_ == h.treeCount) {
            if (at_ != h.payloadEnd)
                throw corrupt(std::to_string(h.payloadEnd - at_) +
                              " bytes left over after the last tree");
            done_ = true;
            return;
        }
        const std::string where =
            in_->name + ": tree " + std::to_string(index_) + " (byte " + std::to_string(at_) + ")";
        const TreeRecordExtent r = treeRecordAt(in_->file->bytes(), at_, h.payloadEnd, where);
        if (index_ > 0 && !(current_.key < r.key))
            throw VisibilityFileError(
                VisibilityFileStatus::Corrupt,
                where + ": " + pairName(r.key) + " out of order (a file is sorted by key)");
        current_ = r;
    }

    const Input* in_;
    size_t at_;
    uint64_t index_ = 0;
    TreeRecordExtent current_;
    bool done_ = false;
};

// One k-way merge over the inputs, handing each output record to `emit`; returns the trees and
// counts the duplicates.
template <typename Emit>
size_t mergeOnce(const std::vector<Input>& inputs, size_t& duplicates, Emit emit) {
    std::vector<Cursor> cursors;
    cursors.reserve(inputs.size());
    for (const Input& in : inputs) cursors.emplace_back(in);
    // A min-heap of cursor indices by (key, input order).
    const auto later = [&](size_t a, size_t b) {
        if (cursors[a].key() != cursors[b].key()) return cursors[b].key() < cursors[a].key();
        return b < a;
    };
    std::priority_queue<size_t, std::vector<size_t>, decltype(later)> heap(later);
    for (size_t i = 0; i < cursors.size(); ++i)
        if (!cursors[i].done()) heap.push(i);
    size_t trees = 0;
    duplicates = 0;
    while (!heap.empty()) {
        const size_t first = heap.top();
        heap.pop();
        const PairKey key = cursors[first].key();
        const Bytes kept = cursors[first].record();
        emit(kept);
        ++trees;
        std::vector<size_t> advanced{first};
        while (!heap.empty() && cursors[heap.top()].key() == key) {
            const size_t other = heap.top();
            heap.pop();
            const Bytes b = cursors[other].record();
            if (b.size() != kept.size() || std::memcmp(b.data(), kept.data(), b.size()) != 0)
                throw VisibilityFileError(
                    VisibilityFileStatus::Corrupt,
                    cursors[other].input().name + ": the tree of " + pairName(key) +
                        " differs from the one in " + cursors[first].input().name +
                        " (two runs built the same pair differently: other settings or another "
                        "program version?)");
            ++duplicates;
            advanced.push_back(other);
        }
        for (size_t i : advanced) {
            cursors[i].next();
            if (!cursors[i].done()) heap.push(i);
        }
    }
    return trees;
}

// The inputs' headers agree (scene hash); the message names what differs.
void checkSameScene(const Input& first, const Input& in) {
    if (in.header.sceneHash == first.header.sceneHash) return;
    const std::string hashes = "scene hash " + hex(in.header.sceneHash) + " here, " +
                               hex(first.header.sceneHash) + " in " + first.name;
    std::string what;
    if (in.header.shard && first.header.shard) {
        const std::string diff =
            settingsDifference(in.header.shard->settings, first.header.shard->settings);
        what = diff.empty() ? "made for another scene than " + first.name +
                                  " (the same settings; " + hashes + ")"
                            : "made with other settings than " + first.name + ": " + diff + " (" +
                                  hashes + ")";
    } else {
        what = "made for another scene or with other settings than " + first.name + " (" + hashes +
               ")";
    }
    throw VisibilityFileError(VisibilityFileStatus::Stale, in.name + ": " + what);
}

}  // namespace detail_merge

VisibilityMergeResult mergeVisibilityFiles(const std::filesystem::path& output,
                                           std::span<const std::filesystem::path> paths) {
    using namespace detail_merge;
    if (paths.empty())
        throw VisibilityFileError(VisibilityFileStatus::Missing, "no visibility files to merge");
    VisibilityMergeResult result;
    std::vector<Input> inputs;
    inputs.reserve(paths.size());
    for (const fs::path& path : paths) {
        Input in;
        in.name = path.string();
        std::error_code ec;
        if (!fs::exists(fs::status(path, ec)))
            throw VisibilityFileError(VisibilityFileStatus::Missing, in.name + ": no such file");
        try {
            in.file = std::make_unique<MappedFile>(path);
        } catch (const FileReadError& e) {
            throw VisibilityFileError(VisibilityFileStatus::Unreadable, e.what());
        }
        in.header = inspectVisibilityFile(in.file->bytes(), in.name);
        if (!inputs.empty()) checkSameScene(inputs.front(), in);
        if (in.header.shard) {
            ++result.shards;
            result.pairTotal = in.header.shard->pairTotal;
        }
        result.bytesRead += in.file->bytes().size();
        inputs.push_back(std::move(in));
    }
    result.inputs = inputs.size();
    result.sceneHash = inputs.front().header.sceneHash;

    // First pass: what the output holds (and every input checked record by record).
    uint64_t payloadBytes = 0;
    result.trees = mergeOnce(inputs, result.duplicates, [&](Bytes r) { payloadBytes += r.size(); });

    // Second pass: the file.
    try {
        AtomicFileWriter writer(output);
        Hash64ByteStream hash;
        std::vector<unsigned char> buffer;
        constexpr size_t kBufferBytes = size_t{4} << 20;
        buffer.reserve(kBufferBytes);
        const auto flush = [&] {
            hash.add(buffer);
            writer.append(
                std::string_view(reinterpret_cast<const char*>(buffer.data()), buffer.size()));
            buffer.clear();
        };
        const auto put = [&](Bytes b) {
            if (buffer.size() + b.size() > kBufferBytes) flush();
            const size_t at = buffer.size();
            buffer.resize(at + b.size());
            std::memcpy(buffer.data() + at, b.data(), b.size());
        };
        put(visibilityFileHeaderBytes(result.sceneHash, result.trees, payloadBytes));
        size_t duplicates = 0;
        mergeOnce(inputs, duplicates, put);
        flush();
        unsigned char trailer[8];
        const uint64_t checksum = hash.value();
        for (int k = 0; k < 8; ++k) trailer[k] = static_cast<unsigned char>(checksum >> (8 * k));
        writer.append(std::string_view(reinterpret_cast<const char*>(trailer), 8));
        writer.commit();
        result.bytes = writer.written();
    } catch (const AtomicWriteError& e) {
        throw VisibilityFileError(VisibilityFileStatus::WriteFailed, e.what());
    }
    return result;
}

}  // namespace penumbra
