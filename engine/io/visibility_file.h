// The visibility file (.pvis): the history trees of a VisibilityStore on disk, so that a scene's
// precompute is paid once.
//
// Format, version 4 (version 1 had no deferred occluders, version 2 stored constructed vertices
// where nodes now name exact chords, version 3 also each tree's build time), every integer
// little-endian, doubles as their IEEE-754 bit patterns:
//   header (48 bytes)  magic "PENUMVIS", u32 version, u32 header size (48), u64 scene hash
//                      (engine/precompute/scene_hash.h), u64 tree count, u64 payload size,
//                      u64 flags (0)
//   payload            one record per tree, in increasing PairKey order:
//                        u32 receiver, patch, light face            (PairKey)
//                        u32 tree.receiver, tree.light               (equal to the key's)
//                        u8 kind, u8 has-stats, u16 reason length, u32 meshVertexCount,
//                        u32 node count, u32 occluder count, u32 node-occluder count,
//                        u32 deferred-occluder count, the reason text (HistoryTree::why), nodes
//                        (4 x u32 each: v0, v1, children; history_tree.h), occluders (u32 face
//                        each: HistoryTree::occluders), node occluders (u32 each), deferred
//                        occluders (u32 face each), and with has-stats the
//                        BuildStats' counts (3 x u32, 8 x u64)
// No time is stored: a visibility file depends only on the scene and the settings, so that any
// number of threads (or processes) writes the same bytes for them. Build times go to stderr
// (precompute's summary) and the bench; a tree read from a file has BuildStats::seconds 0.
//   trailer (8 bytes)  u64 checksum (engine/scene/hash64.h) of header and payload
//
// A shard (one rank's trees of a cluster precompute, `precompute --shards`, docs/cluster.md) is a
// visibility file of the same version holding a subset of the pairs, with flags 1 (kShardFlag)
// and a header of 88 bytes: the 48 above, then u32 shard index, u32 shard count, u64 the scene's
// pair total (everyPairKey), and the settings that shape the trees, which the scene hash mixes
// in: u64 maxLpSolves, f64 patch fraction, u8 mergeLeaves, u8 quadricPruning, u16 0, u32
// kTreeBuilderRevision. It reads as any file (the trees it holds); `penumbra merge` joins shards
// and files into one whole file (engine/io/visibility_merge.h), naming a setting that differs.
//
// Writing is atomic: a temporary file in the same directory, fsync, rename over the target (then
// an fsync of the directory). A failure at any point leaves the old file as it was and removes the
// temporary file.
//
// Reading validates everything before it touches the store (all or nothing): magic, version,
// sizes, checksum, then the scene hash (a mismatch is Stale, not Corrupt: the file is intact but
// made for another scene or other settings), then every record: counts bounded by the bytes left,
// kinds and reasons known, keys in range (faces, patches), node children either leaves or later
// nodes each referenced once (a tree, no cycles), depth at most kMaxTreeDepth (FPQuery recurses
// per level), vertex ids and chords' faces in range, occluder faces in range, no duplicate keys,
// no bytes left over. A file that passes cannot make FPQuery read out of bounds or loop.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/precompute/visibility_store.h"

namespace penumbra {

inline constexpr uint32_t kVisibilityFileVersion = 4;
inline constexpr uint32_t kMaxTreeDepth = 20000;

enum class VisibilityFileStatus {
    Missing,      // no such file
    Unreadable,   // exists but cannot be read (permissions, I/O error, a directory)
    Corrupt,      // not a visibility file, another version, truncated, checksum or content error
    Stale,        // intact, but made for another scene or other build settings
    WriteFailed,  // writing failed (the previous file, if any, is untouched)
};
const char* toString(VisibilityFileStatus status);

// what(): "<file>: <problem>", e.g. "scene.pvis: checksum mismatch (expected 0x..., found 0x...)".
struct VisibilityFileError : std::runtime_error {
    VisibilityFileError(VisibilityFileStatus s, const std::string& message)
        : std::runtime_error(message), status(s) {}
    VisibilityFileStatus status;
};

inline constexpr uint64_t kShardFlag = 1;

// The settings that shape the trees besides the scene (sceneHash mixes them in), as a shard
// states them so that a mismatch can be named.
struct VisibilitySettings {
    uint64_t maxLpSolves = 0;
    double patchFraction = 0;
    bool mergeLeaves = false, quadricPruning = false;
    uint32_t builderRevision = 0;
    bool operator==(const VisibilitySettings&) const = default;
};
VisibilitySettings visibilitySettings(const VisibilityStore::Options& options);
// "" when equal, else what differs: "--max-lp-solves 40 here, 10000 there" (one clause each).
std::string settingsDifference(const VisibilitySettings& here, const VisibilitySettings& there);

struct VisibilityShard {
    uint32_t index = 0, count = 1;
    uint64_t pairTotal = 0;  // every pair of the scene (everyPairKey), for the merge's count
    VisibilitySettings settings;
};

// The file names of the shards: "OUT.rank-00003-of-00064" for path OUT; shardPaths lists those
// present for OUT (any count: the shards of earlier runs too), sorted by name.
std::filesystem::path shardPath(const std::filesystem::path& output, uint32_t index,
                                uint32_t count);
std::vector<std::filesystem::path> shardPaths(const std::filesystem::path& output);

struct VisibilityFileWriteOptions {
    bool stats = true;                     // store each tree's BuildStats
    std::optional<VisibilityShard> shard;  // write a shard's header (settings from the store)
    // Test hook: the write fails (throws) after this many bytes reached the temporary file,
    // standing in for a full disk or an I/O error in the middle of the write.
    size_t failAfterBytes = SIZE_MAX;
};

// Writes every published tree of `store` (a snapshot) tied to sceneHash(store.scene(),
// store.options()). Returns the file's size in bytes. Throws VisibilityFileError (WriteFailed).
size_t writeVisibilityFile(const std::filesystem::path& path, const VisibilityStore& store,
                           const VisibilityFileWriteOptions& options = {});

// Reads `path`, checks it against store.scene() and store.options(), and adds its trees to the
// store (keys already present keep their tree). Returns the number of trees in the file. Throws
// VisibilityFileError (Missing, Unreadable, Corrupt or Stale); the store is unchanged then.
size_t readVisibilityFile(const std::filesystem::path& path, VisibilityStore& store);

// What a file's header says, checked without a scene: magic, version, sizes, checksum, flags (the
// merge, which copies records, and the cluster's shards, whose keys rank 0 lists).
struct VisibilityFileHeader {
    uint64_t sceneHash = 0;
    uint64_t treeCount = 0;
    size_t payloadBegin = 0, payloadEnd = 0;  // the records' bytes
    std::optional<VisibilityShard> shard;
};
// Throws VisibilityFileError (Corrupt) "NAME: problem".
VisibilityFileHeader inspectVisibilityFile(std::span<const unsigned char> bytes,
                                           const std::string& name);
// The key and size in bytes of the tree record at `offset` (before `end`), its counts checked
// against the bytes left but not against a scene. Throws VisibilityFileError (Corrupt) "WHERE:
// problem".
struct TreeRecordExtent {
    PairKey key;
    size_t size = 0;
};
TreeRecordExtent treeRecordAt(std::span<const unsigned char> bytes, size_t offset, size_t end,
                              const std::string& where);
// The keys a file or shard holds (in file order: increasing), checked as inspectVisibilityFile
// does and against `sceneHash`; the trees are not read into memory. Throws VisibilityFileError
// as readVisibilityFile does (Missing, Unreadable, Corrupt, Stale).
std::vector<PairKey> visibilityFileKeys(const std::filesystem::path& path, uint64_t sceneHash);
// The 48 header bytes of a whole file (not a shard) with these fields.
std::vector<unsigned char> visibilityFileHeaderBytes(uint64_t sceneHash, uint64_t treeCount,
                                                     uint64_t payloadBytes);

// Trees in transit between processes (the cluster's precompute, engine/cluster/): the published
// trees of `keys` (those the store holds, in the order given) as a u64 count followed by their
// records in the file's own record format, with their build stats: the one encoding of a tree,
// so that the trees a rank receives write the same bytes as the trees it builds.
std::vector<unsigned char> encodeTreeRecords(const VisibilityStore& store,
                                             std::span<const PairKey> keys);
// Reads what encodeTreeRecords wrote, validates every record as readVisibilityFile does (against
// store.scene() and its patches), and adds the trees to the store (keys already present keep
// theirs). Returns the number of trees decoded. Throws VisibilityFileError (Corrupt, its message
// starting with `source`, e.g. "rank 2"); the store is unchanged then.
size_t decodeTreeRecords(std::span<const unsigned char> bytes, VisibilityStore& store,
                         const std::string& source);

}  // namespace penumbra
