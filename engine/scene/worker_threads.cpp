#include "engine/scene/worker_threads.h"

#include <new>

namespace penumbra {

WorkerThreadsJoinedAtExit::WorkerThreadsJoinedAtExit() : handle_(oneapi::tbb::attach{}) {}

WorkerThreadsJoinedAtExit::~WorkerThreadsJoinedAtExit() {
    // std::nothrow: false when the workers could not be waited for (see the header); nothing
    // else is to be done about it at exit. Checked true after `render`, `precompute`,
    // `screenshot` with and without the preview, and the test executables.
    (void)oneapi::tbb::finalize(handle_, std::nothrow);
}

}  // namespace penumbra
