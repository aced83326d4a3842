#include "io/dng_file.h"

#include "core/error.h"
#include "io/atomic_file.h"

#include <tiffio.h>

#include <cmath>
#include <memory>

namespace metamer {

namespace fs = std::filesystem;

namespace {

// DNG's PhotometricInterpretation for demosaiced or monochrome raw data (DNG 1.4, "LinearRaw");
// libtiff defines PHOTOMETRIC_CFA but not this one.
constexpr uint16_t kPhotometricLinearRaw = 34892;

}  // namespace

void writeDng(const fs::path& path, const DngRaw& raw) {
    AtomicOutput out(path);
    out.naming([&] {
        TIFF* t = TIFFOpen(out.tempPath().c_str(), "w");
        if (!t) failRuntime("cannot open {} for writing", out.tempPath().string());
        std::unique_ptr<TIFF, void (*)(TIFF*)> closer(t, [](TIFF* x) { TIFFClose(x); });
        static const uint8_t dngVersion[4] = {1, 4, 0, 0}, backward[4] = {1, 1, 0, 0};
        static const uint16_t repeat[2] = {2, 2};
        static const uint8_t planeColor[3] = {0, 1, 2};
        float matrix[9], neutral[3];
        for (int i = 0; i < 9; ++i) matrix[i] = float(raw.colorMatrix1[size_t(i)]);
        for (int i = 0; i < 3; ++i) neutral[i] = float(raw.asShotNeutral[size_t(i)]);
        float black = float(raw.blackLevel);
        uint32_t white = raw.whiteLevel;
        TIFFSetField(t, TIFFTAG_SUBFILETYPE, 0);
        TIFFSetField(t, TIFFTAG_IMAGEWIDTH, uint32_t(raw.width));
        TIFFSetField(t, TIFFTAG_IMAGELENGTH, uint32_t(raw.height));
        TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 16);
        TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 1);
        TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_NONE);
        // A monochrome sensor is LinearRaw with one sample per pixel: DNG's form for a sensor
        // without a colour filter array, and without colour calibration.
        TIFFSetField(t, TIFFTAG_PHOTOMETRIC, raw.monochrome ? kPhotometricLinearRaw : PHOTOMETRIC_CFA);
        TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
        TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, uint32_t(raw.height));
        TIFFSetField(t, TIFFTAG_MAKE, "Metamer");
        TIFFSetField(t, TIFFTAG_MODEL, raw.model.c_str());
        TIFFSetField(t, TIFFTAG_SOFTWARE, "metamer capture");
        if (!raw.description.empty()) TIFFSetField(t, TIFFTAG_IMAGEDESCRIPTION, raw.description.c_str());
        TIFFSetField(t, TIFFTAG_DNGVERSION, dngVersion);
        TIFFSetField(t, TIFFTAG_DNGBACKWARDVERSION, backward);
        TIFFSetField(t, TIFFTAG_UNIQUECAMERAMODEL, raw.model.c_str());
        if (!raw.monochrome) {
            TIFFSetField(t, TIFFTAG_CFAREPEATPATTERNDIM, repeat);
            TIFFSetField(t, TIFFTAG_CFAPATTERN, 4, raw.cfa.data());
            TIFFSetField(t, TIFFTAG_CFAPLANECOLOR, 3, planeColor);
            TIFFSetField(t, TIFFTAG_CFALAYOUT, 1);
        }
        TIFFSetField(t, TIFFTAG_BLACKLEVEL, 1, &black);
        TIFFSetField(t, TIFFTAG_WHITELEVEL, 1, &white);
        if (!raw.monochrome) {
            TIFFSetField(t, TIFFTAG_COLORMATRIX1, 9, matrix);
            TIFFSetField(t, TIFFTAG_CALIBRATIONILLUMINANT1, 21);  // D65
            TIFFSetField(t, TIFFTAG_ASSHOTNEUTRAL, 3, neutral);
        }
        for (int y = 0; y < raw.height; ++y)
            if (TIFFWriteScanline(t, const_cast<uint16_t*>(raw.pixels + size_t(y) * raw.width), uint32_t(y), 0) < 0)
                failRuntime("cannot write row {} of {}", y, out.tempPath().string());
        if (!TIFFFlush(t)) failRuntime("cannot finish {}", out.tempPath().string());
    });
    out.commit();
}

}  // namespace metamer
