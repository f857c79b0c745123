// The visibility file: round trip (trees equal field by field, FPQuery results equal those of
// freshly built trees), corruption of any byte and truncation detected, a changed scene reads as
// stale, content errors behind a valid checksum rejected, interrupted writes leave the old file.
#include "engine/io/visibility_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "engine/precompute/scene_hash.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/scene/hash64.h"
#include "engine/scene/procedural_scenes.h"
#include "tests/support/random_points.h"
#include "tests/support/test_scale.h"
#include "tests/support/tree_reference.h"
#include "visibility/fp_query/from_point_query.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;

class VisibilityFileTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               (std::string("penumbra_visfile_") + info->name() + "_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    static Bytes readBytes(const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    static void writeBytes(const fs::path& p, const Bytes& b) {
        // Unlink first: ext4 flushes a file truncated and rewritten in place on close
        // (auto_da_alloc), which makes the byte-by-byte tests wait on the disk.
        fs::remove(p);
        std::ofstream out(p, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    }
    std::vector<fs::path> filesInDir() const {
        std::vector<fs::path> out;
        for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename());
        std::sort(out.begin(), out.end());
        return out;
    }
    // The status readVisibilityFile reports for `path` (into a fresh store), or nullopt if it
    // reads fine; the message must name the file.
    static std::optional<VisibilityFileStatus> readStatus(
        const fs::path& path, const Scene& scene, std::string* message = nullptr,
        const VisibilityStore::Options& options = {}) {
        VisibilityStore store(scene, nullptr, options);
        try {
            readVisibilityFile(path, store);
        } catch (const VisibilityFileError& e) {
            EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
            EXPECT_EQ(store.treeCount(), 0u);  // all or nothing
            if (message) *message = e.what();
            return e.status;
        }
        return std::nullopt;
    }

    fs::path dir_;
};

// Every pair of the given receiver faces with the scene's lights, built through the store.
void buildFaces(VisibilityStore& store, const std::vector<uint32_t>& faces) {
    const Scene& s = store.scene();
    for (uint32_t f : faces)
        for (uint32_t l : s.lights) {
            if (l == f) continue;
            const size_t patches = std::max<size_t>(store.layout().patches(f).patches.size(), 1);
            for (uint32_t p = 0; p < patches; ++p) store.getOrBuild({f, p, l});
        }
}

TEST_F(VisibilityFileTest, RoundTripKeepsEveryFieldAndEveryQuery) {
    const Scene scene = makeStairs();
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    // A random sample of the faces other than the floor (face 0: many patches, seconds each).
    std::mt19937_64 rng(11);
    std::vector<uint32_t> faces;
    for (int i = 0; i < test::scaled(40); ++i)
        faces.push_back(1 + static_cast<uint32_t>(rng() % (scene.faceCount() - 1)));
    buildFaces(store, faces);
    ASSERT_GT(store.kindCounts()[static_cast<int>(vis::PairKind::Penumbra)], 5u);
    const fs::path file = dir_ / "stairs.pvis";
    const size_t size = writeVisibilityFile(file, store);
    EXPECT_EQ(fs::file_size(file), size);

    VisibilityStore loaded(scene);  // no BVH: nothing is built, everything comes from the file
    EXPECT_EQ(readVisibilityFile(file, loaded), store.treeCount());
    EXPECT_EQ(loaded.treeCount(), store.treeCount());
    EXPECT_EQ(loaded.bytes(), store.bytes());
    EXPECT_EQ(loaded.kindCounts(), store.kindCounts());
    const auto reasons = vis::knownReasons();
    size_t withChords = 0;
    store.forEach([&](const PairKey& k, const PairRecord& original) {
        const PairRecord* r = loaded.find(k);
        ASSERT_NE(r, nullptr);
        EXPECT_TRUE(test::sameTree(r->tree, original.tree));
        // `why` points to one of the builder's static strings.
        EXPECT_TRUE(std::any_of(reasons.begin(), reasons.end(), [&](std::string_view s) {
            return s.data() == r->tree.why.data();
        }));
        EXPECT_EQ(r->stats.classifications, original.stats.classifications);
        EXPECT_EQ(r->stats.lpSolves, original.stats.lpSolves);
        EXPECT_EQ(r->stats.occludersInShaft, original.stats.occludersInShaft);
        EXPECT_EQ(r->stats.seconds, 0.0);  // no time in the file (visibility_file.h)
        withChords += std::any_of(r->tree.nodes.begin(), r->tree.nodes.end(),
                                  [](const vis::HistoryNode& n) { return vis::isClipEdge(n.v0); });
    });
    EXPECT_GT(withChords, 0u);  // the chords of clipped occluders are exercised

    // FPQuery on the loaded trees against trees built afresh (no store, no BVH, no file).
    const uint32_t light = scene.lights[0];
    std::map<PairKey, vis::HistoryTree> fresh;
    int queried = 0, walked = 0;
    for (int i = 0; i < test::scaled(400); ++i) {
        const uint32_t f = faces[rng() % faces.size()];
        if (f == light) continue;
        const Vec3 x = test::randomPointOn(scene.mesh, f, rng);
        const PairKey key = loaded.layout().keyAt(f, x, light);
        const PairRecord* r = loaded.find(key);
        ASSERT_NE(r, nullptr);
        auto it = fresh.find(key);
        if (it == fresh.end()) it = fresh.emplace(key, test::referenceTree(store, key)).first;
        const vis::FromPointResult a = vis::fromPointQuery(scene.mesh, r->tree, x);
        const vis::FromPointResult b = vis::fromPointQuery(scene.mesh, it->second, x);
        EXPECT_EQ(a.fragments, b.fragments) << "face " << f << " point " << vis::toString(x);
        EXPECT_EQ(vis::traceNodes(a.trace), vis::traceNodes(b.trace));
        ++queried;
        walked += !a.fragments.empty() && !a.trace.empty();
    }
    EXPECT_GT(queried, test::scaled(400) / 2);
    EXPECT_GT(walked, 0);  // some queries walked a tree and saw light

    // Reading into a store that already holds trees keeps them and adds the rest.
    VisibilityStore partial(scene);
    const PairKey first = fresh.begin()->first;
    partial.insert(first, PairRecord{fresh.begin()->second, {}});
    EXPECT_EQ(readVisibilityFile(file, partial), store.treeCount());
    EXPECT_EQ(partial.treeCount(), store.treeCount());
}

// Partial trees (a small build budget) come back with their deferred occluders, boxes included,
// and answer every query as before.
TEST_F(VisibilityFileTest, RoundTripKeepsPartialTrees) {
    const Scene scene = makeStairs();
    VisibilityStore::Options options;
    options.build.maxLpSolves = 50;
    VisibilityStore store(scene, nullptr, options);
    std::mt19937_64 rng(5);
    std::vector<uint32_t> faces;
    for (int i = 0; i < std::max(16, test::scaled(30)); ++i)
        faces.push_back(1 + static_cast<uint32_t>(rng() % (scene.faceCount() - 1)));
    buildFaces(store, faces);
    ASSERT_GT(store.partialCount(), 2u);
    const fs::path file = dir_ / "partial.pvis";
    writeVisibilityFile(file, store);
    VisibilityStore loaded(scene, nullptr, options);
    EXPECT_EQ(readVisibilityFile(file, loaded), store.treeCount());
    EXPECT_EQ(loaded.partialCount(), store.partialCount());
    EXPECT_EQ(loaded.bytes(), store.bytes());
    store.forEach([&](const PairKey& k, const PairRecord& original) {
        const PairRecord* r = loaded.find(k);
        ASSERT_NE(r, nullptr);
        EXPECT_TRUE(test::sameTree(r->tree, original.tree));
        EXPECT_EQ(r->stats.occludersDeferred, original.stats.occludersDeferred);
    });
    int deferredQueries = 0;
    for (uint32_t f : faces) {
        for (int i = 0; i < 5; ++i) {
            const Vec3 x = test::randomPointOn(scene.mesh, f, rng);
            const PairKey key = loaded.layout().keyAt(f, x, scene.lights[0]);
            const PairRecord* a = loaded.find(key);
            const PairRecord* b = store.find(key);
            if (a == nullptr || b == nullptr) continue;
            const vis::FromPointResult qa = vis::fromPointQuery(scene.mesh, a->tree, x);
            const vis::FromPointResult qb = vis::fromPointQuery(scene.mesh, b->tree, x);
            EXPECT_EQ(qa.fragments, qb.fragments);
            deferredQueries += qa.deferredActive > 0;
        }
    }
    EXPECT_GT(deferredQueries, 0);  // some queries did clip deferred occluders
}

// A small file (grids, a few pairs) for the byte-level tests. Built with a small build budget so
// that it holds partial trees (deferred occluders) as well as complete ones.
class SmallFile : public VisibilityFileTest {
  protected:
    void SetUp() override {
        VisibilityFileTest::SetUp();
        scene_ = makeGrids();
        options_.build.maxLpSolves = 25;
        VisibilityStore store(scene_, nullptr, options_);
        const uint32_t light = scene_.lights[0];
        for (uint32_t f : {0u, 1u, 5u, 30u}) store.getOrBuild({f, 0, light});
        ASSERT_GT(store.kindCounts()[static_cast<int>(vis::PairKind::Penumbra)], 0u);
        ASSERT_GT(store.partialCount(), 0u);
        file_ = dir_ / "grids.pvis";
        writeVisibilityFile(file_, store);
        bytes_ = readBytes(file_);
    }
    // Rewrites the trailer so the checksum matches the (modified) contents.
    static void fixChecksum(Bytes& b) {
        Hash64 h;
        h.addBytes(std::span<const unsigned char>(b.data(), b.size() - 8));
        const uint64_t v = h.value();
        for (int k = 0; k < 8; ++k) b[b.size() - 8 + k] = static_cast<unsigned char>(v >> (8 * k));
    }
    static uint32_t u32At(const Bytes& b, size_t at) {
        uint32_t v = 0;
        for (int k = 0; k < 4; ++k) v |= uint32_t{b[at + k]} << (8 * k);
        return v;
    }
    static void setU32(Bytes& b, size_t at, uint32_t v) {
        for (int k = 0; k < 4; ++k) b[at + k] = static_cast<unsigned char>(v >> (8 * k));
    }
    // The documented layout of the record at `at`: its counts, and where its parts begin.
    struct Record {
        size_t at = 0, reasonAt = 0, nodesAt = 0, occludersAt = 0, deferredAt = 0, end = 0;
        uint32_t nodes = 0, occluders = 0, deferred = 0;
    };
    Record recordAt(size_t at) const {
        Record r;
        r.at = at;
        const uint8_t hasStats = bytes_[at + 21];
        const uint32_t reason = bytes_[at + 22] | (bytes_[at + 23] << 8);
        r.nodes = u32At(bytes_, at + 28);
        r.occluders = u32At(bytes_, at + 32);
        const uint32_t o = u32At(bytes_, at + 36);
        r.deferred = u32At(bytes_, at + 40);
        r.reasonAt = at + 44;
        r.nodesAt = r.reasonAt + reason;
        r.occludersAt = r.nodesAt + 16 * r.nodes;
        r.deferredAt = r.occludersAt + 4 * r.occluders + 4 * o;
        r.end = r.deferredAt + 4 * r.deferred + (hasStats ? 84 : 0);
        return r;
    }
    // The first record that satisfies `want`, read with the documented layout.
    template <typename Want>
    Record firstRecord(Want want, const char* what) const {
        for (size_t at = 48; at < bytes_.size() - 8;) {
            const Record r = recordAt(at);
            if (want(r)) return r;
            at = r.end;
        }
        ADD_FAILURE() << "no record with " << what;
        return recordAt(48);
    }
    size_t firstTreeWithNodes(uint32_t* nodes) const {
        const Record r = firstRecord([](const Record& x) { return x.nodes >= 2; }, "two nodes");
        *nodes = r.nodes;
        return r.at;
    }
    std::string statusOf(const Bytes& b, VisibilityFileStatus expected) {
        writeBytes(file_, b);
        std::string message;
        const auto s = readStatus(file_, scene_, &message, options_);
        EXPECT_TRUE(s.has_value());
        if (s) {
            EXPECT_EQ(*s, expected) << message;
        }
        return message;
    }

    Scene scene_;
    VisibilityStore::Options options_;
    fs::path file_;
    Bytes bytes_;
};

TEST_F(SmallFile, ReadsBackIntact) {
    EXPECT_EQ(readStatus(file_, scene_, nullptr, options_), std::nullopt);
    // The same file is stale for the default build budget (the budget shapes the trees).
    EXPECT_EQ(readStatus(file_, scene_), VisibilityFileStatus::Stale);
}

TEST_F(SmallFile, EveryFlippedByteIsDetected) {
    // Every position (the file is small), each with a different bit pattern.
    std::mt19937_64 rng(3);
    for (size_t i = 0; i < bytes_.size(); ++i) {
        Bytes b = bytes_;
        b[i] ^= static_cast<unsigned char>(1 + rng() % 255);
        writeBytes(file_, b);
        const auto s = readStatus(file_, scene_, nullptr, options_);
        ASSERT_TRUE(s.has_value()) << "flipped byte " << i << " of " << bytes_.size();
        EXPECT_EQ(*s, VisibilityFileStatus::Corrupt) << "byte " << i;
    }
    Bytes b = bytes_;
    b[100] ^= 0x10;
    const std::string m = statusOf(b, VisibilityFileStatus::Corrupt);
    EXPECT_NE(m.find("checksum mismatch (expected 0x"), std::string::npos) << m;
}

TEST_F(SmallFile, EveryTruncationIsDetected) {
    for (size_t n = 0; n < bytes_.size(); n += (n < 100 ? 1 : 7)) {
        writeBytes(file_, Bytes(bytes_.begin(), bytes_.begin() + n));
        const auto s = readStatus(file_, scene_, nullptr, options_);
        ASSERT_TRUE(s.has_value()) << "truncated to " << n;
        EXPECT_EQ(*s, VisibilityFileStatus::Corrupt);
    }
    Bytes longer = bytes_;
    longer.push_back(0);
    statusOf(longer, VisibilityFileStatus::Corrupt);
    const std::string m =
        statusOf(Bytes(bytes_.begin(), bytes_.end() - 1), VisibilityFileStatus::Corrupt);
    EXPECT_NE(m.find("truncated"), std::string::npos) << m;
}

TEST_F(SmallFile, ChangedSceneOrSettingsMakeItStale) {
    std::string message;
    Scene moved = scene_;
    moved.mesh.vertices[7].y = std::nextafter(moved.mesh.vertices[7].y, 1e300);  // one ulp
    ASSERT_EQ(readStatus(file_, moved, &message, options_), VisibilityFileStatus::Stale);
    EXPECT_NE(message.find("another scene"), std::string::npos) << message;

    Scene noLight = scene_;
    noLight.lights.clear();
    EXPECT_EQ(readStatus(file_, noLight, nullptr, options_), VisibilityFileStatus::Stale);

    VisibilityStore::Options other = options_;
    other.patchFraction = 0.5;
    VisibilityStore store(scene_, nullptr, other);
    EXPECT_NE(sceneHash(scene_, other), sceneHash(scene_, VisibilityStore::Options{}));
    try {
        readVisibilityFile(file_, store);
        ADD_FAILURE() << "read a file made with another patch fraction";
    } catch (const VisibilityFileError& e) {
        EXPECT_EQ(e.status, VisibilityFileStatus::Stale);
    }
    VisibilityStore::Options noMerge;
    noMerge.build.mergeLeaves = false;
    EXPECT_NE(sceneHash(scene_, noMerge), sceneHash(scene_, VisibilityStore::Options{}));
}

TEST_F(SmallFile, MissingFileAndNotAFile) {
    EXPECT_EQ(readStatus(dir_ / "nope.pvis", scene_), VisibilityFileStatus::Missing);
    EXPECT_EQ(readStatus(dir_, scene_), VisibilityFileStatus::Unreadable);
    Bytes text = {'h', 'e', 'l', 'l', 'o'};
    text.resize(200, ' ');
    const std::string m = statusOf(text, VisibilityFileStatus::Corrupt);
    EXPECT_NE(m.find("bad magic"), std::string::npos) << m;
}

// Content errors behind a valid checksum (a buggy or hostile writer) are caught by validation.
TEST_F(SmallFile, ContentErrorsBehindAValidChecksum) {
    uint32_t nodes = 0;
    const size_t rec = firstTreeWithNodes(&nodes);
    const size_t node0 = recordAt(rec).nodesAt;  // first node: v0, v1, child0, child1
    auto expectCorrupt = [&](Bytes b, const char* needle) {
        fixChecksum(b);
        const std::string m = statusOf(b, VisibilityFileStatus::Corrupt);
        EXPECT_NE(m.find(needle), std::string::npos) << m;
    };
    {
        Bytes b = bytes_;
        setU32(b, node0 + 8, nodes);  // child out of range
        expectCorrupt(b, "has child");
    }
    {
        Bytes b = bytes_;
        setU32(b, node0 + 8, 0);  // a cycle to itself
        expectCorrupt(b, "has child 0");
    }
    {
        Bytes b = bytes_;
        setU32(b, node0, 0x7FFFFFFF);  // vertex id out of range
        expectCorrupt(b, "vertex id out of range");
    }
    {
        Bytes b = bytes_;
        setU32(b, node0, vis::kClipEdge | 100000);  // a chord of a face out of range
        expectCorrupt(b, "chord of an unknown face or plane");
    }
    {
        Bytes b = bytes_;
        setU32(b, node0, vis::kClipEdge | 0);
        setU32(b, node0 + 4, 7);  // a chord of an unknown plane
        expectCorrupt(b, "chord of an unknown face or plane");
    }
    {
        Bytes b = bytes_;
        b[rec + 20] = 9;  // kind
        expectCorrupt(b, "unknown pair kind");
    }
    {
        Bytes b = bytes_;
        b[rec + 44] ^= 0x20;  // reason text
        expectCorrupt(b, "unknown reason");
    }
    {
        Bytes b = bytes_;
        setU32(b, rec + 28, 0x10000000);  // node count far beyond the file
        expectCorrupt(b, "bad counts");
    }
    {
        Bytes b = bytes_;
        setU32(b, rec, 100000);  // receiver face out of range
        expectCorrupt(b, "face out of range");
    }
    {
        Bytes b = bytes_;
        setU32(b, rec + 4, 100000);  // patch out of range
        expectCorrupt(b, "patch out of range");
    }
    // The inserted occluders.
    const Record withOccluders =
        firstRecord([](const Record& r) { return r.occluders > 0; }, "occluders");
    {
        Bytes b = bytes_;
        setU32(b, withOccluders.occludersAt, 100000);
        expectCorrupt(b, "occluder 0: face 100000 out of range");
    }
    {
        Bytes b = bytes_;
        setU32(b, withOccluders.occludersAt, u32At(bytes_, withOccluders.at + 16));  // the light
        expectCorrupt(b, "occluder 0: the receiver or the light itself");
    }
    // A partial tree's deferred occluders.
    const Record partial =
        firstRecord([](const Record& r) { return r.deferred > 0; }, "deferred occluders");
    {
        Bytes b = bytes_;
        setU32(b, partial.deferredAt, 100000);  // its face
        expectCorrupt(b, "deferred occluder 0: face 100000 out of range");
    }
    {
        Bytes b = bytes_;
        setU32(b, partial.deferredAt, u32At(bytes_, partial.at));  // the receiver itself
        expectCorrupt(b, "deferred occluder 0: the receiver or the light itself");
    }
    {
        Bytes b = bytes_;
        setU32(b, partial.at + 40, 0x10000000);  // deferred count far beyond the file
        expectCorrupt(b, "bad counts");
    }
    {
        Bytes b = bytes_;
        b[16] ^= 1;  // scene hash, checksum fixed: intact but another scene
        fixChecksum(b);
        statusOf(b, VisibilityFileStatus::Stale);
    }
}

TEST_F(SmallFile, InterruptedWriteKeepsTheOldFileAndLeavesNoTemporary) {
    // A different store content to write over the file.
    VisibilityStore other(scene_);
    other.getOrBuild({2, 0, scene_.lights[0]});
    const size_t otherSize = writeVisibilityFile(dir_ / "other.pvis", other);
    fs::remove(dir_ / "other.pvis");
    const std::vector<fs::path> before = filesInDir();
    for (size_t failAfter : {size_t{0}, size_t{1}, size_t{47}, otherSize / 2, otherSize - 1}) {
        VisibilityFileWriteOptions o;
        o.failAfterBytes = failAfter;
        try {
            writeVisibilityFile(file_, other, o);
            ADD_FAILURE() << "the simulated failure did not throw";
        } catch (const VisibilityFileError& e) {
            EXPECT_EQ(e.status, VisibilityFileStatus::WriteFailed);
            EXPECT_NE(std::string(e.what()).find(file_.string()), std::string::npos) << e.what();
        }
        EXPECT_EQ(readBytes(file_), bytes_) << "after failing at byte " << failAfter;
        EXPECT_EQ(filesInDir(), before);
    }
    // An unwritable place: a clear error, nothing created.
    try {
        writeVisibilityFile(dir_ / "no_such_dir" / "x.pvis", other);
        ADD_FAILURE() << "wrote into a missing directory";
    } catch (const VisibilityFileError& e) {
        EXPECT_EQ(e.status, VisibilityFileStatus::WriteFailed);
        EXPECT_NE(std::string(e.what()).find("no_such_dir"), std::string::npos) << e.what();
    }
    // And a successful write replaces the file.
    writeVisibilityFile(file_, other);
    EXPECT_NE(readBytes(file_), bytes_);
    EXPECT_EQ(filesInDir(), before);
    VisibilityStore back(scene_);
    EXPECT_EQ(readVisibilityFile(file_, back), 1u);
}

TEST(SceneHash, SeesEveryVertexBitAndFaceAndLight) {
    const Scene base = makeGrids();
    const VisibilityStore::Options o;
    const uint64_t h = sceneHash(base, o);
    EXPECT_EQ(sceneHash(makeGrids(), o), h);  // deterministic
    Scene s = base;
    s.mesh.vertices.back().z = std::nextafter(s.mesh.vertices.back().z, -1e300);
    EXPECT_NE(sceneHash(s, o), h);
    s = base;
    std::swap(s.mesh.faces[3][0], s.mesh.faces[3][1]);
    EXPECT_NE(sceneHash(s, o), h);
    s = base;
    s.lights.push_back(0);
    EXPECT_NE(sceneHash(s, o), h);
    s = base;
    s.materials.clear();  // materials do not shape the trees
    EXPECT_EQ(sceneHash(s, o), h);
}

}  // namespace
}  // namespace penumbra
