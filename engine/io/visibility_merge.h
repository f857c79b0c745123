// The merge of visibility files: the shards a cluster's ranks wrote (`precompute --shards`,
// docs/cluster.md) and/or whole files of the same scene and settings, joined into one whole file.
//
// The records are copied as they are, in key order (a k-way merge of the inputs, each sorted by
// key), so the result is byte for byte the file one process writes once the inputs cover every
// pair: the format has one encoding of a tree and one order. No scene is needed, and no tree is
// decoded: each input is mapped (engine/io/mapped_file.h), checked whole (header, size, checksum:
// what its rank wrote, intact) and walked record by record twice, once to count what the output
// holds (its header comes first and its checksum covers it) and once to write it through an
// AtomicFileWriter. Memory: one cursor per input and a 4 MB write buffer, whatever the sizes.
//
// Refused, naming the file (VisibilityFileError): a missing or unreadable input; a corrupt one
// (magic, version, sizes, checksum, a record's counts, keys out of order: the record is named); a
// scene hash that differs from the first input's (Stale: between two shards, the differing
// settings are named, or "another scene" when the settings agree); a pair present twice with
// different bytes (Corrupt, naming both files and the pair). A pair present twice with the same
// bytes is kept once and counted. Pairs missing from every input are counted when a shard (which
// states the scene's pair total) is among the inputs; the output is then a valid file that a
// later `precompute` completes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>

namespace penumbra {

struct VisibilityMergeResult {
    size_t inputs = 0, shards = 0;  // files read, and how many of them were shards
    size_t trees = 0;               // in the output
    size_t duplicates = 0;          // records present in more than one input, same bytes
    size_t bytesRead = 0;           // of the inputs
    size_t bytes = 0;               // of the output file
    uint64_t sceneHash = 0;
    std::optional<uint64_t> pairTotal;  // the scene's pairs, known when a shard was read
};

// Writes `output` atomically (an input may be `output` itself: it is read before the rename).
// Throws VisibilityFileError (Missing, Unreadable, Corrupt, Stale; WriteFailed).
VisibilityMergeResult mergeVisibilityFiles(const std::filesystem::path& output,
                                           std::span<const std::filesystem::path> inputs);

}  // namespace penumbra
