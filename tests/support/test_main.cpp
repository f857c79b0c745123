// main() of the test executables: GoogleTest's, with the process's oneTBB worker threads ended
// before the exit handlers run (engine/scene/worker_threads.h: under the sanitizers,
// LeakSanitizer's check at exit must not meet a worker on its way out).
#include <gtest/gtest.h>

#include "engine/scene/worker_threads.h"

int main(int argc, char** argv) {
    const penumbra::WorkerThreadsJoinedAtExit workerThreads;
    testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
