// CPU time of the whole process (user + system, every thread), in seconds: what the renderer's
// and the bench's "cpu" figures report beside wall time.
#pragma once

namespace penumbra {

double processCpuSeconds();

}  // namespace penumbra
