#include "engine/io/visibility_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "engine/io/atomic_file.h"
#include "engine/io/finite_output.h"
#include "engine/io/mapped_file.h"
#include "engine/io/text_input.h"
#include "engine/precompute/scene_hash.h"
#include "engine/scene/hash64.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

constexpr std::array<unsigned char, 8> kMagic = {'P', 'E', 'N', 'U', 'M', 'V', 'I', 'S'};
constexpr size_t kHeaderBytes = 48;
constexpr size_t kShardHeaderBytes = 88;
constexpr size_t kTrailerBytes = 8;
// Fixed part of a tree record: 5 u32 + u8 + u8 + u16 + 4 u32.
constexpr size_t kRecordFixedBytes = 5 * 4 + 1 + 1 + 2 + 5 * 4;
constexpr size_t kNodeBytes = 16;
constexpr size_t kStatsBytes = 3 * 4 + 8 * 8;
constexpr size_t kMaxReasonBytes = 1024;

std::string hex(uint64_t v) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "0x%016llx", static_cast<unsigned long long>(v));
    return buf;
}

// --- writing ---------------------------------------------------------------------------------

class ByteWriter {
  public:
    void u8(uint8_t v) { bytes_.push_back(v); }
    void u16(uint16_t v) { put(v, 2); }
    void u32(uint32_t v) { put(v, 4); }
    void u64(uint64_t v) { put(v, 8); }
    void f64(double v) { put(std::bit_cast<uint64_t>(v), 8); }
    void text(std::string_view s) { bytes_.insert(bytes_.end(), s.begin(), s.end()); }
    // resize + memcpy rather than insert: GCC 12 warns falsely (-Wstringop-overflow) about
    // vector<unsigned char>::insert once this is inlined into a larger unit.
    void raw(std::span<const unsigned char> s) {
        const size_t at = bytes_.size();
        bytes_.resize(at + s.size());
        if (!s.empty()) std::memcpy(bytes_.data() + at, s.data(), s.size());
    }
    void patchU64(size_t at, uint64_t v) {
        for (int k = 0; k < 8; ++k) bytes_[at + k] = static_cast<unsigned char>(v >> (8 * k));
    }
    std::vector<unsigned char>& bytes() { return bytes_; }

  private:
    void put(uint64_t v, int n) {
        for (int k = 0; k < n; ++k) bytes_.push_back(static_cast<unsigned char>(v >> (8 * k)));
    }
    std::vector<unsigned char> bytes_;
};

// One tree record of the payload (the header's format comment): the one encoding of a tree, in the
// file and in the trees sent between processes (encodeTreeRecords).
void writeRecord(ByteWriter& w, const PairKey& key, const PairRecord& record, bool withStats) {
    const vis::HistoryTree& t = record.tree;
    w.u32(key.receiver);
    w.u32(key.patch);
    w.u32(key.lightFace);
    w.u32(t.receiver);
    w.u32(t.light);
    w.u8(static_cast<uint8_t>(t.kind));
    w.u8(withStats ? 1 : 0);
    w.u16(static_cast<uint16_t>(std::min(t.why.size(), kMaxReasonBytes)));
    w.u32(t.meshVertexCount);
    w.u32(static_cast<uint32_t>(t.nodes.size()));
    w.u32(static_cast<uint32_t>(t.occluders.size()));
    w.u32(static_cast<uint32_t>(t.nodeOccluder.size()));
    w.u32(static_cast<uint32_t>(t.deferred.size()));
    w.text(t.why.substr(0, kMaxReasonBytes));
    for (const vis::HistoryNode& n : t.nodes) {
        w.u32(n.v0);
        w.u32(n.v1);
        w.u32(n.child[0]);
        w.u32(n.child[1]);
    }
    for (uint32_t f : t.occluders) w.u32(f);
    for (uint32_t f : t.nodeOccluder) w.u32(f);
    for (const vis::DeferredOccluder& d : t.deferred) w.u32(d.face);
    if (withStats) {
        const vis::BuildStats& s = record.stats;
        w.u32(s.occludersInShaft);
        w.u32(s.occludersInserted);
        w.u32(s.occludersDeferred);
        for (uint64_t v : {s.classifications, s.lpSolves, s.uncertain, s.exactCertificates,
                           s.prunedSplits, s.realLineTests, s.realLineWitness, s.mergedLeaves})
            w.u64(v);
    }
}

void writeHeader(ByteWriter& w, uint64_t hash, uint64_t treeCount, uint64_t payloadBytes,
                 const std::optional<VisibilityShard>& shard) {
    w.raw(kMagic);
    w.u32(kVisibilityFileVersion);
    w.u32(static_cast<uint32_t>(shard ? kShardHeaderBytes : kHeaderBytes));
    w.u64(hash);
    w.u64(treeCount);
    w.u64(payloadBytes);
    w.u64(shard ? kShardFlag : 0);
    if (!shard) return;
    w.u32(shard->index);
    w.u32(shard->count);
    w.u64(shard->pairTotal);
    const VisibilitySettings& v = shard->settings;
    w.u64(v.maxLpSolves);
    w.f64(v.patchFraction);
    w.u8(v.mergeLeaves ? 1 : 0);
    w.u8(v.quadricPruning ? 1 : 0);
    w.u16(0);
    w.u32(v.builderRevision);
}

std::vector<unsigned char> serialize(const VisibilityStore& store, bool withStats,
                                     std::optional<VisibilityShard> shard) {
    std::vector<std::pair<PairKey, const PairRecord*>> trees;
    // The refined sub-patches' trees are the render's cache (PatchLayout::refine): only the
    // patches' own trees are kept.
    store.forEach([&](const PairKey& k, const PairRecord& r) {
        if (PatchLayout::refineLevel(k) == 0) trees.emplace_back(k, &r);
    });
    std::sort(trees.begin(), trees.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });

    ByteWriter w;
    if (shard) shard->settings = visibilitySettings(store.options());
    writeHeader(w, sceneHash(store.scene(), store.options()), trees.size(), 0, shard);
    const size_t headerBytes = w.bytes().size();
    for (const auto& [key, record] : trees) writeRecord(w, key, *record, withStats);
    w.patchU64(32, w.bytes().size() - headerBytes);  // the payload size
    Hash64 h;
    h.addBytes(w.bytes());
    w.u64(h.value());
    return std::move(w.bytes());
}

// --- reading ---------------------------------------------------------------------------------

// Thrown while parsing; becomes VisibilityFileError(Corrupt) with the file name in front.
struct Corrupt : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class ByteReader {
  public:
    ByteReader(std::span<const unsigned char> bytes, size_t offset) : b_(bytes), at_(offset) {}
    size_t offset() const { return at_; }
    size_t left() const { return b_.size() - at_; }
    void need(size_t n, const char* what) const {
        if (n > left())
            throw Corrupt(std::string("truncated: ") + what + " at byte " + std::to_string(at_) +
                          " needs " + std::to_string(n) + " bytes, " + std::to_string(left()) +
                          " left");
    }
    uint8_t u8() { return static_cast<uint8_t>(get(1)); }
    uint16_t u16() { return static_cast<uint16_t>(get(2)); }
    uint32_t u32() { return static_cast<uint32_t>(get(4)); }
    uint64_t u64() { return get(8); }
    double f64() { return std::bit_cast<double>(get(8)); }
    std::string_view text(size_t n) {
        need(n, "text");
        std::string_view s(reinterpret_cast<const char*>(b_.data() + at_), n);
        at_ += n;
        return s;
    }

  private:
    uint64_t get(int n) {
        need(static_cast<size_t>(n), "a field");
        uint64_t v = 0;
        for (int k = 0; k < n; ++k) v |= static_cast<uint64_t>(b_[at_ + k]) << (8 * k);
        at_ += static_cast<size_t>(n);
        return v;
    }
    std::span<const unsigned char> b_;
    size_t at_;
};

std::string_view canonicalReason(std::string_view text) {
    for (std::string_view known : vis::knownReasons())
        if (known == text) return known;
    return {};
}

// Structural checks of one tree against the scene (see the header for the list).
void validateTree(const PairKey& key, const vis::HistoryTree& t, const VisibilityStore& store,
                  const std::string& where) {
    const Scene& scene = store.scene();
    const uint32_t faces = scene.faceCount();
    auto fail = [&](const std::string& what) { throw Corrupt(where + ": " + what); };
    if (key.receiver >= faces || key.lightFace >= faces)
        fail("face out of range (" + std::to_string(faces) + " faces)");
    if (key.receiver == key.lightFace) fail("receiver and light are the same face");
    if (t.receiver != key.receiver || t.light != key.lightFace)
        fail("tree faces (" + std::to_string(t.receiver) + ", " + std::to_string(t.light) +
             ") differ from its key");
    // (A refined sub-patch's key, as the cluster's render sends them, is checked against the
    // layout's refinements when its region is taken: parseRecords.)
    const size_t patches = std::max<size_t>(store.layout().patches(key.receiver).patches.size(), 1);
    if (PatchLayout::refineLevel(key) == 0 && key.patch >= patches)
        fail("patch out of range (the receiver has " + std::to_string(patches) + ")");
    if (t.meshVertexCount != scene.mesh.vertices.size())
        fail("mesh vertex count " + std::to_string(t.meshVertexCount) + " (the scene has " +
             std::to_string(scene.mesh.vertices.size()) + ")");
    const bool penumbra = t.kind == vis::PairKind::Penumbra;
    if (penumbra && t.nodes.empty() && t.deferred.empty())
        fail("a penumbra tree without nodes or deferred occluders");
    if (!penumbra && (!t.nodes.empty() || !t.deferred.empty()))
        fail(std::string(vis::toString(t.kind)) + " pair with nodes or deferred occluders");
    if (t.kind == vis::PairKind::BackFacing && !t.occluders.empty())
        fail("back-facing pair with occluders");
    if (!t.nodeOccluder.empty() && t.nodeOccluder.size() != t.nodes.size())
        fail("node occluder count " + std::to_string(t.nodeOccluder.size()) + " for " +
             std::to_string(t.nodes.size()) + " nodes");
    for (uint32_t f : t.nodeOccluder)
        if (f >= faces) fail("node occluder face " + std::to_string(f) + " out of range");
    for (size_t i = 0; i < t.occluders.size(); ++i) {
        const uint32_t f = t.occluders[i];
        const std::string what = "occluder " + std::to_string(i);
        if (f >= faces) fail(what + ": face " + std::to_string(f) + " out of range");
        if (f == key.receiver || f == key.lightFace)
            fail(what + ": the receiver or the light itself");
    }
    for (size_t i = 0; i < t.deferred.size(); ++i) {
        const vis::DeferredOccluder& d = t.deferred[i];
        const std::string what = "deferred occluder " + std::to_string(i);
        if (d.face >= faces) fail(what + ": face " + std::to_string(d.face) + " out of range");
        if (d.face == key.receiver || d.face == key.lightFace)
            fail(what + ": the receiver or the light itself");
    }
    const auto n = static_cast<uint32_t>(t.nodes.size());
    std::vector<uint32_t> parents(n, 0), depth(n, 1);
    for (uint32_t i = 0; i < n; ++i) {
        const vis::HistoryNode& node = t.nodes[i];
        if (vis::isClipEdge(node.v0)) {
            if ((node.v0 & ~vis::kClipEdge) >= faces ||
                (node.v1 != vis::kReceiverPlaneEdge && node.v1 != vis::kLightPlaneEdge))
                fail("node " + std::to_string(i) + " has a chord of an unknown face or plane");
        } else if (node.v0 >= t.meshVertexCount || node.v1 >= t.meshVertexCount) {
            fail("node " + std::to_string(i) + " uses a vertex id out of range");
        }
        for (uint32_t c : node.child) {
            if (vis::isLeaf(c)) continue;
            // Nodes are stored parent first: a child index is always larger than its parent's.
            if (c <= i || c >= n)
                fail("node " + std::to_string(i) + " has child " + std::to_string(c) +
                     " (must be a leaf or a later node of " + std::to_string(n) + ")");
            if (++parents[c] > 1) fail("node " + std::to_string(c) + " has two parents");
            depth[c] = depth[i] + 1;
            if (depth[c] > kMaxTreeDepth)
                fail("deeper than " + std::to_string(kMaxTreeDepth) + " levels");
        }
    }
    for (uint32_t i = 1; i < n; ++i)
        if (parents[i] == 0) fail("node " + std::to_string(i) + " is unreachable");
}

struct ParsedTree {
    PairKey key;
    PairRecord record;
};

// The header and the file as a whole (size, checksum, flags), without a scene.
VisibilityFileHeader inspectHeader(std::span<const unsigned char> bytes) {
    if (bytes.size() < kHeaderBytes + kTrailerBytes)
        throw Corrupt("truncated: " + std::to_string(bytes.size()) + " bytes, not even a header");
    if (!std::equal(kMagic.begin(), kMagic.end(), bytes.begin()))
        throw Corrupt("not a penumbra visibility file (bad magic)");
    ByteReader r(bytes, kMagic.size());
    const uint32_t version = r.u32();
    if (version != kVisibilityFileVersion)
        throw Corrupt("format version " + std::to_string(version) + " (this program reads " +
                      std::to_string(kVisibilityFileVersion) + ")");
    const uint32_t headerBytes = r.u32();
    if (headerBytes != kHeaderBytes && headerBytes != kShardHeaderBytes)
        throw Corrupt("header size " + std::to_string(headerBytes) + " (expected " +
                      std::to_string(kHeaderBytes) + ", or " + std::to_string(kShardHeaderBytes) +
                      " for a shard)");
    if (bytes.size() < headerBytes + kTrailerBytes)
        throw Corrupt("truncated: " + std::to_string(bytes.size()) + " bytes, not even a header");
    VisibilityFileHeader header;
    header.sceneHash = r.u64();
    header.treeCount = r.u64();
    const uint64_t payloadBytes = r.u64();
    const uint64_t flags = r.u64();
    const uint64_t expectedSize = bytes.size() - headerBytes - kTrailerBytes;
    if (payloadBytes != expectedSize)
        throw Corrupt((payloadBytes > expectedSize ? "truncated: " : "size mismatch: ") +
                      std::string("header says ") + std::to_string(payloadBytes) +
                      " payload bytes, the file holds " + std::to_string(expectedSize));
    header.payloadBegin = headerBytes;
    header.payloadEnd = headerBytes + payloadBytes;
    Hash64 h;
    h.addBytes(bytes.first(header.payloadEnd));
    const uint64_t stored = ByteReader(bytes, header.payloadEnd).u64();
    if (h.value() != stored)
        throw Corrupt("checksum mismatch (expected " + hex(stored) + ", found " + hex(h.value()) +
                      ")");
    const bool shard = flags == kShardFlag;
    if (flags != 0 && !shard) throw Corrupt("unknown flags " + hex(flags));
    if (shard != (headerBytes == kShardHeaderBytes))
        throw Corrupt("header size " + std::to_string(headerBytes) + " with flags " + hex(flags));
    if (shard) {
        VisibilityShard& s = header.shard.emplace();
        s.index = r.u32();
        s.count = r.u32();
        s.pairTotal = r.u64();
        s.settings.maxLpSolves = r.u64();
        s.settings.patchFraction = r.f64();
        s.settings.mergeLeaves = r.u8() != 0;
        s.settings.quadricPruning = r.u8() != 0;
        r.u16();
        s.settings.builderRevision = r.u32();
        if (s.count == 0 || s.index >= s.count)
            throw Corrupt("shard " + std::to_string(s.index) + " of " + std::to_string(s.count));
    }
    if (header.treeCount > payloadBytes / kRecordFixedBytes)
        throw Corrupt("tree count " + std::to_string(header.treeCount) + " does not fit in " +
                      std::to_string(payloadBytes) + " payload bytes");
    return header;
}

// inspectHeader, then the scene hash, so that a stale file is told apart from a corrupt one only
// when it is intact.
VisibilityFileHeader parseHeader(std::span<const unsigned char> bytes,
                                 const VisibilityStore& store) {
    const VisibilityFileHeader header = inspectHeader(bytes);
    const uint64_t current = sceneHash(store.scene(), store.options());
    if (header.sceneHash != current)
        throw VisibilityFileError(VisibilityFileStatus::Stale,
                                  "made for another scene or other build settings (scene hash " +
                                      hex(header.sceneHash) + " in the file, " + hex(current) +
                                      " now)");
    return header;
}

void readStats(ByteReader& p, vis::BuildStats& s) {
    s.occludersInShaft = p.u32();
    s.occludersInserted = p.u32();
    s.occludersDeferred = p.u32();
    for (uint64_t* v : {&s.classifications, &s.lpSolves, &s.uncertain, &s.exactCertificates,
                        &s.prunedSplits, &s.realLineTests, &s.realLineWitness, &s.mergedLeaves})
        *v = p.u64();
    s.seconds = 0;  // not in the file (visibility_file.h)
}

// The bytes of a record after its fixed part, from its counts.
uint64_t recordBodyBytes(uint16_t reasonBytes, uint32_t nodes, uint32_t inserted,
                         uint32_t occluders, uint32_t deferred, bool hasStats) {
    return uint64_t{reasonBytes} + uint64_t{nodes} * kNodeBytes + uint64_t{inserted} * 4 +
           uint64_t{occluders} * 4 + uint64_t{deferred} * 4 + (hasStats ? kStatsBytes : 0);
}

// One tree record, its fields checked on their own; validateTree checks it against the scene.
ParsedTree parseTree(ByteReader& p, const std::string& where) {
    p.need(kRecordFixedBytes, "a tree record");
    ParsedTree pt;
    PairKey& key = pt.key;
    vis::HistoryTree& t = pt.record.tree;
    key.receiver = p.u32();
    key.patch = p.u32();
    key.lightFace = p.u32();
    t.receiver = p.u32();
    t.light = p.u32();
    const uint8_t kind = p.u8();
    const uint8_t hasStats = p.u8();
    const uint16_t reasonBytes = p.u16();
    t.meshVertexCount = p.u32();
    const uint32_t nodes = p.u32(), inserted = p.u32(), occluders = p.u32(), deferred = p.u32();
    if (kind >= vis::kPairKindCount)
        throw Corrupt(where + ": unknown pair kind " + std::to_string(kind));
    t.kind = static_cast<vis::PairKind>(kind);
    if (hasStats > 1) throw Corrupt(where + ": bad stats flag " + std::to_string(hasStats));
    if (reasonBytes > kMaxReasonBytes) throw Corrupt(where + ": reason text too long");
    // Every count against the bytes left before anything is allocated.
    const uint64_t need =
        recordBodyBytes(reasonBytes, nodes, inserted, occluders, deferred, hasStats != 0);
    if (need > p.left())
        throw Corrupt(where + ": truncated or bad counts (" + std::to_string(nodes) + " nodes, " +
                      std::to_string(inserted) + " occluders, " + std::to_string(occluders) +
                      " node occluders need " + std::to_string(need) + " bytes, " +
                      std::to_string(p.left()) + " left)");
    const std::string_view reason = p.text(reasonBytes);
    t.why = canonicalReason(reason);
    if (t.why.empty())
        throw Corrupt(where + ": unknown reason \"" + std::string(reason.substr(0, 80)) + "\"");
    t.nodes.resize(nodes);
    for (vis::HistoryNode& n : t.nodes) {
        n.v0 = p.u32();
        n.v1 = p.u32();
        n.child[0] = p.u32();
        n.child[1] = p.u32();
    }
    t.occluders.resize(inserted);
    for (uint32_t& f : t.occluders) f = p.u32();
    t.nodeOccluder.resize(occluders);
    for (uint32_t& f : t.nodeOccluder) f = p.u32();
    t.deferred.resize(deferred);
    for (vis::DeferredOccluder& d : t.deferred) d.face = p.u32();
    if (hasStats) readStats(p, pt.record.stats);
    return pt;
}

// `count` tree records from p, each parsed, validated against the store's scene and prepared for
// queries; no key twice.
std::vector<ParsedTree> parseRecords(ByteReader& p, uint64_t count, const VisibilityStore& store) {
    std::vector<ParsedTree> out;
    out.reserve(static_cast<size_t>(count));
    std::set<PairKey> seen;
    for (uint64_t i = 0; i < count; ++i) {
        const std::string where =
            "tree " + std::to_string(i) + " (byte " + std::to_string(p.offset()) + ")";
        ParsedTree pt = parseTree(p, where);
        validateTree(pt.key, pt.record.tree, store, where);
        if (PatchLayout::refineLevel(pt.key) == 0) {
            vis::prepareForQueries(store.scene().mesh, pt.record.tree,
                                   store.layout().patches(pt.key.receiver).patches[pt.key.patch]);
        } else {
            std::vector<Vec3> region;
            try {
                region = store.layout().region(pt.key);
            } catch (const std::out_of_range&) {
                throw Corrupt(where + ": a sub-patch of a pair not refined here");
            }
            vis::prepareForQueries(store.scene().mesh, pt.record.tree, region);
        }
        if (!seen.insert(pt.key).second) throw Corrupt(where + ": a second tree for the same pair");
        out.push_back(std::move(pt));
    }
    if (p.left() != 0)
        throw Corrupt(std::to_string(p.left()) + " bytes left over after the last tree");
    return out;
}

std::vector<ParsedTree> parse(std::span<const unsigned char> bytes, const VisibilityStore& store) {
    const VisibilityFileHeader header = parseHeader(bytes, store);
    ByteReader p(bytes.first(header.payloadEnd), header.payloadBegin);
    return parseRecords(p, header.treeCount, store);
}

}  // namespace

const char* toString(VisibilityFileStatus status) {
    switch (status) {
        case VisibilityFileStatus::Missing:
            return "missing";
        case VisibilityFileStatus::Unreadable:
            return "unreadable";
        case VisibilityFileStatus::Corrupt:
            return "corrupt";
        case VisibilityFileStatus::Stale:
            return "stale";
        case VisibilityFileStatus::WriteFailed:
            return "write failed";
    }
    return "?";
}

size_t writeVisibilityFile(const fs::path& path, const VisibilityStore& store,
                           const VisibilityFileWriteOptions& options) {
    const std::string name = path.string();
    const std::vector<unsigned char> bytes = serialize(store, options.stats, options.shard);
    try {
        writeFileAtomically(
            path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
            AtomicWriteOptions{options.failAfterBytes});
    } catch (const AtomicWriteError& e) {
        throw VisibilityFileError(VisibilityFileStatus::WriteFailed, e.what());
    }
    return bytes.size();
}

size_t readVisibilityFile(const fs::path& path, VisibilityStore& store) {
    const std::string name = path.string();
    std::error_code ec;
    if (!fs::exists(fs::status(path, ec)))
        throw VisibilityFileError(VisibilityFileStatus::Missing, name + ": no such file");
    std::vector<unsigned char> bytes;
    try {
        bytes = readWholeFileBytes(path);  // a directory too: "Is a directory"
    } catch (const FileReadError& e) {
        throw VisibilityFileError(VisibilityFileStatus::Unreadable, e.what());
    }
    std::vector<ParsedTree> trees;
    try {
        trees = parse(bytes, store);
    } catch (const Corrupt& e) {
        throw VisibilityFileError(VisibilityFileStatus::Corrupt, name + ": " + e.what());
    } catch (const VisibilityFileError& e) {
        throw VisibilityFileError(e.status, name + ": " + e.what());
    }
    for (ParsedTree& t : trees) store.insert(t.key, std::move(t.record));
    return trees.size();
}

VisibilitySettings visibilitySettings(const VisibilityStore::Options& options) {
    VisibilitySettings v;
    v.maxLpSolves = options.build.maxLpSolves;
    v.patchFraction = options.patchFraction;
    v.mergeLeaves = options.build.mergeLeaves;
    v.quadricPruning = options.build.quadricPruning;
    v.builderRevision = kTreeBuilderRevision;
    return v;
}

std::string settingsDifference(const VisibilitySettings& here, const VisibilitySettings& there) {
    std::string out;
    const auto clause = [&](const std::string& name, const std::string& a, const std::string& b) {
        if (a == b) return;
        out += (out.empty() ? "" : ", ") + name + " " + a + " here, " + b + " there";
    };
    const auto number = [](double v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.17g", v);
        return std::string(buf);
    };
    const auto onOff = [](bool v) { return std::string(v ? "on" : "off"); };
    clause("--max-lp-solves", std::to_string(here.maxLpSolves), std::to_string(there.maxLpSolves));
    clause("--patch-fraction", number(here.patchFraction), number(there.patchFraction));
    clause("leaf merging", onOff(here.mergeLeaves), onOff(there.mergeLeaves));
    clause("quadric pruning", onOff(here.quadricPruning), onOff(there.quadricPruning));
    clause("tree builder revision", std::to_string(here.builderRevision),
           std::to_string(there.builderRevision));
    return out;
}

fs::path shardPath(const fs::path& output, uint32_t index, uint32_t count) {
    char suffix[48];
    std::snprintf(suffix, sizeof suffix, ".rank-%05u-of-%05u", index, count);
    return fs::path(output.string() + suffix);
}

std::vector<fs::path> shardPaths(const fs::path& output) {
    const fs::path dir = output.parent_path().empty() ? fs::path(".") : output.parent_path();
    const std::string prefix = output.filename().string() + ".rank-";
    std::vector<fs::path> out;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        unsigned index = 0, count = 0;
        char tail = 0;
        if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
        if (std::sscanf(name.c_str() + prefix.size(), "%5u-of-%5u%c", &index, &count, &tail) != 2)
            continue;
        if (name != shardPath(output, index, count).filename().string()) continue;
        out.push_back(output.parent_path() / name);
    }
    std::sort(out.begin(), out.end());
    return out;
}

VisibilityFileHeader inspectVisibilityFile(std::span<const unsigned char> bytes,
                                           const std::string& name) {
    try {
        return inspectHeader(bytes);
    } catch (const Corrupt& e) {
        throw VisibilityFileError(VisibilityFileStatus::Corrupt, name + ": " + e.what());
    }
}

TreeRecordExtent treeRecordAt(std::span<const unsigned char> bytes, size_t offset, size_t end,
                              const std::string& where) {
    try {
        ByteReader p(bytes.first(end), offset);
        p.need(kRecordFixedBytes, "a tree record");
        TreeRecordExtent r;
        r.key.receiver = p.u32();
        r.key.patch = p.u32();
        r.key.lightFace = p.u32();
        p.u32();
        p.u32();
        p.u8();
        const uint8_t hasStats = p.u8();
        const uint16_t reasonBytes = p.u16();
        p.u32();
        const uint32_t nodes = p.u32(), inserted = p.u32(), occluders = p.u32(), deferred = p.u32();
        if (hasStats > 1) throw Corrupt("bad stats flag " + std::to_string(hasStats));
        const uint64_t need =
            recordBodyBytes(reasonBytes, nodes, inserted, occluders, deferred, hasStats != 0);
        if (need > p.left())
            throw Corrupt("truncated or bad counts (" + std::to_string(need) +
                          " bytes after the "
                          "record's fixed part, " +
                          std::to_string(p.left()) + " left)");
        r.size = kRecordFixedBytes + static_cast<size_t>(need);
        return r;
    } catch (const Corrupt& e) {
        throw VisibilityFileError(VisibilityFileStatus::Corrupt, where + ": " + e.what());
    }
}

std::vector<PairKey> visibilityFileKeys(const fs::path& path, uint64_t hash) {
    const std::string name = path.string();
    std::error_code ec;
    if (!fs::exists(fs::status(path, ec)))
        throw VisibilityFileError(VisibilityFileStatus::Missing, name + ": no such file");
    std::optional<MappedFile> file;
    try {
        file.emplace(path);
    } catch (const FileReadError& e) {
        throw VisibilityFileError(VisibilityFileStatus::Unreadable, e.what());
    }
    const std::span<const unsigned char> bytes = file->bytes();
    const VisibilityFileHeader header = inspectVisibilityFile(bytes, name);
    if (header.sceneHash != hash)
        throw VisibilityFileError(VisibilityFileStatus::Stale,
                                  name +
                                      ": made for another scene or other build settings (scene "
                                      "hash " +
                                      hex(header.sceneHash) + " in the file, " + hex(hash) +
                                      " now)");
    std::vector<PairKey> keys;
    keys.reserve(static_cast<size_t>(header.treeCount));
    size_t at = header.payloadBegin;
    for (uint64_t i = 0; i < header.treeCount; ++i) {
        const std::string where =
            name + ": tree " + std::to_string(i) + " (byte " + std::to_string(at) + ")";
        const TreeRecordExtent r = treeRecordAt(bytes, at, header.payloadEnd, where);
        if (!keys.empty() && !(keys.back() < r.key))
            throw VisibilityFileError(VisibilityFileStatus::Corrupt,
                                      where + ": keys out of order (a file is sorted by key)");
        keys.push_back(r.key);
        at += r.size;
    }
    if (at != header.payloadEnd)
        throw VisibilityFileError(VisibilityFileStatus::Corrupt,
                                  name + ": " + std::to_string(header.payloadEnd - at) +
                                      " bytes left over after the last tree");
    return keys;
}

std::vector<unsigned char> visibilityFileHeaderBytes(uint64_t hash, uint64_t treeCount,
                                                     uint64_t payloadBytes) {
    ByteWriter w;
    writeHeader(w, hash, treeCount, payloadBytes, std::nullopt);
    return std::move(w.bytes());
}

std::vector<unsigned char> encodeTreeRecords(const VisibilityStore& store,
                                             std::span<const PairKey> keys) {
    ByteWriter w;
    w.u64(0);  // the count, patched below
    uint64_t count = 0;
    for (const PairKey& key : keys)
        if (const PairRecord* record = store.find(key)) {
            writeRecord(w, key, *record, true);
            ++count;
        }
    w.patchU64(0, count);
    return std::move(w.bytes());
}

size_t decodeTreeRecords(std::span<const unsigned char> bytes, VisibilityStore& store,
                         const std::string& source) {
    std::vector<ParsedTree> trees;
    try {
        ByteReader p(bytes, 0);
        const uint64_t count = p.u64();
        if (count > p.left() / kRecordFixedBytes)
            throw Corrupt("tree count " + std::to_string(count) + " does not fit in " +
                          std::to_string(p.left()) + " bytes");
        trees = parseRecords(p, count, store);
    } catch (const Corrupt& e) {
        throw VisibilityFileError(VisibilityFileStatus::Corrupt, source + ": " + e.what());
    }
    for (ParsedTree& t : trees) store.insert(t.key, std::move(t.record));
    return trees.size();
}

}  // namespace penumbra
