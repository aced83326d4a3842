// What every spectral cube writer does — OpenEXR (io/spectral_exr), HDF5 (io/hdf5_cube), ENVI
// (io/envi_cube): take the image's rows in order, pixel-interleaved, then complete its temporary
// files for commitTogether (io/atomic_file.h), which renames a run's files into place together.
// Which writers a render opens is the table in render/cube_formats.h.
// Tests: io/spectral_exr_test.cpp, io/hdf5_cube_test.cpp, io/envi_cube_test.cpp.
#pragma once

#include "io/atomic_file.h"

#include <cstddef>
#include <vector>

namespace metamer {

class CubeWriter {
public:
    virtual ~CubeWriter() = default;
    // `rows` rows starting at `firstRow`, pixel-interleaved (width × rows × bands floats).
    virtual void writeRows(int firstRow, int rows, const float* data) = 0;
    // The same with the display preview's rows beside them, R, G, B, A per pixel (width × rows × 4
    // floats), for a container that carries one (OpenEXR, when opened with a preview); the others
    // write the bands alone.
    virtual void writeRows(int firstRow, int rows, const float* data, const float* /*preview*/) {
        writeRows(firstRow, rows, data);
    }
    // Completes the temporary files and returns them, to be renamed into place together.
    virtual std::vector<AtomicOutput*> finish() = 0;
    // After finish(): finite values the container's precision could not hold and clamped (float16's ±65 504).
    virtual size_t clampedValues() const { return 0; }
};

}  // namespace metamer
