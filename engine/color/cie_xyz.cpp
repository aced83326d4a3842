#include "color/cie_xyz.h"
#include "spectral/resampling.h"

#include "spectral/csv.h"

namespace metamer {

ColorMatchingFunctions loadObserver(const SpectrumLibrary& library, const std::string& name,
                                    const Grid& grid) {
    // Observers are 3-column tables, which SpectrumLibrary::get (single spectra) does not read.
    if (!library.contains(name)) {
        std::string s = library.suggest(name);
        if (!s.empty()) failInput(Where{}, "no observer '{}'; did you mean '{}'?", name, s);
        failInput(Where{}, "no observer '{}' in the spectra library ({})", name, library.root().string());
    }
    SpectralTable table = readSpectralTable(library.root() / (name + ".csv"), 3);
    if (table.columns.size() != 3)
        failInput(Where{(library.root() / (name + ".csv")).string()},
                  "an observer needs exactly 3 value columns (x_bar, y_bar, z_bar), found {}",
                  table.columns.size());
    ColorMatchingFunctions cmfs;
    cmfs.grid = grid;
    cmfs.source = name;
    std::vector<double>* out[3] = {&cmfs.x, &cmfs.y, &cmfs.z};
    for (int c = 0; c < 3; ++c) {
        Spectrum s;
        s.wavelengths_nm = table.wavelengths_nm;
        s.values = table.columns[c];
        s.source = name;
        *out[c] = resample(s, grid);  // 0 outside the data: no sensitivity there
    }
    return cmfs;
}

glm::dvec3 spectrumToXyz(const float* bands, const ColorMatchingFunctions& cmfs) {
    const int n = cmfs.grid.bands();
    glm::dvec3 xyz(0.0);
    for (int i = 0; i < n; ++i) {
        double l = bands[i];
        xyz.x += l * cmfs.x[i];
        xyz.y += l * cmfs.y[i];
        xyz.z += l * cmfs.z[i];
    }
    return xyz * cmfs.grid.step_nm;
}

std::vector<glm::dvec3> cubeToXyz(const SpectralCube& cube, const ColorMatchingFunctions& cmfs) {
    if (!(cube.grid == cmfs.grid))
        failRuntime("colour-matching functions are on grid {} but the cube is on {}", cmfs.grid.str(),
                    cube.grid.str());
    std::vector<glm::dvec3> xyz(static_cast<size_t>(cube.width) * cube.height);
    for (int y = 0; y < cube.height; ++y)
        for (int x = 0; x < cube.width; ++x)
            xyz[static_cast<size_t>(y) * cube.width + x] = spectrumToXyz(cube.pixel(x, y), cmfs);
    return xyz;
}

}  // namespace metamer
