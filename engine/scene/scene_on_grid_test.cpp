#include "scene/scene_on_grid.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <set>
#include <string>

using namespace metamer;

namespace {

// The number of members of an aggregate: the most initializers T{…} accepts.
struct AnyValue {
    template <typename T>
    operator T() const;
};
template <typename T, typename... Values>
constexpr size_t memberCount() {
    if constexpr (requires { T{Values{}..., AnyValue{}}; })
        return memberCount<T, Values..., AnyValue>();
    else
        return sizeof...(Values);
}

}  // namespace

// A field added to MaterialOnGrid must be visited by forEachSpectrum when it is per band, or
// the representation modes (which transform a copy through it) would pass it through untouched,
// in wavelengths the mode's renderers do not use. Update the count, and the visitor, together.
TEST(MaterialOnGrid, EveryFieldIsKnownToTheSpectrumVisitor) {
    static_assert(memberCount<MaterialOnGrid>() == 17,
                  "MaterialOnGrid gained or lost a field: visit it in forEachSpectrum (scene_on_grid.h) if it is "
                  "per band, then update this count");
    MaterialOnGrid m;
    std::set<std::string> names;
    std::set<const std::vector<double>*> arrays;
    forEachSpectrum(m, [&](std::vector<double>& v, MaterialSpectrum, const char* name) {
        names.insert(name);
        arrays.insert(&v);
    });
    EXPECT_EQ(names, (std::set<std::string>{"diffuse", "specular", "excitation", "emission", "donaldson", "transmittance",
                                             "absorbance", "ior", "slabAbsorbance", "emitted"}));
    EXPECT_EQ(arrays.size(), 10u);  // ten distinct members
    // The same through a const material.
    const MaterialOnGrid& c = m;
    size_t visited = 0;
    forEachSpectrum(c, [&](const std::vector<double>&, MaterialSpectrum, const char*) { ++visited; });
    EXPECT_EQ(visited, 10u);
}
