// VisibilityLink: the visibility file (.pvis, engine/io/visibility_file.h) the viewer reads its
// trees from and writes them back to (`penumbra view SCENE --visibility FILE`, the Precompute
// panel's Load and Save).
//
// The file belongs to the scene it was given with: opening that scene (again: a new build budget
// reopens it) reads the file into the new store when it is current; a stale or corrupt file is
// reported, as `render --visibility` reports it, and its trees are rebuilt as the viewer needs
// them (or by the precompute), and written back over it. Opening another scene detaches the file,
// so that one scene's trees never overwrite another's. Every write is atomic (the file's own).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "engine/precompute/visibility_store.h"

namespace penumbra::viewer {

class VisibilityLink {
  public:
    VisibilityLink() = default;
    // The file for the scene at `scenePath` (empty file: none; empty scene: the first scene
    // opened).
    VisibilityLink(std::filesystem::path file, std::filesystem::path scenePath);

    bool attached() const { return !file_.empty(); }
    const std::filesystem::path& file() const { return file_; }
    // Whether the file belongs to the scene at `scenePath` (false detaches it: another scene).
    bool follows(const std::filesystem::path& scenePath);

    // Reads the file into `store` (a scene just opened, or the panel's Load): the trees of a
    // current file are added; a missing file is noted (the first Save writes it); a stale or
    // corrupt one is reported in status() (and marked for rewriting). Returns status().
    const std::string& load(VisibilityStore& store);
    // Writes every tree of `store` to the file, atomically. Returns status() (which says what was
    // written or why it failed).
    const std::string& save(const VisibilityStore& store);

    // What the last load or save did, for the status line and the panel.
    const std::string& status() const { return status_; }
    size_t treesLoaded() const { return treesLoaded_; }    // by the last load (0: none)
    size_t treesWritten() const { return treesWritten_; }  // by the last save (0: none)
    // The last load found a stale or corrupt file (or none): the next precompute writes it.
    bool needsWrite() const { return needsWrite_; }
    // "current", "missing", "stale", "corrupt", "unreadable", "written", "write failed", or ""
    // (nothing done yet): the state JSON's.
    const std::string& state() const { return state_; }

  private:
    std::filesystem::path file_, scenePath_;
    std::string status_, state_;
    size_t treesLoaded_ = 0, treesWritten_ = 0;
    bool needsWrite_ = false;
};

}  // namespace penumbra::viewer
