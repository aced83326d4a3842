#include "batch/sweep_draws.h"

#include "scene/json_values.h"
#include "sensor/counter_rng.h"
#include "spectral/illuminant_models.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace metamer {

using Json = nlohmann::ordered_json;
using namespace json_read;

namespace {

// The draws' own Philox stream purpose, apart from the sensor's (1 … 4).
constexpr uint64_t kDrawStream = 101;

// [lo, hi] of a family, within its model's range.
void familyRange(const Json& v, const Where& w, double minK, double maxK, std::vector<double>& lo, std::vector<double>& hi) {
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
        failInput(w, "expected [lowest, highest] in kelvin, got {}", describe(v));
    const double a = v[0].get<double>(), b = v[1].get<double>();
    if (!(a >= minK && b <= maxK && a <= b))
        failInput(w, "expected lowest ≤ highest within {:g} … {:g} K, got [{:g}, {:g}]", minK, maxK, a, b);
    lo = {a};
    hi = {b};
}

// A choose entry that is itself a family to draw from: {"daylight_cct": [lo, hi]} or {"blackbody_k": [lo, hi]}.
bool isFamily(const Json& e) {
    return e.is_object() && e.size() == 1 && (e.contains("daylight_cct") || e.contains("blackbody_k")) &&
           e.begin().value().is_array();
}

void checkFamily(const Json& e, const Where& w) {
    std::vector<double> lo, hi;
    if (e.contains("daylight_cct"))
        familyRange(e["daylight_cct"], w.child("daylight_cct"), kDaylightMinK, kDaylightMaxK, lo, hi);
    else
        familyRange(e["blackbody_k"], w.child("blackbody_k"), kBlackbodyMinK, kBlackbodyMaxK, lo, hi);
}

double between(double lo, double hi, double u) { return lo + (hi - lo) * u; }

constexpr double kPi = 3.14159265358979323846;

// A unit vector uniform on the cap of half-angle θ about unit `a`: cos α uniform in [cos θ, 1]
// (Archimedes: equal heights, equal areas), the azimuth uniform.
Json drawDirection(const glm::dvec3& a, double withinDeg, CounterStream& s) {
    const double cosAlpha = 1.0 - s.uniform() * (1.0 - std::cos(withinDeg * kPi / 180.0));
    const double sinAlpha = std::sqrt(std::max(0.0, 1.0 - cosAlpha * cosAlpha)), phi = 2.0 * kPi * s.uniform();
    // A frame (t, b, a): t perpendicular to a, from the world axis least aligned with it.
    const glm::dvec3 m = glm::abs(a);
    const glm::dvec3 axis = m.x <= m.y && m.x <= m.z ? glm::dvec3(1, 0, 0) : m.y <= m.z ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
    const glm::dvec3 c = glm::cross(a, axis), t = c / glm::length(c), b = glm::cross(a, t);
    const glm::dvec3 v = sinAlpha * (std::cos(phi) * t + std::sin(phi) * b) + cosAlpha * a;
    return Json::array({v.x, v.y, v.z});
}

// A rotation uniform over all orientations (Shoemake's unit quaternion from three uniforms), as a
// glTF object's "rotate_deg" [x, y, z]: M = Rz(γ)·Ry(β)·Rx(α) (docs/scene-format.md, "Object transform").
Json drawRotation(CounterStream& s) {
    const double u1 = s.uniform(), u2 = s.uniform(), u3 = s.uniform();
    const double x = std::sqrt(1 - u1) * std::sin(2 * kPi * u2), y = std::sqrt(1 - u1) * std::cos(2 * kPi * u2);
    const double z = std::sqrt(u1) * std::sin(2 * kPi * u3), w = std::sqrt(u1) * std::cos(2 * kPi * u3);
    // The quaternion's matrix entries that the Euler angles need.
    const double r00 = 1 - 2 * (y * y + z * z), r10 = 2 * (x * y + w * z), r20 = 2 * (x * z - w * y);
    const double r21 = 2 * (y * z + w * x), r22 = 1 - 2 * (x * x + y * y);
    const double alpha = std::atan2(r21, r22), beta = std::atan2(-r20, std::sqrt(r00 * r00 + r10 * r10)),
                 gamma = std::atan2(r10, r00);
    const double deg = 180.0 / kPi;
    return Json::array({alpha * deg, beta * deg, gamma * deg});
}

Json drawFamily(const Json& e, CounterStream& s) {
    const char* key = e.contains("daylight_cct") ? "daylight_cct" : "blackbody_k";
    const Json& r = e[key];
    return Json{{key, between(r[0].get<double>(), r[1].get<double>(), s.uniform())}};
}

}  // namespace

SweepDraws readSweepDraws(const Json& v, const Where& w, const SpectrumLibrary& library) {
    asObject(v, w);
    checkKeys(v, w, {"count", "seed", "values"}, "the draws");
    SweepDraws d;
    d.where = w;
    d.count = size_t(integerIn(require(v, w, "count", "how many draws per job"), w.child("count"), 1, 1000000));
    if (const Json* s = find(v, "seed")) {
        const double seed = numberIn(*s, w.child("seed"), 0, 9007199254740992.0, false, false);
        if (std::floor(seed) != seed) failInput(w.child("seed"), "expected a whole number, got {:g}", seed);
        d.seed = uint64_t(seed);
    }
    const Json& values = require(v, w, "values", "an array of drawn values");
    const Where vw = w.child("values");
    if (!values.is_array() || values.empty()) failInput(vw, "expected a non-empty array of drawn values");
    for (size_t i = 0; i < values.size(); ++i) {
        const Json& e = values[i];
        const Where ew = vw.index(i);
        asObject(e, ew);
        checkKeys(e, ew, {"set", "name", "choose", "choose_spectra", "uniform", "daylight_cct", "blackbody_k",
                          "direction", "rotation"},
                  "a drawn value");
        SweepDrawValue x;
        x.where = ew;
        x.setKey = string(require(e, ew, "set", "the scene key the value goes to"), ew.child("set"));
        if (x.setKey.empty()) failInput(ew.child("set"), "expected a scene key path, e.g. \"lights.0.spectrum\"");
        x.name = find(e, "name") ? string(e["name"], ew.child("name")) : x.setKey;
        int kinds = 0;
        for (const char* k : {"choose", "choose_spectra", "uniform", "daylight_cct", "blackbody_k", "direction", "rotation"})
            kinds += find(e, k) ? 1 : 0;
        if (kinds != 1)
            failInput(ew, "a drawn value has exactly one of choose, choose_spectra, uniform, daylight_cct, blackbody_k, "
                          "direction, rotation");
        if (const Json* c = find(e, "choose")) {
            if (!c->is_array() || c->empty()) failInput(ew.child("choose"), "expected a non-empty array of values");
            for (size_t k = 0; k < c->size(); ++k) {
                if (isFamily((*c)[k])) checkFamily((*c)[k], ew.child("choose").index(k));
                x.choices.push_back((*c)[k]);
            }
        } else if (const Json* f = find(e, "choose_spectra")) {
            const std::string folder = string(*f, ew.child("choose_spectra"));
            const std::string prefix = folder.empty() || folder.back() == '/' ? folder : folder + "/";
            for (const std::string& name : library.names())
                if (!prefix.empty() && name.rfind(prefix, 0) == 0 && name.find('/', prefix.size()) == std::string::npos)
                    x.choices.push_back(name);
            if (x.choices.empty())
                failInput(ew.child("choose_spectra"), "the library has no spectra in '{}' (reflectances/cie_2017_ces, …)",
                          folder);
        } else if (const Json* u = find(e, "uniform")) {
            x.kind = SweepDrawValue::Kind::Uniform;
            const Where uw = ew.child("uniform");
            if (!u->is_array() || u->size() != 2) failInput(uw, "expected [lowest, highest] or [[lowest …], [highest …]]");
            x.vector = (*u)[0].is_array();
            auto numbers = [&](const Json& a, const Where& aw) {
                std::vector<double> out;
                if (!x.vector) out.push_back(number(a, aw));
                else
                    for (size_t k = 0; k < a.size(); ++k) out.push_back(number(a[k], aw.index(k)));
                return out;
            };
            if (x.vector && (!(*u)[1].is_array() || (*u)[0].size() != (*u)[1].size() || (*u)[0].empty()))
                failInput(uw, "expected two arrays of the same length: the lowest and the highest corner");
            x.lo = numbers((*u)[0], uw.index(0));
            x.hi = numbers((*u)[1], uw.index(1));
            for (size_t k = 0; k < x.lo.size(); ++k)
                if (!(x.lo[k] <= x.hi[k])) failInput(uw, "the lowest ({:g}) is above the highest ({:g})", x.lo[k], x.hi[k]);
        } else if (const Json* dir = find(e, "direction")) {
            x.kind = SweepDrawValue::Kind::Direction;
            const Where dw = ew.child("direction");
            asObject(*dir, dw);
            checkKeys(*dir, dw, {"around", "within_deg"}, "a direction");
            if (const Json* a = find(*dir, "around")) {
                if (!a->is_array() || a->size() != 3) failInput(dw.child("around"), "expected [x, y, z], got {}", describe(*a));
                for (int c = 0; c < 3; ++c) x.around[c] = number((*a)[size_t(c)], dw.child("around").index(size_t(c)));
                const double n = glm::dot(x.around, x.around);
                if (!(n > 0) || !std::isfinite(n)) failInput(dw.child("around"), "expected a non-zero, finite vector");
                x.around /= std::sqrt(n);
            }
            if (const Json* t = find(*dir, "within_deg")) x.withinDeg = numberIn(*t, dw.child("within_deg"), 0, 180, true, false);
        } else if (const Json* rot = find(e, "rotation")) {
            x.kind = SweepDrawValue::Kind::Rotation;
            if (!rot->is_string() || rot->get<std::string>() != "uniform")
                failInput(ew.child("rotation"), "expected \"uniform\" (every orientation equally likely), got {}", describe(*rot));
        } else if (const Json* dcct = find(e, "daylight_cct")) {
            x.kind = SweepDrawValue::Kind::Daylight;
            familyRange(*dcct, ew.child("daylight_cct"), kDaylightMinK, kDaylightMaxK, x.lo, x.hi);
        } else {
            x.kind = SweepDrawValue::Kind::Blackbody;
            familyRange(e["blackbody_k"], ew.child("blackbody_k"), kBlackbodyMinK, kBlackbodyMaxK, x.lo, x.hi);
        }
        d.values.push_back(std::move(x));
    }
    return d;
}

std::vector<DrawnValue> drawValues(const SweepDraws& d, uint64_t position) {
    std::vector<DrawnValue> out;
    for (size_t i = 0; i < d.values.size(); ++i) {
        const SweepDrawValue& x = d.values[i];
        // One stream per (job, value): adding a value to the sweep leaves the others' draws alone.
        CounterStream s({d.seed, kDrawStream}, position, i, 0);
        Json v;
        switch (x.kind) {
            case SweepDrawValue::Kind::Choose: {
                const size_t k = std::min(x.choices.size() - 1, size_t(s.uniform() * double(x.choices.size())));
                v = isFamily(x.choices[k]) ? drawFamily(x.choices[k], s) : x.choices[k];
                break;
            }
            case SweepDrawValue::Kind::Uniform:
                if (x.vector) {
                    v = Json::array();
                    for (size_t c = 0; c < x.lo.size(); ++c) v.push_back(between(x.lo[c], x.hi[c], s.uniform()));
                } else {
                    v = between(x.lo[0], x.hi[0], s.uniform());
                }
                break;
            case SweepDrawValue::Kind::Daylight: v = Json{{"daylight_cct", between(x.lo[0], x.hi[0], s.uniform())}}; break;
            case SweepDrawValue::Kind::Blackbody: v = Json{{"blackbody_k", between(x.lo[0], x.hi[0], s.uniform())}}; break;
            case SweepDrawValue::Kind::Direction: v = drawDirection(x.around, x.withinDeg, s); break;
            case SweepDrawValue::Kind::Rotation: v = drawRotation(s); break;
        }
        out.push_back({x.name, x.setKey, std::move(v)});
    }
    return out;
}

}  // namespace metamer
