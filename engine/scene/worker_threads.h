// WorkerThreadsJoinedAtExit: the process's oneTBB worker threads, ended before the process ends.
//
// oneTBB tells its workers to stop from its own static destructors and does not wait for them, so
// a worker can still be on its way out while the last exit handlers run. LeakSanitizer's leak
// check is one of them (the sanitizer builds): it stops every thread to scan its stack, and a
// thread that is half gone crashes its tracer ("Tracer caught signal 11", clang 14), which fails
// the run although nothing leaked. Declared first in main() (the command line's, the tests'),
// this object waits in its destructor, after everything else main() owned is gone, until every
// worker has ended. Where that cannot be done (a task_arena or global_control still alive, or a
// call from inside a worker), oneTBB returns at once and the workers end as they did before.
#pragma once

#include <oneapi/tbb/global_control.h>

namespace penumbra {

class WorkerThreadsJoinedAtExit {
  public:
    WorkerThreadsJoinedAtExit();
    ~WorkerThreadsJoinedAtExit();
    WorkerThreadsJoinedAtExit(const WorkerThreadsJoinedAtExit&) = delete;
    WorkerThreadsJoinedAtExit& operator=(const WorkerThreadsJoinedAtExit&) = delete;

  private:
    oneapi::tbb::task_scheduler_handle handle_;
};

}  // namespace penumbra
