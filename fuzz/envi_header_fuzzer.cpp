// libFuzzer target: the ENVI header parser (io/envi_cube.h). The input's bytes are the text of a
// .hdr given to parseEnviHeader; what it accepts must keep the promises of EnviHeader (sizes and
// codes in range, one finite wavelength per band, fwhm empty or one per band). A header that
// parses and describes a small cube is then read by readEnviCube beside a data file of the size it
// names, as a user's file would be. Input errors (metamer::Error) are expected; anything else is a
// finding.
#include "fuzz_support.h"

#include "io/envi_cube.h"

#include <cmath>
#include <cstdint>
#include <string>

using namespace metamer;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::silenceWarnings();
    fuzz::workDir();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::filesystem::path header = fuzz::workDir() / "fuzz.hdr";
    EnviHeader h;
    try {
        h = parseEnviHeader(text, Where{header.string()});
    } catch (const Error&) {
        return 0;
    }
    METAMER_FUZZ_CHECK(h.samples >= 1 && h.samples <= 65536);
    METAMER_FUZZ_CHECK(h.lines >= 1 && h.lines <= 65536);
    METAMER_FUZZ_CHECK(h.bands >= 1 && h.bands <= 10000);
    METAMER_FUZZ_CHECK(h.dataType == 4 || h.dataType == 5);
    METAMER_FUZZ_CHECK(h.byteOrder == 0 || h.byteOrder == 1);
    METAMER_FUZZ_CHECK(h.wavelengths_nm.size() == size_t(h.bands));
    METAMER_FUZZ_CHECK(h.fwhm_nm.empty() || h.fwhm_nm.size() == size_t(h.bands));
    for (double w : h.wavelengths_nm) METAMER_FUZZ_CHECK(std::isfinite(w));
    for (double w : h.fwhm_nm) METAMER_FUZZ_CHECK(std::isfinite(w));

    // Small enough to read: a data file of exactly the size the header names (a counting pattern).
    const uint64_t values = uint64_t(h.samples) * uint64_t(h.lines) * uint64_t(h.bands);
    if (values > 4096 || h.headerOffset > 4096) return 0;
    std::string bytes(h.headerOffset + values * h.bytesPerValue(), '\0');
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = char(i * 7);
    fuzz::writeFile(header, text.data(), text.size());
    fuzz::writeFile(fuzz::workDir() / "fuzz.img", bytes.data(), bytes.size());
    try {
        const SpectralImage image = readEnviCube(header);
        METAMER_FUZZ_CHECK(image.cube.width == h.samples && image.cube.height == h.lines);
        METAMER_FUZZ_CHECK(image.cube.bands() == h.bands);
        METAMER_FUZZ_CHECK(image.cube.data.size() == values);
    } catch (const Error&) {
    }
    return 0;
}
