// Random scene draws for a sweep (issue 49, item 2; docs/batch.md, "Random draws"): a sweep's
// "draws" crosses every job with `count` draws of scene values — a light from a list or a family
// (CIE daylight by CCT, a blackbody by temperature), a spectrum from a list or a library folder,
// numbers and vectors uniform in a box, directions uniform on a sphere or a cap, rotations uniform
// over all orientations — each drawn from counter-based streams keyed by the sweep's
// seed and the job's position, so a job's values never depend on how the sweep is split, and its
// record (which holds them as overrides and as axis values) re-renders it alone.
// Tests: engine/batch/sweep_test.cpp (SweepDraws.*), tests/batch_test.cpp.
#pragma once

#include "core/error.h"
#include "spectral/library.h"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace metamer {

// One drawn scene value: `setKey` gets a value drawn by `kind`.
struct SweepDrawValue {
    enum class Kind { Choose, Uniform, Daylight, Blackbody, Direction, Rotation };
    std::string name, setKey;
    Kind kind = Kind::Choose;
    // Choose: the entries, one picked uniformly; an entry {"daylight_cct": [lo, hi]} or
    // {"blackbody_k": [lo, hi]} is itself drawn (a light family). "choose_spectra": FOLDER fills it
    // with the library's spectra in that folder, sorted.
    std::vector<nlohmann::ordered_json> choices;
    std::vector<double> lo, hi;  // Uniform (a number, or each component of a vector); Daylight, Blackbody
    bool vector = false;         // Uniform over arrays: the value is an array
    // Direction: a unit vector uniform on the cap of half-angle withinDeg about `around` (180: the sphere).
    glm::dvec3 around{0, 0, 1};
    double withinDeg = 180;
    Where where;
};

struct SweepDraws {
    size_t count = 0;   // draws per base job and axis value
    uint64_t seed = 0;
    std::vector<SweepDrawValue> values;
    Where where;
};

// "draws": {"count": N, "seed": S, "values": [{"set": KEY, "name": NAME, and one of "choose": [...],
// "choose_spectra": "FOLDER", "uniform": [lo, hi] or [[lo, …], [hi, …]], "daylight_cct": [lo, hi],
// "blackbody_k": [lo, hi], "direction": {"around": [x, y, z], "within_deg": θ}, "rotation": "uniform"},
// …]}. Input errors name the key.
SweepDraws readSweepDraws(const nlohmann::ordered_json& v, const Where& where, const SpectrumLibrary& library);

struct DrawnValue {
    std::string name, setKey;
    nlohmann::ordered_json value;
};

// The values of the job at `position` (0-based, in the whole sweep): the same for the same seed and
// position, on any machine and in any shard.
std::vector<DrawnValue> drawValues(const SweepDraws& draws, uint64_t position);

}  // namespace metamer
