#include "app/viewer/selection.h"

#include <algorithm>
#include <exception>
#include <utility>

namespace penumbra::viewer {

struct Selection::Pending {
    std::shared_ptr<LoadedScene> scene;
    uint32_t face = 0;
    Vec3 point;
    std::atomic<bool> done{false};
    std::mutex mutex;  // guards result and error once done is set
    std::optional<PointInspection> result;
    std::string error;
};

bool Selection::select(std::shared_ptr<LoadedScene> scene, uint32_t face, const Vec3& x,
                       tbb::task_group& tasks) {
    inspection_.reset();
    try {
        if (scene->bvh)
            inspection_ = inspectPointDirect(scene->scene, scene->bvh->faceBoxes(), face, x,
                                             clickWorkPerLight(scene->scene.lights.size()),
                                             &scene->bvh->faceClusters());
    } catch (const std::exception&) {
        inspection_.reset();  // the full inspection reports it
    }
    if (inspection_)
        light_ = std::min(light_,
                          inspection_->lights.empty() ? size_t{0} : inspection_->lights.size() - 1);
    auto pending = std::make_shared<Pending>();
    pending->scene = std::move(scene);
    pending->face = face;
    pending->point = x;
    pending_ = pending;
    tasks.run([pending] {
        std::optional<PointInspection> result;
        std::string error;
        try {
            result = inspectPoint(*pending->scene->store, pending->face, pending->point);
        } catch (const std::exception& e) {
            error = e.what();
        }
        {
            const std::lock_guard lock(pending->mutex);
            pending->result = std::move(result);
            pending->error = std::move(error);
        }
        pending->done = true;
    });
    return inspection_.has_value();
}

void Selection::clear() {
    pending_.reset();
    inspection_.reset();
}

Selection::Event Selection::poll(std::string& message) {
    if (!pending_ || !pending_->done) return Event::None;
    const std::shared_ptr<Pending> p = std::move(pending_);
    const std::lock_guard lock(p->mutex);
    if (!p->result) {
        inspection_.reset();
        message = "the point query failed: " + p->error;
        return Event::Failed;
    }
    inspection_ = std::move(p->result);
    light_ =
        std::min(light_, inspection_->lights.empty() ? size_t{0} : inspection_->lights.size() - 1);
    message = "point (" + std::to_string(inspection_->point.x) + ", " +
              std::to_string(inspection_->point.y) + ", " + std::to_string(inspection_->point.z) +
              ") on face " + std::to_string(inspection_->face);
    return Event::Arrived;
}

void Selection::selectLight(size_t k) {
    if (inspection_ && k < inspection_->lights.size()) light_ = k;
}

void Selection::nextLight() {
    if (inspection_ && !inspection_->lights.empty())
        light_ = (light_ + 1) % inspection_->lights.size();
}

const LightInspection* Selection::selectedLight() const {
    if (!inspection_ || inspection_->lights.empty()) return nullptr;
    return &inspection_->lights[std::min(light_, inspection_->lights.size() - 1)];
}

}  // namespace penumbra::viewer
