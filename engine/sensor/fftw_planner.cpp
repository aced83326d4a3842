#include "sensor/fftw_planner.h"

namespace metamer {

std::mutex& fftwPlannerMutex() {
    static std::mutex m;
    return m;
}

}  // namespace metamer
