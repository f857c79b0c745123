#include "app/viewer/visibility_link.h"

#include <system_error>
#include <utility>

#include "engine/io/visibility_file.h"

namespace penumbra::viewer {

namespace fs = std::filesystem;

VisibilityLink::VisibilityLink(fs::path file, fs::path scenePath)
    : file_(std::move(file)), scenePath_(std::move(scenePath)) {}

bool VisibilityLink::follows(const fs::path& scenePath) {
    if (!attached()) return false;
    if (scenePath_.empty()) scenePath_ = scenePath;  // the first scene opened
    std::error_code ec;
    const bool same = fs::equivalent(scenePath, scenePath_, ec) || scenePath == scenePath_;
    if (!same) {
        status_ = file_.string() + " detached: it holds the trees of " + scenePath_.string();
        state_ = "detached";
        file_.clear();
    }
    return same;
}

const std::string& VisibilityLink::load(VisibilityStore& store) {
    treesLoaded_ = 0;
    needsWrite_ = false;
    try {
        treesLoaded_ = readVisibilityFile(file_, store);
        status_ = std::to_string(treesLoaded_) + " trees loaded from " + file_.string();
        state_ = "current";
    } catch (const VisibilityFileError& e) {
        state_ = toString(e.status);
        needsWrite_ = true;
        status_ = e.status == VisibilityFileStatus::Missing
                      ? file_.string() + ": no such file yet (the precompute or Save writes it)"
                      : std::string(e.what()) + " (" + state_ +
                            "); its trees are rebuilt and the file rewritten";
    }
    return status_;
}

const std::string& VisibilityLink::save(const VisibilityStore& store) {
    try {
        const size_t bytes = writeVisibilityFile(file_, store);
        // The file keeps the patches' own trees, not the render's refined sub-patches.
        treesWritten_ = 0;
        store.forEach([&](const PairKey& key, const PairRecord&) {
            if (PatchLayout::refineLevel(key) == 0) ++treesWritten_;
        });
        needsWrite_ = false;
        state_ = "written";
        status_ = "wrote " + std::to_string(treesWritten_) + " trees to " + file_.string() + " (" +
                  std::to_string(bytes) + " bytes)";
    } catch (const VisibilityFileError& e) {
        state_ = "write failed";
        status_ = std::string("cannot write the trees: ") + e.what();
    }
    return status_;
}

}  // namespace penumbra::viewer
