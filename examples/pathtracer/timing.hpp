// Wall-clock time of the frame phases (FrameTimings).
#pragma once

#include <chrono>

namespace pt {

using Clock = std::chrono::steady_clock;

/// Milliseconds from `start` to now.
inline double milliseconds_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

} // namespace pt
