// FFTW's planner (plan creation and destruction, and its allocator) is not thread-safe; executing
// distinct plans is. Every user of FFTW in the engine (sensor/lens, sensor/slanted_edge) holds
// this one lock around planning, so a lens running on worker threads (a Python capture releases
// the GIL) and an SFR measured on another thread never plan at once.
// Tests: engine/sensor/lens_test.cpp (bands planned on several threads), slanted_edge_test.cpp.
#pragma once

#include <mutex>

namespace metamer {

std::mutex& fftwPlannerMutex();

}  // namespace metamer
