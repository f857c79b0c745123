// LightMoveJob: the viewer's light moves, built off the UI thread. A move makes the next version of
// the scene (withLightMoves, loaded_scene.h: a scene copy and a BVH build, tens of milliseconds on
// a large mesh); while one builds, the newest request waits (older waiting ones are dropped: a drag
// asks every frame), and take() hands the newest finished version to the UI thread's poll.
#pragma once

#include <tbb/task_group.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "app/viewer/loaded_scene.h"
#include "engine/render/exact_options.h"

namespace penumbra::viewer {

class LightMoveJob {
  public:
    // A new version of `from` with `moves` (one per light; its number one more than any before, so
    // that two versions never share one), on a task of `tasks` (which must outlive
    // the job's work: the viewer waits for its tasks before it is destroyed).
    void request(std::shared_ptr<const LoadedScene> from, std::vector<LightMove> moves,
                 const ExactOptions& exact, tbb::task_group& tasks);
    struct Result {
        std::shared_ptr<LoadedScene> scene;  // null when the move was refused
        std::string error;                   // why (SceneError's message)
        std::vector<LightMove> moves;        // what was asked
    };
    // The newest finished request, once.
    std::optional<Result> take();
    // A request is building or waiting.
    bool busy() const;
    // Another scene opened: what is building or waiting is for the old one and is dropped.
    void drop();

  private:
    struct Request {
        std::shared_ptr<const LoadedScene> from;
        std::vector<LightMove> moves;
        ExactOptions exact;
        uint64_t generation = 0;
        uint64_t version = 0;
    };
    void work();

    mutable std::mutex mutex_;
    std::optional<Request> waiting_;
    bool building_ = false;
    std::optional<Result> done_;
    uint64_t generation_ = 0;  // drop() makes every older request's result void
    uint64_t versions_ = 0;    // the versions given so far (each request its own, increasing)
};

}  // namespace penumbra::viewer
